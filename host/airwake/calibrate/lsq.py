"""Fast calibration: one-step-ahead (equation-error) nonlinear least squares.

    minimise  sum_n sum_c ((z_c[n] - z_hat_c[n; p]) / s_c)^2    over the free parameters p

with `scipy.optimize.least_squares` (trust-region reflective, bounds from the effects),
z_hat from `WindowedPredictor` (measured body states, simulated rotor states; see
`residuals.py` for the windows and the channel scales s_c). Parameters are optimised in
bound-scaled form q = (p - lo)/(hi - lo) in [0, 1] (plus `x_scale="jac"`), so a Lock
number and a flap stiffness share one trust region. The Jacobian is a forward finite
difference with step 1e-4 max(|p|, 1 % of the bound width), all perturbed parameter sets
evaluated in one batched pass (K = number of free parameters rows per window and step).
Parameter uncertainty and identifiability: `fit.uncertainty` from the final Jacobian.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.optimize import least_squares

from airwake.calibrate.fit import FitResult, identifiability_notes, uncertainty
from airwake.calibrate.residuals import WindowedPredictor

FD_REL_STEP = 1e-4
PENALTY = 1e3  # weighted residual given to every sample of an invalid parameter set


class _Problem:
    """Residuals and Jacobian in bound-scaled coordinates, with a one-point cache."""

    def __init__(self, predictor: WindowedPredictor, full0: np.ndarray, free: np.ndarray,
                 lo: np.ndarray, hi: np.ndarray, progress=None) -> None:
        self.pred = predictor
        self.full0 = full0.copy()
        self.free = free
        self.lo, self.hi = lo, hi
        self.width = hi - lo
        self.progress = progress
        self._cache_q = None
        self._cache_r = None
        self.history: list[float] = []
        self.n_jac = 0

    def full(self, q: np.ndarray) -> np.ndarray:
        p = self.full0.copy()
        p[self.free] = self.lo + np.clip(q, 0.0, 1.0) * self.width
        return p

    def _residual_sets(self, sets: np.ndarray) -> np.ndarray:
        r, valid = self.pred.residuals(sets)
        r[~valid] = PENALTY
        return np.where(np.isfinite(r), r, PENALTY)

    def fun(self, q: np.ndarray) -> np.ndarray:
        if self._cache_q is not None and np.array_equal(q, self._cache_q):
            return self._cache_r
        r = self._residual_sets(self.full(q)[None])[0]
        self._cache_q, self._cache_r = q.copy(), r
        rms = float(np.sqrt(np.mean(r * r)))
        self.history.append(rms)
        if self.progress is not None:
            self.progress.update(len(self.history), f"weighted rms {rms:.4g}")
        return r

    def steps(self, q: np.ndarray) -> np.ndarray:
        p = self.lo + q * self.width
        h = FD_REL_STEP * np.maximum(np.abs(p), 0.01 * self.width) / self.width
        return np.where(q + h > 1.0, -h, h)  # step inwards at the upper bound

    def jac(self, q: np.ndarray) -> np.ndarray:
        r0 = self.fun(q)
        h = self.steps(q)
        base = self.full(q)
        sets = np.repeat(base[None], h.size, 0)
        idx = np.flatnonzero(self.free)
        sets[np.arange(h.size), idx] = self.lo + (q + h) * self.width
        r = self._residual_sets(sets)  # (p, n)
        self.n_jac += 1
        return ((r - r0[None]) / h[:, None]).T


def _tolerance(n_residuals: int) -> float:
    """Relative cost tolerance: stop when a step gains less than 0.1 in chi^2 (the cost is
    ~n/2 at the noise floor), i.e. when the parameters move by a small fraction of their
    uncertainty."""
    return float(np.clip(0.1 / max(n_residuals, 1), 1e-10, 1e-6))


def fit_lsq(model, predictor: WindowedPredictor, free: np.ndarray, max_nfev: int = 60,
            tol: float | None = None, coarse_fraction: float = 0.125,
            progress=None) -> FitResult:
    """Fit the free parameters (mask over model.parameter_names) by least squares.

    Long flights (>= 64 windows) are fitted in two stages: first on an evenly spaced
    `coarse_fraction` of the windows (each iteration ~1/8 of the cost), then on all of
    them from there; the answer is the second stage's, on the whole flight."""
    t0 = time.perf_counter()
    full0 = model.parameter_vector()
    lo_all, hi_all = model.bounds()
    lo, hi = lo_all[free], hi_all[free]
    q0 = np.clip((full0[free] - lo) / (hi - lo), 0.0, 1.0)
    rms_before = predictor.channel_rms(full0[None])[0]
    n_win = predictor.windows.n_windows
    history, nfev, njev, stages = [], 0, 0, []
    if coarse_fraction and n_win >= 64:
        pick = np.unique(np.linspace(0, n_win - 1, max(int(n_win * coarse_fraction), 32))
                         .round().astype(int))
        coarse = WindowedPredictor(model, predictor.data, predictor.windows.subset(pick))
        prob = _Problem(coarse, full0, free, lo, hi, progress)
        res = least_squares(prob.fun, q0, jac=prob.jac, bounds=(0.0, 1.0), method="trf",
                            x_scale="jac", ftol=tol or _tolerance(coarse.windows.n_scored * 6),
                            xtol=1e-8, gtol=1e-8, max_nfev=max_nfev)
        q0 = np.clip(res.x, 0.0, 1.0)
        history += prob.history
        nfev, njev = nfev + int(res.nfev), njev + prob.n_jac
        stages.append(f"{len(pick)} of {n_win} windows: {int(res.nfev)} evaluations")
        predictor.evaluations += coarse.evaluations
    prob = _Problem(predictor, full0, free, lo, hi, progress)
    res = least_squares(prob.fun, q0, jac=prob.jac, bounds=(0.0, 1.0), method="trf",
                        x_scale="jac", ftol=tol or _tolerance(predictor.windows.n_scored * 6),
                        xtol=1e-8, gtol=1e-8, max_nfev=max_nfev)
    stages.append(f"all {n_win} windows: {int(res.nfev)} evaluations")
    q = np.clip(res.x, 0.0, 1.0)
    full = prob.full(q)
    fitted = model.with_parameters(full)
    jac_q = res.jac if np.array_equal(q, res.x) else prob.jac(q)
    jac_p = np.asarray(jac_q) / (hi - lo)[None, :]  # d r / d p
    r = prob.fun(q)
    at_bound = (q <= 1e-9) | (q >= 1 - 1e-9)
    names = [n for n, f in zip(model.parameter_names, free, strict=True) if f]
    unc = uncertainty(jac_p, r, names, full[free], at_bound,
                      clusters=predictor.windows.residual_windows())
    notes, ident = identifiability_notes(names, full[free], unc, at_bound)
    rms_after, offset_after = (v[0] for v in predictor.channel_stats(full[None]))
    return FitResult(
        method="lsq", model=fitted, names=names, start=full0[free], values=full[free],
        std=unc.std, std_white=unc.std_white, uncertainty_kind=unc.kind,
        correlation=unc.correlation, at_bound=at_bound, identifiable=ident,
        notes=notes, rms_before=rms_before, rms_after=rms_after,
        noise_scale=predictor.data.scale, cost_history=history + prob.history,
        evaluations=predictor.evaluations, seconds=time.perf_counter() - t0,
        info={"status": int(res.status), "message": str(res.message),
              "nfev": nfev + int(res.nfev), "njev": njev + int(prob.n_jac),
              "stages": "; ".join(stages), "residual_sigma": float(np.sqrt(unc.sigma2)),
              "condition": float(unc.condition),
              "model_error_offset": [float(v) for v in offset_after]},
    )
