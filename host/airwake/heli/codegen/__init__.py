"""The numba code generator: how a model's effects become machine code. Private to
`airwake.heli` (a layering test keeps every other package out of it); effect authors use
`airwake.heli.kernel`, everyone else `HeliModel`, `Stepper`, `simulate` and
`predict_measurements`.

    jit.py      numba options, kernel marks, `unmanaged` arrays
    cache.py    where compiled code is cached on disk, and when it is stale
    compose.py  one fused, compiled function per effect composition (`compiled(model)`)
    loops.py    the batch/RK4/simulation/hidden-state loops, compiled once, calling a
                composition's row through its address
    staged.py   stage-by-stage evaluation for models with numpy effects
"""

from airwake.heli.codegen.compose import Compiled, Step, compiled

__all__ = ["Compiled", "Step", "compiled"]
