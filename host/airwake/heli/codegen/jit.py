"""numba settings and the low-level helpers every compiled function of the package shares.

- `JIT_OPTIONS`: no fastmath, numpy's error model (x/0 -> inf/nan, as the numpy effects
  behave), for the effects' kernels and everything generated around them.
- `disk_cached(fn)`: mark a function for the heli kernel cache (`cache.KernelCacheLocator`,
  stamped with the fingerprint of every file of `airwake.heli`), as `@kernel` does.
- `is_kernel(obj)`: an effect stage written as a compiled kernel (`airwake.heli.kernel`).
- `unmanaged(a)`: a C-contiguous array without reference counting, for the hot loops.
- `call_row_at(address, …)`: call a composition's C-callable row through its address.
- `generated_module(kind, text, ...)`: generated source as a module whose functions are
  compiled and cached on disk like the kernels.
"""

from __future__ import annotations

import hashlib
import sys
from types import ModuleType

import numba
from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic
from numba.np.arrayobj import make_array

# importing cache registers the kernels' cache locator, before any @kernel compiles
from airwake.heli.codegen.cache import cache_dir, fingerprint, write_once

JIT_OPTIONS = {"error_model": "numpy", "fastmath": False}


def disk_cached(fn):
    """Mark `fn` for the kernel cache (before numba.njit(cache=True) wraps it)."""
    fn._airwake_kernel = True
    return fn


def mark_kernel(dispatcher):
    """Mark a compiled effect stage as a kernel (what `is_kernel` checks)."""
    dispatcher.airwake_kernel = True
    return dispatcher


def is_kernel(obj) -> bool:
    return getattr(obj, "airwake_kernel", False) is True


@intrinsic
def _data_pointer(typingctx, arr):
    """Pointer to a C-contiguous array's first element."""
    sig = types.CPointer(arr.dtype)(arr)

    def codegen(context, builder, signature, args):
        return make_array(signature.args[0])(context, builder, value=args[0]).data

    return sig, codegen


@intrinsic
def call_row_at(typingctx, address, q, x, xdot, meas, loads, scratch, u, w, hagl, omm, params):
    """Call the C function at `address` (an integer),
    void row(double *q, *x, *xdot, *meas, *loads, *scratch, *u, *w, double hagl, omm,
    double *params), with the arrays' data pointers (a composition's row: compose.py).
    An address is an integer to the dispatcher: no per-call typing of a function object."""
    arrays = (q, x, xdot, meas, loads, scratch, u, w)
    sig = types.void(address, *arrays, hagl, omm, params)

    def codegen(context, builder, signature, args):
        dbl = ir.DoubleType()
        ptr = dbl.as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [ptr] * 8 + [dbl, dbl, ptr])
        fn = builder.inttoptr(args[0], fnty.as_pointer())
        data = [make_array(t)(context, builder, value=v).data
                for t, v in zip(signature.args[1:9], args[1:9], strict=True)]
        hv = context.cast(builder, args[9], signature.args[9], types.float64)
        ov = context.cast(builder, args[10], signature.args[10], types.float64)
        pv = make_array(signature.args[11])(context, builder, value=args[11]).data
        builder.call(fn, [*data, hv, ov, pv])
        return context.get_dummy_value()

    return sig, codegen


@disk_cached  # called, not inlined (cheaper to compile, same speed)
def _unmanaged(a):
    """The same C-contiguous array without reference counting: views sliced from it (one
    per effect and row) then cost no atomic increments. The caller keeps `a` alive."""
    return numba.carray(_data_pointer(a), a.shape)


unmanaged = numba.njit(cache=True, **JIT_OPTIONS)(_unmanaged)


def generated_module(kind: str, text: str, kernels, glb: dict, inline: dict,
                     cfuncs: dict | None = None) -> ModuleType:
    """The module the generated source `text` defines, with `glb` as its globals, the
    functions named in `inline` (name -> numba's inline option) compiled with
    numba.njit(cache=True) and those in `cfuncs` (name -> signature) with
    numba.cfunc(cache=True), C-callable. The source is written once to the cache directory
    as `{kind}_{digest}.py`, the digest covering the text and the fingerprint of the
    `kernels` it calls, so the first process compiles and later ones load the machine
    code numba cached next to the file. Memoised as a real module in sys.modules: numba's
    cache rebuilds a function's environment by importing its module name."""
    digest = hashlib.sha256((text + fingerprint(kernels)).encode()).hexdigest()[:24]
    path = cache_dir() / f"{kind}_{digest}.py"
    write_once(path, text)
    mod_name = f"airwake_heli_{kind}_{digest}"
    module = sys.modules.get(mod_name)
    if module is None:
        module = ModuleType(mod_name)
        module.__file__ = str(path)
        module.__dict__.update(glb)
        exec(compile(text, str(path), "exec"), module.__dict__)
        for name, how in inline.items():
            module.__dict__[name] = numba.njit(cache=True, inline=how, **JIT_OPTIONS)(
                module.__dict__[name])
        # registered before the cfuncs compile (eagerly): loading one from the cache
        # imports its module by name
        sys.modules[mod_name] = module
        try:
            for name, sig in (cfuncs or {}).items():
                module.__dict__[name] = numba.cfunc(sig, cache=True, **JIT_OPTIONS)(
                    module.__dict__[name])
        except BaseException:
            del sys.modules[mod_name]
            raise
    return module
