"""A wind net's interval at sea: its own error plus the wind's fast part it cannot see.

    fast = disagreement_std(net_df, model_df)        # (n, 3) m/s, at the net's samples
    std = np.sqrt(net_std**2 + fast**2)

A still-air wind net (docs/networks.md "Still-air labels") learns the air velocity from
flights where it changes only as fast as the pilot flies. At sea, measured against the
blade-element truth's spectra, it follows the wind below about 0.1 Hz (gain 0.94-1.04),
lags between 0.1 and 0.3 Hz and misses what is faster; its validation error, measured in
still air, leaves that part out, so its interval alone covers about half to four fifths
of the truth at sea (0.45-0.83 on the blade-element ship flights).

The model's smoother (`airwake.estimate.smoother`) reads the wind through the dynamics:
it follows the fast part, with a steady offset from the model's misfit and a fast error
of its own. Both read the same INS velocity, so its error cancels in their difference.
Above the net's band the difference (model - net) is the fast wind the net misses plus
the smoother's own fast error. The two are not independent: the smoother follows the
fast wind only in part, so its fast error is the wind it leaves out (correlation with
the fast truth -0.23 ... -0.79 on four blade-element ship flights and the fans), and the
difference's local power falls short of the net's missing part (on v_y of two b0 flights
its RMS is 0.09 / 0.11 m/s against the net's fast error of 0.13 / 0.14, 2026-11-29; the
slow part of the net's error at sea, 0.07-0.24 against its still-air 0.07-0.11, is not
in it either; docs/networks.md). It is what the flight shows of that part without a
truth. The difference is high-passed by a centred Gaussian whose complement passes half
the power at `HIGHPASS_HZ` (the net's measured band edge) and its square averaged over a
centred Gaussian window of `WINDOW_S` (1 sigma, cut at 3: 30 s in all, most of its
weight in the middle 20 s; several correlation times of the high-passed wind) — local,
because the airwake's turbulence is not the same everywhere over the deck. Offline only:
both windows read the future.
"""

from __future__ import annotations

import math

import numpy as np

HIGHPASS_HZ = 0.1  # the still-air net's band edge at sea (module doc)
WINDOW_S = 5.0  # 1 sigma of the local-power window (s)
MEAN_FLOW = ("wind_vx_m_s", "wind_vy_m_s", "wind_vz_m_s")


def highpass_sigma_s(corner_hz: float) -> float:
    """The Gaussian's sigma (s) whose complement (y - G*y) passes half the power at
    `corner_hz`: 1 - exp(-(2 pi f sigma)^2 / 2) = 1/sqrt(2)."""
    if not (np.isfinite(corner_hz) and corner_hz > 0):
        raise ValueError(f"high-pass corner {corner_hz!r} Hz: must be a number > 0")
    return math.sqrt(-2.0 * math.log(1.0 - 1.0 / math.sqrt(2.0))) / (2.0 * math.pi * corner_hz)


def _rate_hz(t: np.ndarray) -> float:
    dt = np.diff(t)
    if t.size < 3 or not np.all(dt > 0):
        raise ValueError("the net's estimate needs at least 3 samples at increasing times")
    return 1.0 / float(np.median(dt))


def _fill(y: np.ndarray) -> np.ndarray:
    """y (n,) with its non-finite samples interpolated from the finite ones."""
    ok = np.isfinite(y)
    if ok.all():
        return y
    if not ok.any():
        raise ValueError("no sample of the difference is finite")
    idx = np.arange(y.size)
    return np.interp(idx, idx[ok], y[ok])


def disagreement_std(net_df, model_df, highpass_hz: float = HIGHPASS_HZ,
                     window_s: float = WINDOW_S) -> np.ndarray:
    """(n, 3) the local RMS (m/s) of (model - net) above `highpass_hz`, per mean-flow
    component at the net table's times (module doc). `net_df`, `model_df`: wind tables
    (`t_s` and the `wind_v*_m_s` columns); the model's is interpolated to the net's
    times and held at its ends."""
    from airwake.nets.features import gaussian_smooth

    if not (np.isfinite(window_s) and window_s > 0):
        raise ValueError(f"window {window_s!r} s: must be a number > 0")
    t = np.asarray(net_df["t_s"], dtype=float)
    tm = np.asarray(model_df["t_s"], dtype=float)
    rate = _rate_hz(t)
    hp_sigma = highpass_sigma_s(highpass_hz)
    out = np.empty((t.size, len(MEAN_FLOW)))
    for j, name in enumerate(MEAN_FLOW):
        ref = np.interp(t, tm, np.asarray(model_df[name], dtype=float))
        d = _fill(ref - np.asarray(net_df[name], dtype=float))
        hp = d - gaussian_smooth(d, rate, hp_sigma, 3.0 * hp_sigma)
        out[:, j] = np.sqrt(gaussian_smooth(hp * hp, rate, window_s, 3.0 * window_s))
    return out
