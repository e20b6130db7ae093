"""Fixed-step RK4 integration of `HeliModel.derivatives` (batched: N trajectories at once)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


def rk4_step(model, x, u, dt: float, w=None, env=None, params=None) -> np.ndarray:
    """One classical RK4 step, inputs/wind/env held over the step. x (N,S) -> (N,S)."""
    k1 = model.derivatives(x, u, w, env, params)
    k2 = model.derivatives(x + 0.5 * dt * k1, u, w, env, params)
    k3 = model.derivatives(x + 0.5 * dt * k2, u, w, env, params)
    k4 = model.derivatives(x + dt * k3, u, w, env, params)
    return x + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


@dataclass
class Trajectory:
    """Samples of a simulation: t (K,), x (K,N,S), u (K,N,4), w (K,N,6)."""

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    w: np.ndarray


def simulate(
    model,
    x0,
    duration_s: float,
    dt: float,
    inputs: Callable[[float, np.ndarray], np.ndarray],
    wind: Callable[[float], np.ndarray] | None = None,
    env=None,
    params=None,
    sample_every: int = 1,
) -> Trajectory:
    """Integrate from x0 (N,S) with `inputs(t, x) -> (N,4)` (closed loop allowed) and
    `wind(t) -> (N,6)` evaluated at the start of each step; keeps every `sample_every`-th
    state. Python loop over time steps only (never over rows)."""
    x = np.atleast_2d(np.asarray(x0, dtype=float)).copy()
    steps = int(round(duration_s / dt))
    ts, xs, us, ws = [], [], [], []
    for k in range(steps + 1):
        t = k * dt
        u = np.atleast_2d(inputs(t, x))
        w = np.zeros((1, 6)) if wind is None else np.atleast_2d(wind(t))
        if k % sample_every == 0:
            ts.append(t)
            xs.append(x.copy())
            us.append(np.broadcast_to(u, (x.shape[0], 4)).copy())
            ws.append(np.broadcast_to(w, (x.shape[0], 6)).copy())
        if k == steps:
            break
        x = rk4_step(model, x, u, dt, w, env, params)
    return Trajectory(np.array(ts), np.array(xs), np.array(us), np.array(ws))
