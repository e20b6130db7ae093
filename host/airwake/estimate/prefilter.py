"""The wind estimators' front end: a zero-phase low-pass below the rotor's harmonics, then
decimation.

    pre = prefilter(data, model, cutoff_hz=6.0, rate_hz=15.0)   # data: residuals.FlightData
    pre.data     # FlightData at the kept samples: t, x (body states), u, env, z, runs, dt
    pre.mid_x, pre.mid_u, pre.mid_env   # inputs half-way between consecutive kept samples
    pre.index    # (n,) flight rows of the kept samples

Why: the six measured channels of a flying helicopter carry rotor-synchronous vibration at
1/rev and 2/rev (26 and 52 Hz for a 600-class rotor at 163 rad/s) that is 10-30x larger than
the broadband sensor noise, and the body rates and velocities the model reads carry the
same vibration (it is sensor noise to the model: the airframe does not move at 52 Hz). The
wind the helicopter feels — turbulence convected past a 1.3 m rotor at a few m/s — lives
below ~3 Hz. So every signal the estimator reads (measured body states, inputs, rotor
speed and the six channels) goes through the same zero-phase Butterworth low-pass
(`scipy.signal.sosfiltfilt`, order 4 applied forward and backward: no phase lag, -6 dB at
`cutoff_hz`, -48 dB/octave beyond) and is then sampled every D-th row,
D = round(f_s / rate_hz), with `rate_hz` >= 2.5 x `cutoff_hz` so nothing aliases. On the
truth world's ship flights this takes the channels' noise floor from 0.12 / 0.12 / 0.29
m/s^2 and 0.08 / 0.08 / 0.04 rad/s^2 to below 0.01 (docs/wind-estimation.md). Filtering a
nonlinear model's inputs and outputs alike is exact for its linear part and, for the
slowly varying flight states, close to it for the rest.

Each continuous run of the flight (split at time gaps) is filtered on its own; a run too
short to filter (under 1 s or 3 filter lengths) is left out, and `runs` lists the kept
runs in decimated samples. Heights above ground that are not finite (+inf: no height
measured) are passed through unfiltered.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal

from airwake.calibrate.residuals import FlightData
from airwake.estimate.errors import WindEstimationError

CUTOFF_HZ = 6.0
RATE_HZ = 15.0
FILTER_ORDER = 4
MIN_RUN_S = 1.0
# cutoff must stay below this fraction of the rotor's 1/rev frequency
MAX_CUTOFF_OVER_1REV = 0.5


@dataclass
class Prefiltered:
    """The decimated, low-passed flight (see module docstring). `data` is a FlightData of
    the kept samples (n rows); `mid_x` (n, S), `mid_u` (n, 4), `mid_env` {name: (n,)} the
    filtered inputs half-way between sample k-1 and k (row 0 repeats sample 0); `index`
    (n,) the kept rows of the original flight; `cutoff_hz`, `rate_hz` (actual), `factor` D."""

    data: FlightData
    mid_x: np.ndarray
    mid_u: np.ndarray
    mid_env: dict
    index: np.ndarray
    cutoff_hz: float
    rate_hz: float
    factor: int

    def __len__(self) -> int:
        return self.data.t.size


def check_settings(cutoff_hz: float, rate_hz: float, sample_rate_hz: float,
                   rotor_speed_rad_s: float | None = None) -> int:
    """Decimation factor D for the settings; WindEstimationError naming the option when a
    setting cannot work (aliasing, above the rotor's 1/rev, above the flight's rate)."""
    if not (np.isfinite(cutoff_hz) and cutoff_hz > 0):
        raise WindEstimationError(f"--cutoff-hz {cutoff_hz!r}: must be a positive number")
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise WindEstimationError(f"--rate-hz {rate_hz!r}: must be a positive number")
    if rate_hz > sample_rate_hz * 1.0001:
        raise WindEstimationError(
            f"--rate-hz {rate_hz:g}: above the flight's own rate ({sample_rate_hz:.4g} Hz)")
    factor = max(int(round(sample_rate_hz / rate_hz)), 1)
    actual = sample_rate_hz / factor
    if cutoff_hz > actual / 2.5 * 1.01:  # 1 %: a recorder's clock is not exactly 150 Hz
        raise WindEstimationError(
            f"--cutoff-hz {cutoff_hz:g}: must be at most rate / 2.5 = {actual / 2.5:.3g} Hz "
            f"(the estimator samples at {actual:.4g} Hz; a higher cutoff aliases)")
    if cutoff_hz >= 0.45 * sample_rate_hz:
        raise WindEstimationError(
            f"--cutoff-hz {cutoff_hz:g}: must be below 0.45 x the flight's rate "
            f"({sample_rate_hz:.4g} Hz)")
    if rotor_speed_rad_s is not None and np.isfinite(rotor_speed_rad_s) and rotor_speed_rad_s > 0:
        one_rev = rotor_speed_rad_s / (2.0 * np.pi)
        if cutoff_hz > MAX_CUTOFF_OVER_1REV * one_rev:
            raise WindEstimationError(
                f"--cutoff-hz {cutoff_hz:g}: must be below half the rotor's 1/rev frequency "
                f"({one_rev:.3g} Hz at {rotor_speed_rad_s:.4g} rad/s): the rotor's vibration "
                "would pass into the estimator")
    return factor


def _lowpass(sos, a: np.ndarray) -> np.ndarray:
    return signal.sosfiltfilt(sos, a, axis=0)


def prefilter(data: FlightData, model, cutoff_hz: float = CUTOFF_HZ,
              rate_hz: float = RATE_HZ) -> Prefiltered:
    """Low-pass every signal the measurement model reads and keep every D-th sample
    (module docstring). `model` names the measured states (the columns filtered)."""
    fs = 1.0 / data.dt
    omega = data.env.get("rotor_speed_rad_s")
    om = float(np.median(omega)) if omega is not None else _nominal_rotor_speed(model)
    factor = check_settings(cutoff_hz, rate_hz, fs, om)
    sos = signal.butter(FILTER_ORDER, cutoff_hz / (fs / 2.0), output="sos")
    body = [model.state_index(s) for s in model.measured_states]
    yaw = [i for i in body if model.state_names[i].endswith("yaw_rad")]
    pad = 3 * (2 * sos.shape[0] + 1)
    min_len = max(pad + 1, int(np.ceil(MIN_RUN_S * fs)), 2 * factor + 1)
    keep, mid_rows, runs = [], [], []
    x_f = np.zeros_like(data.x)
    u_f = np.empty_like(data.u)
    z_f = np.empty_like(data.z)
    env_f = {k: np.asarray(v, float).copy() for k, v in data.env.items()}
    for run in data.runs:
        a, b = run.start, run.stop
        if b - a < min_len:
            continue
        xs = data.x[a:b][:, body].copy()
        for j, i in enumerate(body):
            if i in yaw:
                xs[:, j] = np.unwrap(xs[:, j])
        x_f[a:b, body] = _lowpass(sos, xs)
        u_f[a:b] = _lowpass(sos, data.u[a:b])
        z_f[a:b] = _lowpass(sos, data.z[a:b])
        for k, v in env_f.items():
            seg = np.asarray(data.env[k][a:b], float)
            if np.all(np.isfinite(seg)):
                v[a:b] = _lowpass(sos, seg)
        rows = np.arange(a, b, factor)
        start = len(keep)
        keep.extend(rows.tolist())
        mid_rows.extend((rows - factor / 2.0).tolist())
        runs.append(slice(start, len(keep)))
    if not keep:
        raise WindEstimationError(
            f"{data.source}: no continuous run of the flight is longer than "
            f"{min_len / fs:.2f} s; nothing to estimate")
    idx = np.asarray(keep, dtype=int)
    mid = np.asarray(mid_rows, dtype=float)
    for run in runs:  # the first sample of a run has no predecessor: its own inputs
        mid[run.start] = idx[run.start]
    lo = np.floor(mid).astype(int)
    hi = np.ceil(mid).astype(int)
    frac = (mid - lo)[:, None]

    def at_mid(a):
        a = np.asarray(a, float)
        f = frac[:, 0] if a.ndim == 1 else frac
        with np.errstate(invalid="ignore"):
            out = a[lo] * (1.0 - f) + a[hi] * f
        return np.where(np.isfinite(out), out, a[lo])  # +inf heights stay +inf

    dec = FlightData(t=data.t[idx], x=x_f[idx], u=u_f[idx],
                     env={k: v[idx] for k, v in env_f.items()}, z=z_f[idx], runs=runs,
                     dt=factor * data.dt, scale=data.scale.copy(), source=data.source)
    return Prefiltered(dec, at_mid(x_f), at_mid(u_f), {k: at_mid(v) for k, v in env_f.items()},
                       idx, float(cutoff_hz), fs / factor, factor)


def _nominal_rotor_speed(model) -> float | None:
    try:
        return float(model["main_rotor"].parameters()["nominal_speed_rad_s"])
    except (KeyError, TypeError):
        return None
