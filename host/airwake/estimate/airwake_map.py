"""The airwake map: the helicopter's wind estimates gridded in the ship's frame
(reference §2.1.5, §4.5).

    samples = map_samples(wind_df, flight)            # per estimate: position, flow, std
    cells = grid_samples(samples, cell_m=0.5)         # one row per occupied cell
    write_map(cells, "MAPDIR", metadata)              # map.parquet (map_report: the rest)

Frames. On a ship the position is the rotor hub in the ship frame from the flight table's
`hub_ship_x/y/z_m` (RTK baseline rotated by the ship's attitude plus the base antenna's
place on the ship: x forward of the hangar step, y starboard, z down from the deck), and
the flow is the air velocity *relative to the ship*:

    u = R_z(psi_ship)^T (R(roll, pitch, yaw) v_body - v_ship)

with v_body the estimate's mean flow (eq 5.3, body axes, over the ground), R the INS
attitude, psi_ship the ship's heading and v_ship its translational velocity over the
ground: the base INS velocity averaged over `SHIP_VELOCITY_WINDOW_S` (the deck's
roll/pitch/yaw oscillations move the INS point by a few tenths of m/s and average out;
the wake moves with the ship's translation). Rotations are turned the same way
(R_z^T R w_body). Without a ship (a hall, a field) the frame is the site's NED frame and
the position the INS's (`pos_n/e/d_m`): indoors without the tracker that position drifts
by the INS's own error.

Samples where the flight's `hub_ship_valid` is 0 (an RTK or base-INS gap: the position
is held there, not measured) are left out.

Cells: squares of `cell_m` in x, y and layers of `layer_m` in z. Per cell, from the n
samples (times t, mean m_i, posterior std s_i per component) in it:

    mean flow     U = mean_i m_i
    its std       sqrt(ins^2 + mean_i(s_i^2 - ins^2) * min(1, tau_e / T))
                  (estimate errors are correlated over ~tau_e = `ERROR_CORRELATION_S`;
                  the INS velocity error `ins` over seconds: it does not average out)
    turbulence    sigma^2 = var_i(m_i) + mean_i(s_i^2 - ins^2)     (total variance: the
                  smoothed means' spread plus what the posterior says they miss)
    intensity     TI = sqrt(mean over x, y, z of sigma^2) / U_ref, U_ref the mean
                  relative wind speed over the flight (or given), with the std of a
                  variance estimate from N_eff = T / tau_e independent samples:
                  std(TI) = TI / sqrt(2 N_eff)

T = n dt the time spent in the cell. Cells with less than `min_seconds` are dropped.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from airwake.estimate.errors import WindEstimationError
from airwake.heli.model import WIND_NAMES

SHIP_VELOCITY_WINDOW_S = 20.0
ERROR_CORRELATION_S = 1.0
CELL_M = 0.5
LAYER_M = 1.0
MIN_SECONDS = 0.5
SCORE_MIN_SECONDS = 2.0
FLOW_NAMES = ("u_m_s", "v_m_s", "w_m_s")
ROT_NAMES = ("wx_rad_s", "wy_rad_s", "wz_rad_s")
SHIP_POSITION = ("hub_ship_x_m", "hub_ship_y_m", "hub_ship_z_m")
SITE_POSITION = ("pos_n_m", "pos_e_m", "pos_d_m")
ATTITUDE = ("roll_rad", "pitch_rad", "yaw_rad")
SHIP_MOTION = ("ship_yaw_rad", "ship_vel_n_m_s", "ship_vel_e_m_s", "ship_vel_d_m_s")
# every flight column the map reads (checked when the flight is loaded)
FLIGHT_COLUMNS = (*ATTITUDE, *SHIP_POSITION, *SITE_POSITION, *SHIP_MOTION, "hub_ship_valid")


@dataclass
class MapSamples:
    """Per wind-table sample (n): t (n,), pos (n, 3) in the map frame, flow (n, 3)
    relative flow, flow_std (n, 3), rot (n, 3) rotation, rot_std (n, 3); frame "ship" or
    "site"; ins_std (m/s) inside flow_std; dt (s) per sample; u_ref (m/s); flow_steady and
    rot_steady (n, 3): the std the wind table's intervals carry for the model's still-air
    error (its metadata's `still_air_wind_error`, turned the same way), taken out of
    flow_std and rot_std: a model error, neither turbulence nor fast error."""

    t: np.ndarray
    pos: np.ndarray
    flow: np.ndarray
    flow_std: np.ndarray
    rot: np.ndarray
    rot_std: np.ndarray
    frame: str
    ins_std: float
    dt: float
    u_ref: float
    flow_steady: np.ndarray = None
    rot_steady: np.ndarray = None

    def __post_init__(self) -> None:
        if self.flow_steady is None:
            self.flow_steady = np.zeros_like(self.flow_std)
        if self.rot_steady is None:
            self.rot_steady = np.zeros_like(self.rot_std)


def _rz(psi: np.ndarray) -> np.ndarray:
    c, s = np.cos(psi), np.sin(psi)
    r = np.zeros(psi.shape + (3, 3))
    r[..., 0, 0] = c
    r[..., 0, 1] = -s
    r[..., 1, 0] = s
    r[..., 1, 1] = c
    r[..., 2, 2] = 1.0
    return r


def body_to_ned(roll, pitch, yaw) -> np.ndarray:
    """(n, 3, 3) rotation body -> NED (yaw-pitch-roll)."""
    from airwake.record.flight_builder import euler_to_dcm

    return euler_to_dcm(np.asarray(roll, float), np.asarray(pitch, float),
                        np.asarray(yaw, float))


def moving_average(t: np.ndarray, x: np.ndarray, window_s: float) -> np.ndarray:
    """Centred moving average over `window_s` (by time; edges: the window shrinks)."""
    x = np.asarray(x, float)
    c = np.concatenate([[0.0], np.cumsum(x)])
    lo = np.searchsorted(t, t - 0.5 * window_s, side="left")
    hi = np.searchsorted(t, t + 0.5 * window_s, side="right")
    return (c[hi] - c[lo]) / np.maximum(hi - lo, 1)


def check_same_flight(wind_meta: dict, flight_df, wind_name: str, flight_name: str) -> None:
    """WindEstimationError when the wind table was estimated from another flight."""
    from airwake.record.flight_table import flight_fingerprint

    fp = wind_meta.get("flight_fingerprint")
    if not fp:
        return
    here = flight_fingerprint(flight_df)
    if fp != here:
        raise WindEstimationError(
            f"{wind_name} was estimated from another flight ({fp['rows']} rows, "
            f"t = {fp['t0_s']} ... {fp['t1_s']} s; {wind_meta.get('flight') or '?'}), not "
            f"{flight_name} ({here['rows']} rows, t = {here['t0_s']} ... {here['t1_s']} s)")


def map_frame(flight_df) -> str:
    cols = set(flight_df.columns)
    if set(SHIP_POSITION) <= cols:
        return "ship"
    if {"ship_yaw_rad", "rel_pos_n_m"} <= cols:
        raise WindEstimationError(
            "the flight has the ship's attitude and the RTK baseline but not the hub in the "
            "ship frame (hub_ship_x/y/z_m): export it again with --base-antenna-ship-m X,Y "
            "(the base antenna's place on the ship)")
    if "ship_yaw_rad" in cols:
        raise WindEstimationError(
            "the flight has the ship's attitude but no RTK baseline (rel_pos_n/e/d_m): the "
            "helicopter cannot be placed relative to the ship")
    if set(SITE_POSITION) <= cols:
        return "site"
    raise WindEstimationError("the flight has no position columns (hub_ship_x/y/z_m or "
                              "pos_n/e/d_m): the wind cannot be placed on a map")


def map_samples(wind_df, flight_df, ins_std: float = 0.05,
                u_ref: float | None = None, excess=None) -> MapSamples:
    """The wind table's samples placed and turned into the map frame (module docstring).
    Flight columns are interpolated at the wind table's times. `excess`: the model's
    still-air error (6,) inside the table's std (its metadata's `still_air_wind_error`;
    None: none), kept apart as flow_steady / rot_steady."""
    frame = map_frame(flight_df)
    need = [*ATTITUDE, *(SHIP_POSITION if frame == "ship" else SITE_POSITION)]
    if frame == "ship":
        need += list(SHIP_MOTION)
    missing = [c for c in need if c not in flight_df.columns]
    if missing:
        raise WindEstimationError(f"the flight lacks column(s) {missing} for the map")
    missing = [c for c in ("t_s", *WIND_NAMES, *(f"{n}_std" for n in WIND_NAMES))
               if c not in wind_df.columns]
    if missing:
        raise WindEstimationError(f"the wind table lacks column(s) {missing}")
    tf = np.asarray(flight_df["t_s"], float)
    t = np.asarray(wind_df["t_s"], float)
    if t.size == 0:
        raise WindEstimationError("the wind table has no rows")
    inside = (t >= tf[0] - 1e-9) & (t <= tf[-1] + 1e-9)
    if not inside.all():
        raise WindEstimationError(
            f"the wind table spans t = {t[0]:.3f} ... {t[-1]:.3f} s, outside the flight's "
            f"{tf[0]:.3f} ... {tf[-1]:.3f} s: is it from another flight?")
    if frame == "ship" and "hub_ship_valid" in flight_df.columns:
        # positions held over RTK or base-INS gaps are not positions: those samples go
        valid = np.interp(t, tf, np.asarray(flight_df["hub_ship_valid"], float)) > 0.999
        if not valid.any():
            raise WindEstimationError("no sample of the flight has both the RTK baseline "
                                      "and the ship's INS (hub_ship_valid is 0 throughout)")
        wind_df = wind_df[valid].reset_index(drop=True)
        t = t[valid]

    def at(col, unwrap=False):
        v = np.asarray(flight_df[col], float)
        return np.interp(t, tf, np.unwrap(v) if unwrap else v)

    rot_b = body_to_ned(at("roll_rad"), at("pitch_rad"), at("yaw_rad", unwrap=True))
    v_body = np.column_stack([np.asarray(wind_df[n], float) for n in WIND_NAMES[:3]])
    w_body = np.column_stack([np.asarray(wind_df[n], float) for n in WIND_NAMES[3:]])
    s_v = np.column_stack([np.asarray(wind_df[f"{n}_std"], float) for n in WIND_NAMES[:3]])
    s_w = np.column_stack([np.asarray(wind_df[f"{n}_std"], float) for n in WIND_NAMES[3:]])
    v_ned = np.einsum("nij,nj->ni", rot_b, v_body)
    w_ned = np.einsum("nij,nj->ni", rot_b, w_body)
    if frame == "ship":
        pos = np.column_stack([at(c) for c in SHIP_POSITION])
        ship_v = np.column_stack([
            moving_average(tf, np.asarray(flight_df[c], float), SHIP_VELOCITY_WINDOW_S)
            for c in ("ship_vel_n_m_s", "ship_vel_e_m_s", "ship_vel_d_m_s")])
        ship_v = np.column_stack([np.interp(t, tf, ship_v[:, j]) for j in range(3)])
        heading = at("ship_yaw_rad", unwrap=True)
        r_to = np.swapaxes(_rz(heading), -1, -2)  # NED -> ship heading frame
        flow = np.einsum("nij,nj->ni", r_to, v_ned - ship_v)
        rot = np.einsum("nij,nj->ni", r_to, w_ned)
        full = np.einsum("nij,njk->nik", r_to, rot_b)
    else:
        pos = np.column_stack([at(c) for c in SITE_POSITION])
        flow, rot, full = v_ned, w_ned, rot_b
    # the model's still-air error in the std (`estimate.wind.still_air_wind_error`): kept
    # apart, it is no turbulence and does not average out over a cell (an anchored table's
    # gap rows carry the plain entry, of which the part above this one stays in the std)
    g = np.zeros(6) if excess is None else np.asarray(excess, float).reshape(6)
    s_v = np.sqrt(np.maximum(s_v**2 - g[:3] ** 2, 0.0))
    s_w = np.sqrt(np.maximum(s_w**2 - g[3:] ** 2, 0.0))
    # std of a rotated vector: Var_i = sum_j R_ij^2 Var_j (components taken independent)
    flow_std = np.sqrt(np.einsum("nij,nj->ni", full**2, s_v**2))
    rot_std = np.sqrt(np.einsum("nij,nj->ni", full**2, s_w**2))
    flow_steady = np.sqrt(np.einsum("nij,j->ni", full**2, g[:3] ** 2))
    rot_steady = np.sqrt(np.einsum("nij,j->ni", full**2, g[3:] ** 2))
    dt = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    if u_ref is None:
        u_ref = float(np.mean(np.linalg.norm(flow, axis=1))) if t.size else float("nan")
    if not (np.isfinite(u_ref) and u_ref > 0):
        raise WindEstimationError(f"reference speed {u_ref!r}: must be a positive number")
    return MapSamples(t, pos, flow, flow_std, rot, rot_std, frame, float(ins_std), dt,
                      float(u_ref), flow_steady, rot_steady)


def cell_index(pos: np.ndarray, cell_m: float, layer_m: float) -> np.ndarray:
    """(n, 3) integer cell indexes: floor(x / cell), floor(y / cell), floor(z / layer)."""
    size = np.array([cell_m, cell_m, layer_m])
    return np.floor(pos / size).astype(np.int64)


def grid_samples(s: MapSamples, cell_m: float = CELL_M, layer_m: float = LAYER_M,
                 min_seconds: float = MIN_SECONDS,
                 error_correlation_s: float = ERROR_CORRELATION_S):
    """One row per cell with at least `min_seconds` of samples (module docstring):
    x_m, y_m, z_m (centre), samples, seconds, u/v/w_m_s and their _std, wx/wy/wz_rad_s
    and their _std, sigma_u/v/w_m_s, ti, ti_std, speed_m_s, and the cell indexes."""
    import pandas as pd

    for name, v in (("--cell-m", cell_m), ("--layer-m", layer_m)):
        if not (np.isfinite(v) and v > 0):
            raise WindEstimationError(f"{name} {v!r}: must be a positive number")
    idx = cell_index(s.pos, cell_m, layer_m)
    keys, inverse, counts = np.unique(idx, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    rows = []
    ins2 = s.ins_std**2
    for c, key in enumerate(keys):
        sel = inverse == c
        n = int(counts[c])
        seconds = n * s.dt
        if seconds < min_seconds - 1e-9:
            continue
        frac = min(1.0, error_correlation_s / max(seconds, 1e-9))
        n_eff = max(seconds / error_correlation_s, 1.0)
        m = s.flow[sel]
        pv = np.maximum(s.flow_std[sel] ** 2 - ins2, 0.0)
        mean = m.mean(0)
        std_mean = np.sqrt(ins2 + (s.flow_steady[sel] ** 2).mean(0) + pv.mean(0) * frac)
        sig2 = m.var(0) + pv.mean(0)
        mr = s.rot[sel]
        pr = s.rot_std[sel] ** 2
        pr_steady = (s.rot_steady[sel] ** 2).mean(0)
        ti = math.sqrt(float(np.mean(sig2))) / s.u_ref
        centre = (key + 0.5) * np.array([cell_m, cell_m, layer_m])
        row = {"ix": int(key[0]), "iy": int(key[1]), "iz": int(key[2]),
               "x_m": centre[0], "y_m": centre[1], "z_m": centre[2], "samples": n,
               "seconds": seconds}
        for j, name in enumerate(FLOW_NAMES):
            row[name] = float(mean[j])
            row[f"{name[:-4]}_std_m_s"] = float(std_mean[j])
        for j, name in enumerate(ROT_NAMES):
            row[name] = float(mr[:, j].mean())
            row[f"{name[:-6]}_std_rad_s"] = float(math.sqrt(pr[:, j].mean() * frac
                                                            + pr_steady[j]))
        for j, name in enumerate(("sigma_u_m_s", "sigma_v_m_s", "sigma_w_m_s")):
            row[name] = float(math.sqrt(sig2[j]))
        row["ti"] = ti
        row["ti_std"] = ti / math.sqrt(2.0 * n_eff)
        row["speed_m_s"] = float(np.linalg.norm(mean))
        rows.append(row)
    cols = ["ix", "iy", "iz", "x_m", "y_m", "z_m", "samples", "seconds", *FLOW_NAMES,
            "u_std_m_s", "v_std_m_s", "w_std_m_s", *ROT_NAMES, "wx_std_rad_s",
            "wy_std_rad_s", "wz_std_rad_s", "sigma_u_m_s", "sigma_v_m_s", "sigma_w_m_s",
            "ti", "ti_std", "speed_m_s"]
    return pd.DataFrame(rows, columns=cols)


def cell_means(values: np.ndarray, s: MapSamples, cells, cell_m: float,
               layer_m: float) -> np.ndarray:
    """(n_cells, k) mean of per-sample `values` (n, k) over each cell of `cells`."""
    idx = cell_index(s.pos, cell_m, layer_m)
    out = np.full((len(cells), values.shape[1]), np.nan)
    for c, (ix, iy, iz) in enumerate(zip(cells["ix"], cells["iy"], cells["iz"],
                                         strict=True)):
        sel = (idx[:, 0] == ix) & (idx[:, 1] == iy) & (idx[:, 2] == iz)
        if sel.any():
            out[c] = values[sel].mean(0)
    return out


def write_map(cells, out_dir, metadata: dict) -> Path:
    """map.parquet (cells + metadata) and summary.json into `out_dir`, via temporary
    files renamed into place."""
    import os
    import tempfile

    from airwake.record.flight_table import write_flight_table

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".map-", suffix=".parquet", dir=out)
    os.close(fd)
    try:
        write_flight_table(cells, tmp, metadata)
        os.replace(tmp, out / "map.parquet")
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return out / "map.parquet"


def write_json(obj, path: Path) -> None:
    import os
    import tempfile

    fd, tmp = tempfile.mkstemp(prefix=".", suffix=".json", dir=path.parent)
    with os.fdopen(fd, "w") as fh:
        json.dump(obj, fh, indent=2)
    os.replace(tmp, path)


@dataclass
class AirwakeMap:
    """cells (DataFrame, one row per cell), samples (MapSamples), settings, score (or
    None)."""

    cells: object
    samples: MapSamples
    settings: dict
    score: dict | None = None


def build_map(wind_df, flight_df, *, wind_meta: dict | None = None, cell_m: float = CELL_M,
              layer_m: float = LAYER_M, min_seconds: float = MIN_SECONDS,
              u_ref: float | None = None, ins_std: float | None = None) -> AirwakeMap:
    """Samples -> cells (module docstring). `wind_meta`: the wind table's metadata (its
    INS velocity std and flight fingerprint are used when present)."""
    wind_meta = wind_meta or {}
    if ins_std is None:
        ins_std = float(wind_meta.get("ins_velocity_std_m_s", 0.05))
    s = map_samples(wind_df, flight_df, ins_std, u_ref,
                    excess=wind_meta.get("still_air_wind_error"))
    cells = grid_samples(s, cell_m, layer_m, min_seconds)
    if len(cells) == 0:
        raise WindEstimationError(
            f"no cell of {cell_m:g} m holds {min_seconds:g} s of data: use a larger "
            "--cell-m or a smaller --min-seconds")
    settings = {"frame": s.frame, "cell_m": cell_m, "layer_m": layer_m,
                "min_seconds": min_seconds, "reference_speed_m_s": s.u_ref,
                "ins_velocity_std_m_s": s.ins_std,
                "error_correlation_s": ERROR_CORRELATION_S,
                "ship_velocity_window_s": SHIP_VELOCITY_WINDOW_S}
    return AirwakeMap(cells, s, settings)


def score_map(amap: AirwakeMap, flight_df, flight_meta: dict,
              min_seconds: float = SCORE_MIN_SECONDS) -> dict:
    """The map against the truth, over cells with >= min_seconds of data:
    "along_track": the flight's truth_wind_* turned and gridded like the estimates (the
    estimator's error, cell by cell); "field": the simulator's wind field at each cell's
    centre at the times the helicopter was in the cell (the map's error as a map of the
    airwake: estimation error plus the spread of the flow within the cell). RMS, mean and
    max |error| per component."""
    from airwake.estimate.truth import truth_field
    from airwake.record.flight_table import TRUTH_WIND

    s = amap.samples
    cells = amap.cells
    st = amap.settings
    good = cells["seconds"].to_numpy() >= min_seconds - 1e-9
    est = cells[[*FLOW_NAMES, *ROT_NAMES]].to_numpy()
    out = {"min_seconds": min_seconds, "cells": int(good.sum()), "cells_total": len(cells)}
    missing = [c for c in TRUTH_WIND if c not in flight_df.columns]
    if missing:
        raise WindEstimationError(f"--score needs the flight's truth columns; missing {missing}")
    import pandas as pd

    tf = np.asarray(flight_df["t_s"], float)
    truth_df = pd.DataFrame({"t_s": s.t})
    for name, col in zip(WIND_NAMES, TRUTH_WIND, strict=True):
        truth_df[name] = np.interp(s.t, tf, np.asarray(flight_df[col], float))
        truth_df[f"{name}_std"] = 0.0
    ts = map_samples(truth_df, flight_df, 0.0, s.u_ref)
    along = cell_means(np.column_stack([ts.flow, ts.rot]), s, cells, st["cell_m"],
                       st["layer_m"])
    out["along_track"] = _errors(est[good], along[good])
    field = truth_field(flight_meta)
    idx = cell_index(s.pos, st["cell_m"], st["layer_m"])
    size = np.array([st["cell_m"], st["cell_m"], st["layer_m"]])
    centres = (idx + 0.5) * size
    euler_cols = [f"truth_{c}" if f"truth_{c}" in flight_df.columns else c for c in ATTITUDE]
    euler = np.column_stack([np.interp(s.t, tf, np.unwrap(np.asarray(flight_df[c], float))
                                       if c.endswith("yaw_rad") else
                                       np.asarray(flight_df[c], float)) for c in euler_cols])
    in_good = np.zeros(s.t.size, bool)
    key = {(int(a), int(b), int(c)) for a, b, c in cells[good][["ix", "iy", "iz"]].to_numpy()}
    for i, k in enumerate(map(tuple, idx)):
        in_good[i] = k in key
    flow = np.full((s.t.size, 6), np.nan)
    if in_good.any():
        flow[in_good] = field.relative_flow(s.t[in_good], centres[in_good], euler[in_good],
                                            s.frame)
    at_cells = cell_means(flow, s, cells, st["cell_m"], st["layer_m"])
    out["field"] = _errors(est[good], at_cells[good])
    out["truth_cells"] = {"along_track": along.tolist(), "field": at_cells.tolist()}
    return out


def _errors(est: np.ndarray, truth: np.ndarray) -> dict:
    names = [*FLOW_NAMES, *ROT_NAMES]
    out = {}
    for j, n in enumerate(names):
        e = est[:, j] - truth[:, j]
        e = e[np.isfinite(e)]
        out[n] = {"rms": float(np.sqrt(np.mean(e * e))) if e.size else float("nan"),
                  "mean": float(np.mean(e)) if e.size else float("nan"),
                  "max_abs": float(np.max(np.abs(e))) if e.size else float("nan")}
    return out
