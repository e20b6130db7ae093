"""The reference's calibrator: particle swarm optimisation (eq 5.16), vectorised.

    V_k = m V_{k-1} + C1 r1 (X_ib - X_{k-1}) + C2 r2 (X_gb - X_{k-1})          (5.16)
    X_k = X_{k-1} + V_k
    m = 0.1 (inertia), C1 = C2 = 0.2, r1, r2 ~ U(0, 1) per particle and dimension.

Fixed parameters have zero velocity (they never move). Bounds: a particle leaving its
box is put back on the bound and that velocity component zeroed. The initial global
best is the starting model (Table 5.1 in the reference); the other particles start
uniformly within +-`spread` (relative) of it, clipped to the bounds. Each iteration
evaluates the whole swarm in one batched pass (`WindowedPredictor`: K = particles
parameter sets x W windows per model evaluation); the cost of a particle is the RMS of
its weighted residuals over a fixed, seeded subset of windows of the flight (the same
subset every iteration so personal/global bests stay comparable). The final global
best is then scored on every window.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from airwake.calibrate.fit import FitResult, identifiability_notes, uncertainty
from airwake.calibrate.residuals import WindowedPredictor

INERTIA = 0.1
C1 = 0.2
C2 = 0.2


def pso_update(x, v, personal_best, global_best, rng, free, lo, hi,
               inertia: float = INERTIA, c1: float = C1, c2: float = C2):
    """One eq 5.16 step for a swarm. x, v, personal_best (N, P); global_best (P,);
    free (P,) bool (False = fixed: zero velocity); lo, hi (P,) bounds. Returns (x, v)
    as new arrays; inputs are not modified."""
    n, p = x.shape
    r1 = rng.random((n, p))
    r2 = rng.random((n, p))
    v_new = inertia * v + c1 * r1 * (personal_best - x) + c2 * r2 * (global_best[None] - x)
    v_new[:, ~free] = 0.0
    x_new = x + v_new
    below = x_new < lo
    above = x_new > hi
    x_new = np.clip(x_new, lo, hi)
    v_new[below | above] = 0.0
    x_new[:, ~free] = x[:, ~free]
    return x_new, v_new


def initial_swarm(start, n_particles: int, rng, free, lo, hi, spread: float = 0.5):
    """(N, P) positions: row 0 = start, the others uniform in start*(1 +- spread) (a
    parameter at 0 spreads over +-spread x 1 % of its bound width), clipped to bounds."""
    start = np.asarray(start, dtype=float)
    half = spread * np.maximum(np.abs(start), 0.01 * (hi - lo))
    x = start + rng.uniform(-1.0, 1.0, (n_particles, start.size)) * half
    x[:, ~free] = start[~free]
    x[0] = start
    return np.clip(x, lo, hi)


@dataclass
class SwarmState:
    x: np.ndarray
    v: np.ndarray
    personal_best: np.ndarray
    personal_cost: np.ndarray
    global_best: np.ndarray
    global_cost: float


def run_pso(cost, start, free, lo, hi, n_particles: int, iterations: int, rng,
            spread: float = 0.5, progress=None, callback=None):
    """Minimise cost((N, P) -> (N,)) with eq 5.16 from `start`. Returns (SwarmState,
    history of the global-best cost per iteration, incl. the start)."""
    x = initial_swarm(start, n_particles, rng, free, lo, hi, spread)
    v = np.zeros_like(x)
    c = _finite(cost(x))
    st = SwarmState(x, v, x.copy(), c.copy(), np.asarray(start, float).copy(), float(c[0]))
    _update_bests(st)
    history = [st.global_cost]
    for it in range(iterations):
        st.x, st.v = pso_update(st.x, st.v, st.personal_best, st.global_best, rng, free, lo, hi)
        c = _finite(cost(st.x))
        better = c < st.personal_cost
        st.personal_best[better] = st.x[better]
        st.personal_cost[better] = c[better]
        _update_bests(st)
        history.append(st.global_cost)
        if progress is not None:
            progress.update(it + 1, f"best {st.global_cost:.5g}")
        if callback is not None:
            callback(it, st)
    return st, history


def _finite(c):
    c = np.asarray(c, dtype=float)
    return np.where(np.isfinite(c), c, np.inf)


def _update_bests(st: SwarmState) -> None:
    i = int(np.argmin(st.personal_cost))
    if st.personal_cost[i] < st.global_cost:
        st.global_cost = float(st.personal_cost[i])
        st.global_best = st.personal_best[i].copy()


def fit_pso(model, predictor: WindowedPredictor, free: np.ndarray, rng,
            n_particles: int = 2000, iterations: int = 500, windows: int | None = 16,
            spread: float = 0.5, progress=None) -> FitResult:
    """Calibrate the free parameters with the swarm; cost = weighted residual RMS over
    `windows` windows of the flight drawn once with `rng` (None: all windows)."""
    t0 = time.perf_counter()
    full0 = model.parameter_vector()
    lo, hi = model.bounds()
    n_win = predictor.windows.n_windows
    if windows is not None and windows < n_win:
        pick = np.sort(rng.choice(n_win, size=windows, replace=False))
        sub = WindowedPredictor(model, predictor.data, predictor.windows.subset(pick))
    else:
        sub = predictor

    st, history = run_pso(sub.cost, full0, free, lo, hi, n_particles, iterations, rng, spread,
                          progress)
    best = st.global_best
    fitted = model.with_parameters(best)
    rms_before = predictor.channel_rms(full0[None])[0]
    rms_after, offset_after = (v[0] for v in predictor.channel_stats(best[None]))
    names = [n for n, f in zip(model.parameter_names, free, strict=True) if f]
    # uncertainty from a finite-difference Jacobian at the swarm's answer (same analysis
    # as the least-squares fit, so the two calibrators' reports compare)
    from airwake.calibrate.lsq import _Problem

    prob = _Problem(predictor, full0, free, lo[free], hi[free])
    q = np.clip((best[free] - lo[free]) / (hi[free] - lo[free]), 0.0, 1.0)
    jac_p = prob.jac(q) / (hi[free] - lo[free])[None, :]
    r = prob.fun(q)
    at_bound = (q <= 1e-9) | (q >= 1 - 1e-9)
    unc = uncertainty(jac_p, r, names, best[free], at_bound,
                      clusters=predictor.windows.residual_windows())
    notes, ident = identifiability_notes(names, best[free], unc, at_bound)
    return FitResult(
        method="pso", model=fitted, names=names, start=full0[free], values=best[free],
        std=unc.std, std_white=unc.std_white, uncertainty_kind=unc.kind,
        correlation=unc.correlation, at_bound=at_bound, identifiable=ident,
        notes=notes, rms_before=rms_before, rms_after=rms_after,
        noise_scale=predictor.data.scale, cost_history=history,
        evaluations=sub.evaluations + predictor.evaluations,
        seconds=time.perf_counter() - t0,
        info={"particles": int(n_particles), "iterations": int(iterations),
              "pso_windows": int(sub.windows.n_windows),
              "residual_sigma": float(np.sqrt(unc.sigma2)),
              "model_error_offset": [float(v) for v in offset_after]},
    )
