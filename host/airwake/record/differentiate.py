"""The smoothing differentiator of the flight tables: angular acceleration from rates.

    pdot(t_k) = d/dt of the least-squares polynomial of degree `polyorder` through the
                samples within +-window_s/2 of t_k (Savitzky-Golay, deriv=1)

A Savitzky-Golay derivative is exact for polynomials up to `polyorder` and a low-pass
whose -3 dB point is about (polyorder + 1) / (3.2 * n_window - 4.6) * f_s. Defaults:
0.1 s (15 samples at 150 Hz), order 3 (in the interior order 3 and 4 give the same
derivative; order 2 equals a straight-line slope, which loses 4 % of a 2 Hz sine): the
passband reaches ~14 Hz, above the helicopter's rigid-body dynamics, and the rotor's
vibration (2 x ~25 Hz for two blades) is attenuated.

The samples are split where the spacing exceeds `max_gap_factor` x the median spacing;
each run is differentiated on its own (edges by fitting the end window, scipy's
`mode="interp"`), so a gap never produces a spurious spike. The recorder export and the
simulator's `sim table` fast path both call `smooth_derivative`.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import savgol_filter

DERIVATIVE_WINDOW_S = 0.1
DERIVATIVE_POLYORDER = 3


def split_runs(t_s: np.ndarray, max_gap_factor: float = 3.0) -> list[slice]:
    """Slices of consecutive samples with no spacing above max_gap_factor x median."""
    t = np.asarray(t_s, dtype=float)
    if t.size < 2:
        return [slice(0, t.size)]
    dt = np.diff(t)
    typical = float(np.median(dt))
    cuts = np.flatnonzero(dt > max_gap_factor * typical) + 1
    edges = [0, *cuts.tolist(), t.size]
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:], strict=True)]


def derivative_window(dt_s: float, window_s: float = DERIVATIVE_WINDOW_S,
                      polyorder: int = DERIVATIVE_POLYORDER) -> int:
    """The odd number of samples the derivative fits at a sample spacing dt_s."""
    window = int(round(window_s / dt_s)) | 1  # odd
    return max(window, polyorder + 2 | 1)


def smooth_derivative(t_s: np.ndarray, x: np.ndarray, window_s: float = DERIVATIVE_WINDOW_S,
                      polyorder: int = DERIVATIVE_POLYORDER,
                      max_gap_factor: float = 3.0) -> np.ndarray:
    """d x / d t, x of shape (N,) or (N, C) sampled at increasing t_s (N,); same shape out."""
    t = np.asarray(t_s, dtype=float)
    x = np.asarray(x, dtype=float)
    if x.shape[0] != t.size:
        raise ValueError(f"x has {x.shape[0]} rows, t_s has {t.size}")
    if window_s <= 0 or polyorder < 1:
        raise ValueError(f"window_s = {window_s!r}, polyorder = {polyorder!r}: need > 0 and >= 1")
    out = np.zeros_like(x)
    for run in split_runs(t, max_gap_factor):
        tr, xr = t[run], x[run]
        n = tr.size
        if n < 2:
            continue
        dt = float(np.median(np.diff(tr)))
        window = derivative_window(dt, window_s, polyorder)
        if n < window:
            out[run] = np.gradient(xr, tr, axis=0)
            continue
        out[run] = savgol_filter(xr, window, polyorder, deriv=1, delta=dt, axis=0, mode="interp")
    return out
