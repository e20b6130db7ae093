"""Nonlinear least squares of named model parameters on the equation error.

    res = fit_parameters(analysis, model, ["ground_effect.strength", ...], start={...})

minimises sum_c w_c sum_t [band(z - z_hat(theta))_c(t)]^2 over the analysis mask (the same
band, mask and noise weights every step uses) with `scipy.optimize.least_squares` (trust
region reflective, bounds from the effects' parameter specs). Parameters are scaled to
their bounds; the Jacobian is a forward difference evaluated as one batched prediction
over all perturbed parameter sets.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from airwake.discrepancy.compare import Analysis, predict
from airwake.discrepancy.errors import DiscrepancyError


@dataclass
class FitResult:
    model: object  # the model with the fitted values
    values: dict  # {"effect.param": value}
    start: dict
    zhat: np.ndarray  # (T, 6)
    cost_before: float
    cost_after: float
    nfev: int
    success: bool
    message: str
    at_bound: list  # parameters that ended on a bound


def predict_sets(model, an: Analysis, vectors: np.ndarray, reuse_hidden: bool = False
                 ) -> np.ndarray:
    """(K, T, 6) predictions for K full parameter vectors of `model` (with the analysis'
    known wind as the input, if it has one)."""
    vectors = np.atleast_2d(vectors)
    if reuse_hidden and an.hidden is not None:
        return np.stack([predict(model, an.flight, params=v, hidden=an.hidden, wind=an.wind)
                         for v in vectors])
    if vectors.shape[0] == 1:
        return predict(model, an.flight, params=vectors[0], wind=an.wind)[None]
    return predict(model, an.flight, params=vectors, wind=an.wind)


def weighted_residual(an: Analysis, zhat: np.ndarray) -> np.ndarray:
    """Flattened sqrt(w) * band(z - z_hat) over the mask."""
    r = an.band(an.flight.z - zhat)[an.mask]
    return (r * np.sqrt(an.weights)).reshape(-1)


def fit_parameters(an: Analysis, model, free: list[str], start: dict | None = None, *,
                   max_nfev: int = 25, reuse_hidden: bool = False, progress=None
                   ) -> FitResult:
    """Fit the parameters named in `free` (full names) of `model` (see module docstring)."""
    names = list(model.parameter_names)
    unknown = [f for f in free if f not in names]
    if unknown:
        raise DiscrepancyError(f"unknown parameter(s) {unknown}; the model has "
                               f"{names}")
    if not free:
        raise DiscrepancyError("nothing to fit: no free parameters")
    start = dict(start or {})
    base = model.parameter_vector()
    for k, v in start.items():
        base[names.index(k)] = v
    lo_all, hi_all = model.bounds()
    idx = np.array([names.index(f) for f in free])
    lo, hi = lo_all[idx], hi_all[idx]
    span = hi - lo
    x0 = np.clip((base[idx] - lo) / span, 0.0, 1.0)
    h = 1e-3
    calls = {"n": 0}

    def vec(xs):
        v = np.repeat(base[None], xs.shape[0], 0)
        v[:, idx] = lo + np.clip(xs, 0.0, 1.0) * span
        return v

    def fun(x):
        z = predict_sets(model, an, vec(x[None]), reuse_hidden)[0]
        calls["n"] += 1
        if progress is not None:
            progress.update(calls["n"])
        return weighted_residual(an, z)

    def jac(x):
        steps = np.where(x + h <= 1.0, h, -h)
        pts = np.concatenate([x[None], x[None] + np.diag(steps)])
        zs = predict_sets(model, an, vec(pts), reuse_hidden)
        calls["n"] += pts.shape[0]
        r0 = weighted_residual(an, zs[0])
        cols = [(weighted_residual(an, zs[k + 1]) - r0) / steps[k] for k in range(x.size)]
        return np.column_stack(cols)

    r_start = fun(x0)
    cost0 = float(r_start @ r_start)
    sol = least_squares(fun, x0, jac=jac, bounds=(0.0, 1.0), method="trf", max_nfev=max_nfev,
                        x_scale=1.0, diff_step=None)
    values = {f: float(v) for f, v in zip(free, lo + np.clip(sol.x, 0, 1) * span, strict=True)}
    try:
        fitted = model.with_parameters(values)
    except ValueError as exc:
        raise DiscrepancyError(f"fitted values are invalid: {exc}") from None
    zhat = predict_sets(fitted, an, fitted.parameter_vector()[None], reuse_hidden)[0]
    r = weighted_residual(an, zhat)
    at_bound = [f for f, x in zip(free, sol.x, strict=True) if x <= 1e-6 or x >= 1 - 1e-6]
    return FitResult(fitted, values, {f: float(base[names.index(f)]) for f in free}, zhat,
                     cost0, float(r @ r), calls["n"], bool(sol.success), str(sol.message),
                     at_bound)
