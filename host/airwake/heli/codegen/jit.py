"""numba settings and the low-level helpers every compiled function of the package shares.

- `JIT_OPTIONS`: no fastmath, numpy's error model (x/0 -> inf/nan, as the numpy effects
  behave), for the effects' kernels and everything generated around them.
- `disk_cached(fn)`: mark a function for the heli kernel cache (`cache.KernelCacheLocator`,
  stamped with the fingerprint of every file of `airwake.heli`), as `@kernel` does.
- `is_kernel(obj)`: an effect stage written as a compiled kernel (`airwake.heli.kernel`).
- `unmanaged(a)`: a C-contiguous array without reference counting, for the hot loops.
"""

from __future__ import annotations

import numba
from numba.core import types
from numba.extending import intrinsic
from numba.np.arrayobj import make_array

from airwake.heli.codegen import cache  # noqa: F401  (registers the kernels' cache locator)

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


@disk_cached  # called, not inlined (cheaper to compile, same speed)
def _unmanaged(a):
    """The same C-contiguous array without reference counting: views sliced from it (one
    per effect and row) then cost no atomic increments. The caller keeps `a` alive."""
    return numba.carray(_data_pointer(a), a.shape)


unmanaged = numba.njit(cache=True, **JIT_OPTIONS)(_unmanaged)
