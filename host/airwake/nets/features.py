"""Input features of the pilot-compensation networks (reference §2.1.4.1, §2.2.2, §2.1.5).

Every filter here is causal (a feature at sample t reads samples <= t only), vectorised
over time and channels, and takes its window lengths in seconds (`FeatureConfig`) so a
net trained at one sample rate can be applied at another. The start of a record, where a
trailing window would reach before the first sample, is edge-padded with the first
sample; the time-block split's guard keeps those rows out of training and scoring.

    line_fit(y, n)              -> slope, intercept, error      eq 2.1, 2.2
    gaussian_lowpass(y, ...)    -> low-passed y                 eq 2.3 (trailing half, causal)
    gaussian_smooth(y, ...)     -> low-passed y                 eq 2.3 (centred: scoring only)
    local_std(y, n)             -> trailing standard deviation
    build_features(inputs, roll, pitch, rates, rate_hz, config) -> (n, F), names
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

INPUT_CHANNELS = ("lat", "lon", "col", "ped")
RATE_NAMES = ("p", "q", "r")


@dataclass(frozen=True)
class FeatureConfig:
    """Window lengths (s) and which feature groups feed the network.

    line_window_s: history window of the line fit per input channel (eq 2.1-2.2; the
        reference used 15 samples = 0.5 s in §2.1 and 43 samples = 0.944 s in §2.2.2).
    lowpass_sigma_s, lowpass_length_s: eq 2.3's t_sigma and t_L of the causal Gaussian
        low-pass of each input (the reference's 0.6 / 1.0 s suit vibration removal of
        gyro data, far too slow for pilot inputs of a few Hz).
    std_window_s: trailing local standard deviation of each input.
    rate_lag_samples: previous body rates fed back (§2.2.2, "recurrent"); for the rate
        target it must be >= 1 (0 would hand the answer to the net); for the angular
        acceleration target 0 means the current rates (§4.3, eq 4.10).
    rate_history_samples: how many past samples of each rate are fed back: lags
        rate_lag_samples ... rate_lag_samples + rate_history_samples - 1 (1: the lagged
        rate alone, as the reference). More lags let a linear model (and the net's ARX
        part) track a periodic signal on the gyro: the T-REX 550's 34 Hz rotor 1/rev.
    use_attitude: roll and pitch angles as inputs (gravity / tilt terms).
    use_rate_lowpass: also the causal low-pass (eq 2.3, the inputs' sigma and length) of
        the lagged rates: a real gyro's sample-to-sample noise (the T-REX 550 log: as
        large as the rates themselves) otherwise enters the prediction one-to-one.
    use_rates: False makes a pilot-only net: no rate is fed back (the rate lag, history
        and rate low-pass are then unused), the prediction is the motion the pilot's
        inputs (and the attitude, with use_attitude) explain — eq 2.4's ω′ as the
        reference meant it, rather than a one-step prediction that tracks ω.
    """

    line_window_s: float = 0.5
    lowpass_sigma_s: float = 0.05
    lowpass_length_s: float = 0.15
    std_window_s: float = 0.5
    rate_lag_samples: int = 1
    rate_history_samples: int = 1
    use_lowpass: bool = True
    use_std: bool = True
    use_attitude: bool = True
    use_rate_lowpass: bool = True
    use_rates: bool = True

    def __post_init__(self) -> None:
        for name in ("line_window_s", "lowpass_sigma_s", "lowpass_length_s", "std_window_s"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"FeatureConfig.{name} must be > 0 s, got {v!r}")
        if self.lowpass_sigma_s >= self.lowpass_length_s:
            raise ValueError("FeatureConfig: eq 2.3 needs lowpass_sigma_s < lowpass_length_s "
                             f"(got {self.lowpass_sigma_s} >= {self.lowpass_length_s})")
        if int(self.rate_lag_samples) != self.rate_lag_samples or self.rate_lag_samples < 0:
            raise ValueError(f"FeatureConfig.rate_lag_samples must be an integer >= 0, got "
                             f"{self.rate_lag_samples!r}")
        n = self.rate_history_samples
        if int(n) != n or n < 1:
            raise ValueError(f"FeatureConfig.rate_history_samples must be an integer >= 1, got "
                             f"{n!r}")

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> FeatureConfig:
        known = {f.name for f in fields(cls)}
        return cls(**{k: v for k, v in d.items() if k in known})

    def samples(self, seconds: float, rate_hz: float) -> int:
        """A window of `seconds` at `rate_hz` in samples (at least 2)."""
        return max(2, int(round(seconds * rate_hz)))

    def history_s(self, rate_hz: float) -> float:
        """How far back the features reach: the split's guard at each block start."""
        longest = max(self.line_window_s, self.lowpass_length_s, self.std_window_s)
        if not self.use_rates:
            return longest
        return longest + (self.rate_lag_samples + self.rate_history_samples) / rate_hz


def _trailing_windows(y: np.ndarray, n: int) -> np.ndarray:
    """(T, C) -> (T, C, n) trailing windows, oldest first, edge-padded at the start."""
    y = np.asarray(y, dtype=float)
    padded = np.concatenate([np.repeat(y[:1], n - 1, axis=0), y], axis=0)
    return sliding_window_view(padded, n, axis=0)


def line_fit(y: np.ndarray, n: int, dt: float = 1.0):
    """Least-squares line over the trailing `n` samples of each channel, eqs 2.1-2.2.

    y: (T, C). x_i is the sample time relative to the current sample, (i - n + 1) * dt,
    so the slope m is per second (per sample with dt = 1) and the intercept c is the
    line's value now. Returns slope, intercept, error (each (T, C)) with the error the
    eq 2.2 sum of absolute residuals over the window.

        m = (N Sxy - Sx Sy) / (N Sxx - Sx^2),  c = (Sxx Sy - Sx Sxy) / (N Sxx - Sx^2)   (2.1)
        e = sum_i |y_i - (m x_i + c)|                                                  (2.2)
    """
    if n < 2:
        raise ValueError(f"line_fit needs a window of >= 2 samples, got {n}")
    w = _trailing_windows(np.atleast_2d(np.asarray(y, float).T).T, n)  # (T, C, n)
    x = (np.arange(n) - (n - 1)) * float(dt)
    sx, sxx = x.sum(), (x * x).sum()
    sy = w.sum(axis=-1)
    sxy = w @ x
    den = n * sxx - sx * sx
    m = (n * sxy - sx * sy) / den
    c = (sxx * sy - sx * sxy) / den
    e = np.abs(w - (m[..., None] * x + c[..., None])).sum(axis=-1)
    return m, c, e


def gaussian_kernel(rate_hz: float, sigma_s: float, length_s: float, causal: bool) -> np.ndarray:
    """Eq 2.3 sampled at `rate_hz`: G(x) ~ exp(-x^2 / (2 sigma^2)) for x in [-N t_L, N t_L]
    (causal: x in [-N t_L, 0], the trailing half), normalised to unit sum, oldest first."""
    k = int(round(length_s * rate_hz))
    sigma = sigma_s * rate_hz
    x = np.arange(-k, 1 if causal else k + 1, dtype=float)
    g = np.exp(-(x * x) / (2.0 * sigma * sigma))
    return g / g.sum()


def gaussian_lowpass(y: np.ndarray, rate_hz: float, sigma_s: float, length_s: float):
    """Causal Gaussian low-pass (eq 2.3, trailing half) of y (T,) or (T, C)."""
    y = np.asarray(y, dtype=float)
    g = gaussian_kernel(rate_hz, sigma_s, length_s, causal=True)
    w = _trailing_windows(y.reshape(len(y), -1), g.size)
    return (w @ g).reshape(y.shape)


def gaussian_smooth(y: np.ndarray, rate_hz: float, sigma_s: float, length_s: float):
    """Centred (zero-phase) Gaussian low-pass, eq 2.3 as written; reads the future, so
    for scoring against a smoothed signal only, never as a feature. y (T,) or (T, C)."""
    y = np.asarray(y, dtype=float)
    g = gaussian_kernel(rate_hz, sigma_s, length_s, causal=False)
    k = g.size // 2
    y2 = y.reshape(len(y), -1)
    padded = np.concatenate([np.repeat(y2[:1], k, axis=0), y2, np.repeat(y2[-1:], k, axis=0)])
    return (sliding_window_view(padded, g.size, axis=0) @ g).reshape(y.shape)


def local_std(y: np.ndarray, n: int) -> np.ndarray:
    """Standard deviation over the trailing `n` samples of y (T,) or (T, C)."""
    y = np.asarray(y, dtype=float)
    w = _trailing_windows(y.reshape(len(y), -1), n)
    return w.std(axis=-1).reshape(y.shape)


def lagged(y: np.ndarray, lag: int) -> np.ndarray:
    """y delayed by `lag` samples (edge-padded): row t holds y[t - lag]."""
    y = np.asarray(y, dtype=float)
    if lag == 0:
        return y.copy()
    if lag >= len(y):  # every row's lagged sample lies before the first: the edge pad
        return np.repeat(y[:1], len(y), axis=0)
    return np.concatenate([np.repeat(y[:1], lag, axis=0), y[:-lag]], axis=0)


def build_features(inputs, roll, pitch, rates, rate_hz: float, config: FeatureConfig):
    """The network's input vector per sample.

    inputs (T, 4) pilot inputs in INPUT_CHANNELS order; roll, pitch (T,) rad; rates
    (T, 3) rad/s (p, q, r). Returns (X (T, F), names (F,)). Per input channel: line
    slope, intercept, error (eqs 2.1-2.2), then optionally the causal low-pass (eq 2.3)
    and the local std; then roll, pitch; then (rate_history_samples > 1) p, q, r at the
    further lags, oldest first; then the causal low-pass of the lagged rates (optional)
    and p, q, r delayed by rate_lag_samples: the lagged rates are the last three columns
    (use_rates False: no rate column at all, a pilot-only net).
    """
    inputs = np.asarray(inputs, dtype=float)
    cols, names = [], []
    n_line = config.samples(config.line_window_s, rate_hz)
    m, c, e = line_fit(inputs, n_line, dt=1.0 / rate_hz)
    for j, ch in enumerate(INPUT_CHANNELS):
        cols += [m[:, j], c[:, j], e[:, j]]
        names += [f"{ch}_slope", f"{ch}_intercept", f"{ch}_fit_error"]
    if config.use_lowpass:
        lp = gaussian_lowpass(inputs, rate_hz, config.lowpass_sigma_s, config.lowpass_length_s)
        cols += list(lp.T)
        names += [f"{ch}_lowpass" for ch in INPUT_CHANNELS]
    if config.use_std:
        sd = local_std(inputs, config.samples(config.std_window_s, rate_hz))
        cols += list(sd.T)
        names += [f"{ch}_std" for ch in INPUT_CHANNELS]
    if config.use_attitude:
        cols += [np.asarray(roll, float), np.asarray(pitch, float)]
        names += ["roll", "pitch"]
    if not config.use_rates:
        if not cols:
            raise ValueError("FeatureConfig: no feature left")
        return np.column_stack(cols), names
    lag = int(config.rate_lag_samples)
    prev = lagged(rates, lag)
    for extra in range(lag + int(config.rate_history_samples) - 1, lag, -1):
        cols += list(lagged(rates, extra).T)
        names += [f"{r}_lag{extra}" for r in RATE_NAMES]
    if config.use_rate_lowpass:
        lp = gaussian_lowpass(prev, rate_hz, config.lowpass_sigma_s, config.lowpass_length_s)
        cols += list(lp.T)
        names += [f"{r}_lag{config.rate_lag_samples}_lowpass" for r in RATE_NAMES]
    cols += list(prev.T)
    names += [f"{r}_lag{config.rate_lag_samples}" for r in RATE_NAMES]
    return np.column_stack(cols), names
