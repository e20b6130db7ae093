"""Scores of a pilot-compensation net: RMS and MAE per axis, in deg/s for body rates
(Table 2.2's unit) and rad/s^2 for angular accelerations (§4.3's unit), against the
measured target and against its low-passed version (sample-to-sample gyro noise no
network can predict), next to the ARX baseline and, for rates, persistence (the
previous rate repeated: what the recurrent input alone gives).
"""

from __future__ import annotations

import numpy as np

from airwake.nets.features import gaussian_smooth
from airwake.nets.split import TEST, TRAIN, VAL

# centred Gaussian (eq 2.3) for the low-passed target: sigma 0.05 s puts the -3 dB point
# near 3.7 Hz, above the pilot's inputs (chirps to 4 Hz) and below the rotor's 1/rev
SCORE_LOWPASS = {"sigma_s": 0.05, "length_s": 0.15}
AXES = {"rates": ("p", "q", "r"), "accel": ("pdot", "qdot")}
UNITS = {"rates": "deg/s", "accel": "rad/s^2"}
_SCALE = {"rates": 180.0 / np.pi, "accel": 1.0}


def smoothed_target(y: np.ndarray, rate_hz: float) -> np.ndarray:
    return gaussian_smooth(y, rate_hz, SCORE_LOWPASS["sigma_s"], SCORE_LOWPASS["length_s"])


def per_axis(target: str, truth: np.ndarray, pred: np.ndarray) -> dict:
    """{axis: {"rms": .., "mae": ..}} in the target's report unit; empty input: {}."""
    if len(truth) == 0:
        return {}
    err = (np.asarray(pred) - np.asarray(truth)) * _SCALE[target]
    return {a: {"rms": float(np.sqrt(np.mean(err[:, k] ** 2))),
                "mae": float(np.mean(np.abs(err[:, k])))}
            for k, a in enumerate(AXES[target])}


def score_rows(target: str, y, y_lp, pred, arx, prev, rows, truth=None) -> dict:
    """Every model's per-axis scores on `rows` (bool mask) against y, y_lp and, where
    given (simulated flights scoring themselves), the noise-free truth."""
    models = {"net": pred, "arx": arx}
    if prev is not None:
        models["persistence"] = prev
    out = {"rows": int(rows.sum())}
    refs = [("measured", y), ("lowpass", y_lp)] + ([("truth", truth)] if truth is not None else [])
    for ref_name, ref in refs:
        out[ref_name] = {m: per_axis(target, ref[rows], p[rows]) for m, p in models.items()}
    return out


def score_sets(target: str, y, y_lp, pred, arx, prev, labels) -> dict:
    """Scores on the train, validation and test rows of a time-block split."""
    out = {"unit": UNITS[target], "lowpass": dict(SCORE_LOWPASS)}
    for name, lab in (("train", TRAIN), ("val", VAL), ("test", TEST)):
        out[name] = score_rows(target, y, y_lp, pred, arx, prev, labels == lab)
    return out
