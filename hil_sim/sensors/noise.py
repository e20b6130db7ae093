"""Stochastic error processes shared by the sensor models, vectorised over samples.

All take the sample times `t_s` (K,) and an explicit `rng`; none keeps hidden state.
Discrete white noise from a density N (units/sqrt(Hz)) at sample interval dt has
standard deviation `N / sqrt(dt)` (the IEEE-952 / Allan-variance convention: the
Allan deviation at tau = dt equals N / sqrt(dt)).
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter


def white(t_s: np.ndarray, density: np.ndarray | float, rng: np.random.Generator,
          width: int = 3) -> np.ndarray:
    """White noise with density `density` (per axis, units/sqrt(Hz)), shape (K, width)."""
    dt = _mean_dt(t_s)
    sigma = np.broadcast_to(np.asarray(density, dtype=float), (width,)) / np.sqrt(dt)
    return rng.standard_normal((t_s.size, width)) * sigma


def random_walk(
    t_s: np.ndarray,
    density: np.ndarray | float,
    rng: np.random.Generator,
    initial: np.ndarray | float = 0.0,
    width: int = 3,
) -> np.ndarray:
    """Integrated white noise (a random-walk bias), shape (K, width).

    Increment std over dt is `density * sqrt(dt)`; the first sample equals `initial`.
    """
    k = t_s.size
    init = np.broadcast_to(np.asarray(initial, dtype=float), (width,))
    dens = np.broadcast_to(np.asarray(density, dtype=float), (width,))
    if k == 0:
        return np.zeros((0, width))
    if not np.any(dens > 0):
        return np.broadcast_to(init, (k, width)).copy()
    dt = np.diff(t_s)
    steps = rng.standard_normal((k - 1, width)) * np.sqrt(dt)[:, None] * dens
    return init + np.concatenate([np.zeros((1, width)), np.cumsum(steps, axis=0)])


def gauss_markov(
    t_s: np.ndarray,
    sigma: np.ndarray | float,
    tau_s: float,
    rng: np.random.Generator,
    width: int = 3,
) -> np.ndarray:
    """Stationary first-order Gauss-Markov process, std `sigma` per axis, correlation time `tau_s`.

    x[k+1] = a x[k] + sqrt(1 - a^2) sigma n[k], a = exp(-dt / tau), started from the
    stationary distribution (so the std is `sigma` from the first sample on). Uses the
    mean sample interval (the sensors sample on regular clocks).
    """
    k = t_s.size
    sig = np.broadcast_to(np.asarray(sigma, dtype=float), (width,))
    if k == 0 or not np.any(sig > 0):
        return np.zeros((k, width))
    a = float(np.exp(-_mean_dt(t_s) / tau_s))
    n = rng.standard_normal((k, width))
    x0 = n[0] * sig
    drive = n[1:] * sig * np.sqrt(1.0 - a * a)
    rest = lfilter([1.0], [1.0, -a], drive, axis=0, zi=(a * x0)[None, :])[0]
    return np.concatenate([x0[None, :], rest], axis=0)


def quantize(values: np.ndarray, step: float) -> np.ndarray:
    """Round to the nearest multiple of `step` (a sensor's output resolution)."""
    if step <= 0:
        return values
    return np.round(values / step) * step


def _mean_dt(t_s: np.ndarray) -> float:
    if t_s.size < 2:
        return 1.0
    return float((t_s[-1] - t_s[0]) / (t_s.size - 1))
