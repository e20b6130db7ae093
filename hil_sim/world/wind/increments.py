"""Elementary functions at a nearby argument from their values at x (numba, scalar).

The airwake differentiates its stream function by central differences (psi at s +- 1 mm,
h +- 1 mm). A compiled scalar loop pays a library call per exp or log, and those calls
are most of its cost, so the stencil's neighbours take their values from the centre's
through the addition theorems (d = x1 - x0)

    exp(x + d)     = exp(x) exp(d)
    tanh(x + d)    = (tanh x + tanh d) / (1 + tanh x tanh d)
    sp(x + d)      = sp(x) + ln(1 + sigma(x) (e^d - 1)),    sp = ln(1 + e^x), sigma = sp'
    ln cosh(x + d) = ln cosh x + ln(1 + (cosh d - 1) + tanh x sinh d)

with the functions of the small d (and of the small argument of ln(1 + a)) by their
Taylor series: for |d| < SMALL = 1/512 the terms kept leave < 1e-16 relative, so each
value is as accurate as the library's (a few ulp). A larger step evaluates at x1
directly. tests/hil_sim/test_wind_compiled.py checks these against the library.
"""

from __future__ import annotations

import math

import numba

# Rounding only (fused multiply-adds, x / c as x * (1 / c)): no effect on the values
# beyond an ulp; the Horner chains run in half the time.
FAST = {"contract", "arcp", "nsz"}
SMALL = 1.0 / 512  # |d| below which the series are used (a stencil step of 1 mm: 2e-4 .. 7e-3)
_LN2 = math.log(2.0)


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def expm1_small(d: float) -> float:
    """e^d - 1; series to d^5 / 5! for |d| < SMALL."""
    if abs(d) >= SMALL:
        return math.expm1(d)
    return d * (1.0 + d * (1 / 2 + d * (1 / 6 + d * (1 / 24 + d * (1 / 120)))))


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def exp_small(d: float) -> float:
    """e^d; series for |d| < SMALL."""
    if abs(d) >= SMALL:
        return math.exp(d)
    return 1.0 + expm1_small(d)


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def log1p_small(a: float) -> float:
    """ln(1 + a); series to a^6 / 6 for |a| < SMALL."""
    if abs(a) >= SMALL:
        return math.log1p(a)
    return a * (1.0 - a * (1 / 2 - a * (1 / 3 - a * (1 / 4 - a * (1 / 5 - a * (1 / 6))))))


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def tanh_of(x: float, em2: float) -> float:
    """tanh x from em2 = exp(-2 |x|)."""
    t = (1.0 - em2) / (1.0 + em2)
    return t if x >= 0 else -t


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def tanh(x: float) -> float:
    """tanh x with one exp (the library's tanh costs about two)."""
    return tanh_of(x, math.exp(-2.0 * abs(x)))


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def tanh_step(t0: float, x0: float, x1: float) -> float:
    """tanh x1 from t0 = tanh x0."""
    d = x1 - x0
    if abs(d) >= SMALL:
        return tanh(x1)
    d2 = d * d
    td = d * (1.0 - d2 * (1 / 3 - d2 * (2 / 15)))  # tanh d to d^5
    return (t0 + td) / (1.0 + t0 * td)


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def softplus(x: float, em: float) -> tuple[float, float]:
    """(sp(x) = ln(1 + e^x), sigma(x) = 1 / (1 + e^-x)) from em = exp(-|x|)."""
    sig = 1.0 / (1.0 + em)
    return max(x, 0.0) + math.log(1.0 + em), sig if x >= 0 else em * sig


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def softplus_step(sp0: float, sig0: float, x0: float, x1: float) -> tuple[float, float]:
    """(sp(x1), sigma(x1)) from sp0 = sp(x0), sig0 = sigma(x0)."""
    d = x1 - x0
    if abs(d) >= SMALL:
        return softplus(x1, math.exp(-abs(x1)))
    c = expm1_small(d)
    a = sig0 * c
    return sp0 + log1p_small(a), sig0 * (1.0 + c) / (1.0 + a)


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def logcosh(x: float) -> tuple[float, float]:
    """(ln cosh x, tanh x)."""
    a = abs(x)
    em2 = math.exp(-2.0 * a)
    return a + math.log(1.0 + em2) - _LN2, tanh_of(x, em2)


@numba.njit(cache=True, error_model="numpy", inline="always", fastmath=FAST)
def logcosh_step(lc0: float, t0: float, x0: float, x1: float) -> tuple[float, float]:
    """(ln cosh x1, tanh x1) from lc0 = ln cosh x0, t0 = tanh x0."""
    d = x1 - x0
    if abs(d) >= SMALL:
        return logcosh(x1)
    d2 = d * d
    sinh_d = d * (1.0 + d2 * (1 / 6 + d2 * (1 / 120)))
    cosh_d_1 = d2 * (1 / 2 + d2 * (1 / 24 + d2 * (1 / 720)))
    return lc0 + log1p_small(cosh_d_1 + t0 * sinh_d), tanh_step(t0, x0, x1)
