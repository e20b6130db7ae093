"""The air velocities a wind net was trained over, and how much of a flight lies inside.

    env = air_envelope(air_velocity_body_m_s, rate_hz)      # at training: into the card
    share = inside_share(env, air_velocity_body_m_s)        # at estimate time: 0 ... 1

A net reads the air velocity off the helicopter's response; where a flight's air velocity
lies outside every state its training flights held it extrapolates (a still-air net from
cruise legs with the nose at +-15 deg reads a ship's 15 deg wind-over-deck with its
lateral part ~0.1 m/s short: docs/networks.md). The envelope is joint, not per axis: 3 m/s
forward and 1.5 m/s sideways together is a state of its own even when each alone was
flown. Air velocity (body axes: the body's velocity through the air, INS velocity less
the wind — the opposite sign of `airwake.calibrate.envelope`'s "air velocity", the air's
velocity seen from the body) in cells of `CELL_M_S`; a cell is flown when the training
flights held it for at least `MIN_S` seconds; a sample is inside when its cell or a
neighbouring one (the 27 around it) is flown.
"""

from __future__ import annotations

import numpy as np

CELL_M_S = 0.25
MIN_S = 0.2
_OFFSETS = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)])
_SPAN = 1 << 20  # cell indices are packed into one integer per cell (|index| < 2^19)


def _cells(air: np.ndarray, cell: float) -> np.ndarray:
    a = np.asarray(air, dtype=float)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"air velocity must be (n, 3), got {a.shape}")
    return np.floor(a[np.all(np.isfinite(a), axis=1)] / cell).astype(np.int64)


def _pack(idx: np.ndarray) -> np.ndarray:
    half = _SPAN // 2
    idx = np.clip(idx, -half + 1, half - 2) + half
    return (idx[:, 0] * _SPAN + idx[:, 1]) * _SPAN + idx[:, 2]


def air_envelope(air_velocity_body_m_s, rate_hz: float, cell_m_s: float = CELL_M_S,
                 min_s: float = MIN_S) -> dict:
    """The flown cells of the training rows' air velocity (n, 3) sampled at `rate_hz`:
    {"cell_m_s", "min_s", "cells": [[i, j, k], ...]} (JSON for the net's card)."""
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise ValueError(f"rate {rate_hz!r} Hz: must be a number > 0")
    idx = _cells(air_velocity_body_m_s, cell_m_s)
    cells, counts = np.unique(idx, axis=0, return_counts=True)
    flown = cells[counts >= min_s * rate_hz]
    return {"cell_m_s": float(cell_m_s), "min_s": float(min_s),
            "cells": flown.astype(int).tolist()}


def inside_share(env: dict, air_velocity_body_m_s) -> float:
    """The share of the finite rows of `air_velocity_body_m_s` (n, 3) inside `env`
    (module doc); NaN when there is none."""
    idx = _cells(air_velocity_body_m_s, float(env["cell_m_s"]))
    if idx.shape[0] == 0:
        return float("nan")
    flown = np.asarray(env["cells"], dtype=np.int64).reshape(-1, 3)
    if flown.shape[0] == 0:
        return 0.0
    near = _pack((flown[:, None, :] + _OFFSETS[None]).reshape(-1, 3))
    return float(np.mean(np.isin(_pack(idx), near)))
