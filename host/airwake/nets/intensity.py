"""Airwake intensity from a pilot-compensation net's residuals (reference §2.1.5, §2.2.3,
§4.4): A_ω per sample, its peaks, and the residuals' local standard deviation.

    pred = predict(net, flight)                       # nets.evaluate
    series = intensity_series(pred, IntensityConfig())
    peaks = find_intensity_peaks(series.t_s, series.a_omega, IntensityConfig())

Eq 2.4, with ω = [p q r] measured and ω′ = [p′ q′ r′] the net's prediction:

    A_ω = (ω_s − ω_s′) · ‖ω − ω′‖

where ω_s is the local standard deviation of the magnitude ‖ω‖ over a window (the
reference's fourth gyro channel, predicted there by NET4) and ω_s′ the same statistic of
the prediction ‖ω′‖ (our nets predict p, q, r; NET4's ω_s′ is their magnitude's local
std). An angular-acceleration net (§4.3) gives ω = [ṗ q̇] and the same formula.

The turbulence statistic calibrated to m/s (§4.4.1) is the norm of the per-axis local
standard deviations of the residuals, `resid_std` (rad/s for rate nets, rad/s² for
acceleration nets). Every window is trailing (samples ≤ t): the same code runs live in
the daemon (`nets.live`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd

_SUFFIXES = ("_resid_rad_s", "_resid_rad_s2")


@dataclass(frozen=True)
class IntensityConfig:
    """Windows (s) of eq 2.4's ω_s and of the residual std; peak detection settings."""

    std_window_s: float = 0.5  # ω_s, ω_s′ and the residuals' local std
    peak_separation_s: float = 15.0  # peaks at least this far apart
    peak_std_window_s: float = 10.0  # the neighbourhood a peak stands above (centred)
    peak_factor: float = 1.5  # ... by at least this many stds of the whole series

    def __post_init__(self) -> None:
        for name in ("std_window_s", "peak_separation_s", "peak_std_window_s", "peak_factor"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"IntensityConfig.{name} = {v!r}: must be a positive number")

    def to_dict(self) -> dict:
        return asdict(self)


def residual_axes(pred: pd.DataFrame) -> tuple[list[str], str]:
    """The axes (p, q, r or pdot, qdot) of a `predict` frame and their unit suffix."""
    for sfx in _SUFFIXES:
        axes = [c[: -len(sfx)] for c in pred.columns if c.endswith(sfx)]
        if axes:
            return axes, sfx[len("_resid"):]
    raise ValueError("not a nets.predict frame: no *_resid_rad_s(2) column in "
                     f"{list(pred.columns)}")


def samples_in(seconds: float, rate_hz: float) -> int:
    return max(2, int(round(seconds * rate_hz)))


def trailing_std(y: np.ndarray, n: int) -> np.ndarray:
    """Standard deviation over the trailing `n` samples of y (T,) or (T, C), the start
    edge-padded (as `nets.features.local_std`), in O(T) from running sums of the values
    less the first one (less cancellation; and row t reads rows <= t only). The live path
    calls it every batch: the sliding-window form was most of its CPU."""
    y = np.asarray(y, dtype=float)
    y2 = y.reshape(len(y), -1)
    c = y2 - y2[:1]
    padded = np.concatenate([np.repeat(c[:1], n - 1, axis=0), c], axis=0)
    zero = np.zeros((1, c.shape[1]))
    s1 = np.cumsum(np.concatenate([zero, padded]), axis=0)
    s2 = np.cumsum(np.concatenate([zero, padded * padded]), axis=0)
    mean = (s1[n:] - s1[:-n]) / n
    var = (s2[n:] - s2[:-n]) / n - mean * mean
    return np.sqrt(np.maximum(var, 0.0)).reshape(y.shape)


def intensity_from_arrays(measured: np.ndarray, predicted: np.ndarray, n_window: int):
    """Eq 2.4 on arrays: measured, predicted (T, K) -> dict of (T,) arrays a_omega,
    omega_s, omega_s_pred, resid_norm, resid_std (trailing windows of n_window samples)."""
    measured = np.asarray(measured, float)
    predicted = np.asarray(predicted, float)
    resid = measured - predicted
    # ω_s, ω_s′: local std of the magnitudes (the reference's fourth gyro channel)
    omega_s = trailing_std(np.linalg.norm(measured, axis=1), n_window)
    omega_s_pred = trailing_std(np.linalg.norm(predicted, axis=1), n_window)
    resid_norm = np.linalg.norm(resid, axis=1)
    # eq 2.4: A_ω = (ω_s − ω_s′) ‖ω − ω′‖
    a_omega = (omega_s - omega_s_pred) * resid_norm
    # §4.4.1: the norm of the residuals' local standard deviation
    resid_std = np.linalg.norm(trailing_std(resid, n_window).reshape(len(resid), -1), axis=1)
    return {"a_omega": a_omega, "omega_s": omega_s, "omega_s_pred": omega_s_pred,
            "resid_norm": resid_norm, "resid_std": resid_std}


def intensity_series(pred: pd.DataFrame, config: IntensityConfig) -> pd.DataFrame:
    """Per sample of a `nets.predict` frame: t_s, a_omega, omega_s, omega_s_pred,
    resid_norm, resid_std, valid (the net's history and the std window both filled)."""
    axes, sfx = residual_axes(pred)
    t = np.asarray(pred["t_s"], float)
    if t.size < 3:
        raise ValueError(f"{t.size} predicted samples: too few for an intensity")
    rate_hz = 1.0 / float(np.median(np.diff(t)))
    resid = np.column_stack([np.asarray(pred[f"{a}_resid{sfx}"], float) for a in axes])
    predicted = np.column_stack([np.asarray(pred[f"{a}_pred{sfx}"], float) for a in axes])
    n = samples_in(config.std_window_s, rate_hz)
    out = {"t_s": t, **intensity_from_arrays(predicted + resid, predicted, n)}
    valid = np.asarray(pred.get("history_valid", np.ones(t.size)), bool)
    # the std window must hold valid rows only
    first = int(np.argmax(valid)) if valid.any() else t.size
    valid = valid & (np.arange(t.size) >= first + n - 1)
    out["valid"] = valid.astype(np.int8)
    return pd.DataFrame(out)


def find_intensity_peaks(t_s: np.ndarray, a_omega: np.ndarray, config: IntensityConfig,
                         valid: np.ndarray | None = None) -> pd.DataFrame:
    """Local maxima of A_ω at least `peak_separation_s` apart that stand at least
    `peak_factor` standard deviations of the whole (valid) series above A_ω's mean over a
    centred `peak_std_window_s` (§2.1.2: "at least 15 sec apart and at least 1.5 times
    higher than the standard deviation (of the whole waveform data) of the points in the
    neighborhood of the 10 sec window"). Returns t_s, a_omega, local_mean, ratio
    ((A_ω − local mean) / std)."""
    from scipy.signal import find_peaks

    from airwake.estimate.airwake_map import moving_average

    t = np.asarray(t_s, float)
    a = np.asarray(a_omega, float)
    ok = np.isfinite(a) if valid is None else np.isfinite(a) & np.asarray(valid, bool)
    cols = ["t_s", "a_omega", "local_mean", "ratio"]
    if ok.sum() < 3:
        return pd.DataFrame(columns=cols)
    floor = float(np.min(a[ok]))  # invalid rows sit at the minimum: never a peak
    x = np.where(ok, a, floor)
    sd = float(np.std(a[ok]))
    if sd == 0:
        return pd.DataFrame(columns=cols)
    local_mean = moving_average(t, x, config.peak_std_window_s)
    rate_hz = 1.0 / float(np.median(np.diff(t)))
    height = np.where(ok, local_mean + config.peak_factor * sd, np.inf)
    idx, _ = find_peaks(x, height=height,
                        distance=max(1, int(round(config.peak_separation_s * rate_hz))))
    return pd.DataFrame({"t_s": t[idx], "a_omega": a[idx], "local_mean": local_mean[idx],
                         "ratio": (a[idx] - local_mean[idx]) / sd}, columns=cols)
