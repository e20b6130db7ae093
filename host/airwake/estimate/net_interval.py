"""A wind net's interval at sea: its own error plus the wind's fast part it cannot see.

    fast = disagreement_std(net_df, model_df)              # (n, 3) m/s, at the net's samples
    unseen = unseen_std(net_df["t_s"], model_result)       # (n, 3) m/s
    std = np.sqrt(net_std**2 + fast**2 + unseen**2)

A still-air wind net (docs/networks.md "Still-air labels") learns the air velocity from
flights where it changes only as fast as the pilot flies. At sea, measured against the
blade-element truth's spectra, it follows the wind below about 0.1 Hz (gain 0.94-1.04),
lags between 0.1 and 0.3 Hz and misses what is faster; its validation error, measured in
still air, leaves that part out, so its interval alone covers about half to four fifths
of the truth at sea (0.45-0.83 on the blade-element ship flights).

The model's smoother (`airwake.estimate.smoother`) reads the wind through the dynamics.
Its smoothed fast wind is what the flight showed it; what it did not show is in its
posterior: the smoothed estimate and its error are orthogonal (a linear-Gaussian
smoother's error is uncorrelated with its estimate), so the fast wind's power is the
estimate's plus the posterior variance of the turbulence part (`SmootherResult.fast_std`,
the Gauss-Markov states xi alone, not the slow mean). The net's fast error is then

  - `disagreement_std`: above the net's band, the difference (model - net) — the fast
    wind the smoother saw and the net missed, plus the smoother's own fast error (both
    read the same INS velocity, so its error cancels in the difference). The difference
    is high-passed by a centred Gaussian whose complement passes half the power at
    `HIGHPASS_HZ` (the net's measured band edge) and its square averaged over a centred
    Gaussian window of `WINDOW_S` (1 sigma, cut at 3: 30 s in all, most of its weight in
    the middle 20 s; several correlation times of the high-passed wind) — local, because
    the airwake's turbulence is not the same everywhere over the deck;
  - `unseen_std`: the fast wind the smoother did not see either — its turbulence
    posterior std times the share of a first-order Gauss-Markov process's power above
    the net's band edge, 1 - (2/pi) atan(2 pi f_c tau) (tau the prior's correlation time;
    `share_above`).

The disagreement alone fell short: the smoother follows the fast wind only in part (its
fast error correlates -0.23 ... -0.79 with the fast truth on four blade-element ship
flights and the fans), so on v_y of two b0 flights its RMS was 0.09 / 0.11 m/s against
the net's fast error of 0.13 / 0.14 and the widened interval covered 0.71-0.94 on six
blade-element ship flights and 0.63-0.92 on the effect-model variant (2026-11-29). The unseen
part is only as honest as the posterior, which rests on the turbulence std the EM learns
(`smoother`'s module doc); where the flight hardly informs the mean flow EM converges
slowly from the physics prior's 0.45 m/s, so the interval model's smoother runs
`INTERVAL_EM_PASSES` passes (0.2 s more per minute of flight each after the two
relinearised ones): the learned std falls from 0.45 / 0.45 / 0.35 to 0.28 / 0.25 / 0.17 on
b0 41 (truth 0.14 / 0.18 / 0.20), and six blade-element ship flights cover 0.88-0.98 on
every component (docs/networks.md "The fast wind neither saw"). The number of passes is
chosen, not converged: on b0 41 EM still moves after 48 passes and by then has gone below
the truth's spread on v_y and v_z (the model reads less turbulence than the airframe
feels, so the likelihood's own optimum is too narrow). The slow part of the
net's error at sea (0.07-0.24 m/s below 0.1 Hz against its still-air 0.07-0.11) is in
neither term. Offline only: both windows read the future.
"""

from __future__ import annotations

import math

import numpy as np

HIGHPASS_HZ = 0.1  # the still-air net's band edge at sea (module doc)
WINDOW_S = 5.0  # 1 sigma of the local-power window (s)
INTERVAL_EM_PASSES = 16  # the interval model's smoother: EM passes (module doc)
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


def share_above(corner_hz: float, tau_s) -> np.ndarray:
    """The share of a first-order Gauss-Markov process's variance (correlation time
    `tau_s`, spectrum ~ 1 / (1 + (2 pi f tau)^2)) above `corner_hz`:
    1 - (2/pi) atan(2 pi f_c tau)."""
    tau = np.asarray(tau_s, dtype=float)
    if not (np.isfinite(corner_hz) and corner_hz > 0):
        raise ValueError(f"corner {corner_hz!r} Hz: must be a number > 0")
    if np.any(~np.isfinite(tau)) or np.any(tau <= 0):
        raise ValueError(f"correlation time {tau_s!r} s: must be numbers > 0")
    return 1.0 - (2.0 / np.pi) * np.arctan(2.0 * np.pi * corner_hz * tau)


def unseen_std(t, result, highpass_hz: float = HIGHPASS_HZ) -> np.ndarray:
    """(n, 3) the fast mean-flow wind the smoother's `result` (a `SmootherResult`) did
    not see, at the times `t` (n,): its turbulence posterior std times the square root of
    the Gauss-Markov share above `highpass_hz` (module doc); held at the result's ends,
    its gaps (separate runs) bridged."""
    fast = getattr(result, "fast_std", None)
    if fast is None:
        raise ValueError("the smoother's result carries no turbulence posterior (fast_std)")
    t = np.asarray(t, dtype=float)
    share = np.sqrt(share_above(highpass_hz, result.prior.tau_s[:3]))
    out = np.empty((t.size, len(MEAN_FLOW)))
    for j in range(len(MEAN_FLOW)):
        out[:, j] = share[j] * np.interp(t, result.t, _fill(np.asarray(fast[:, j], float)))
    return out
