"""The airwake-intensity map: A_ω and the residual std over the helicopter's position in
the ship frame (reference §2.1.5, §2.2.3, Fig. 2.9 / 2.18), calibrated to m/s (§4.4.1)
and, for simulated flights, scored against the simulator's turbulence.

    amap = build_intensity_map(net, flight_table, IntensityConfig())
    fit = calibrate(amap, truth)            # RANSAC on cells (nets.calibration)
    write_intensity_map(amap, "OUTDIR")     # map.parquet, intensity.png, …

Positions are those of `airwake wind map` (`estimate.airwake_map.map_frame`): the rotor
hub in the ship frame (`hub_ship_x/y/z_m`: the RTK baseline rotated by the ship's
attitude plus the base antenna's place; x forward of the hangar step, y starboard, z down
from the deck), or the site's NED position without a ship. Rows with `hub_ship_valid` 0
(a held position) and rows before the net's and the std window's history are left out.
Cells are those of the wind map (`cell_index`): per cell the mean of A_ω, of the
residual std and (scoring) of the truth turbulence at the samples' positions.

Truth turbulence (simulated flights only): the norm of the simulator's local turbulence
std vector at the hub, ‖σ‖ = √3 σ for its isotropic σ (`sigma_m_s` of the wind field,
through `airwake.estimate.truth`), the reference's "norm of the standard deviation of
the wind velocity vector" (§4.5.1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from airwake.estimate.airwake_map import (
    SHIP_POSITION,
    SITE_POSITION,
    cell_index,
    map_frame,
)
from airwake.nets.calibration import LineFit, ransac_line
from airwake.nets.intensity import IntensityConfig, intensity_series, residual_axes

CELL_M = 1.0
LAYER_M = 2.0
MIN_SECONDS = 1.0
SCORE_MIN_SECONDS = 2.0


@dataclass
class IntensityMap:
    """samples (per row: t_s, x_m, y_m, z_m, a_omega, resid_std, …), cells (one row per
    cell), peaks, frame ("ship" / "site"), settings, resid_unit."""

    samples: pd.DataFrame
    cells: pd.DataFrame
    peaks: pd.DataFrame
    frame: str
    settings: dict
    resid_unit: str


def placed_samples(pred: pd.DataFrame, flight_df: pd.DataFrame, config: IntensityConfig):
    """The intensity series at the flight's positions; (samples, frame, whole series)."""
    from airwake.estimate.errors import WindEstimationError

    frame = map_frame(flight_df)
    cols = SHIP_POSITION if frame == "ship" else SITE_POSITION
    series = intensity_series(pred, config)
    tf = np.asarray(flight_df["t_s"], float)
    t = series["t_s"].to_numpy()
    keep = series["valid"].to_numpy().astype(bool)
    if frame == "ship" and "hub_ship_valid" in flight_df.columns:
        keep &= np.interp(t, tf, np.asarray(flight_df["hub_ship_valid"], float)) > 0.999
    if not keep.any():
        raise WindEstimationError("no sample with both a valid intensity and a position")
    out = series[keep].reset_index(drop=True)
    for name, col in zip(("x_m", "y_m", "z_m"), cols, strict=True):
        out[name] = np.interp(out["t_s"].to_numpy(), tf, np.asarray(flight_df[col], float))
    return out, frame, series


def grid_intensity(samples: pd.DataFrame, cell_m: float = CELL_M, layer_m: float = LAYER_M,
                   min_seconds: float = MIN_SECONDS) -> pd.DataFrame:
    """One row per cell with >= min_seconds: ix, iy, iz, x_m, y_m, z_m (centre), samples,
    seconds, a_omega, a_omega_std, resid_std, and truth_turbulence_m_s when the samples
    carry it."""
    pos = samples[["x_m", "y_m", "z_m"]].to_numpy()
    idx = cell_index(pos, cell_m, layer_m)
    t = samples["t_s"].to_numpy()
    dt = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    df = pd.DataFrame({"ix": idx[:, 0], "iy": idx[:, 1], "iz": idx[:, 2]})
    value_cols = [c for c in ("a_omega", "resid_std", "truth_turbulence_m_s")
                  if c in samples.columns]
    for c in value_cols:
        df[c] = samples[c].to_numpy()
    g = df.groupby(["ix", "iy", "iz"], sort=True)
    cells = g[value_cols].mean()
    cells["a_omega_std"] = g["a_omega"].std(ddof=0)
    cells["samples"] = g.size()
    cells = cells.reset_index()
    cells["seconds"] = cells["samples"] * dt
    cells = cells[cells["seconds"] >= min_seconds - 1e-9].reset_index(drop=True)
    size = np.array([cell_m, cell_m, layer_m])
    centre = (cells[["ix", "iy", "iz"]].to_numpy() + 0.5) * size
    cells.insert(3, "x_m", centre[:, 0])
    cells.insert(4, "y_m", centre[:, 1])
    cells.insert(5, "z_m", centre[:, 2])
    return cells


def truth_turbulence(samples: pd.DataFrame, frame: str, flight_metadata: dict) -> np.ndarray:
    """(n,) ‖σ‖ (m/s) of the simulator's turbulence at the samples' positions (module doc)."""
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.truth import truth_field

    tf = truth_field(flight_metadata)
    field = tf.field
    if not (hasattr(field, "sigma_m_s") and hasattr(field, "wake_coordinates")):
        raise WindEstimationError(
            f"--score: the flight's wind field ({type(field).__name__}) has no local "
            "turbulence intensity to score against (a ship_airwake scenario has)")
    t = samples["t_s"].to_numpy()
    pos = samples[["x_m", "y_m", "z_m"]].to_numpy()
    ned = tf.ship.ship_to_ned(t, pos) if frame == "ship" else pos
    s, n, h = field.wake_coordinates(t, ned).T
    sigma = np.asarray(field.sigma_m_s(s, h, n), float)
    return np.sqrt(3.0) * sigma if sigma.ndim == 1 else np.linalg.norm(sigma, axis=-1)


def build_intensity_map(pred: pd.DataFrame, flight_df: pd.DataFrame, config: IntensityConfig,
                        cell_m: float = CELL_M, layer_m: float = LAYER_M,
                        min_seconds: float = MIN_SECONDS,
                        flight_metadata: dict | None = None) -> IntensityMap:
    """Samples, cells and peaks of one flight; with `flight_metadata` of a simulated
    flight the samples and cells carry truth_turbulence_m_s."""
    from airwake.nets.intensity import find_intensity_peaks

    samples, frame, series = placed_samples(pred, flight_df, config)
    if flight_metadata is not None:
        samples["truth_turbulence_m_s"] = truth_turbulence(samples, frame, flight_metadata)
    cells = grid_intensity(samples, cell_m, layer_m, min_seconds)
    peaks = find_intensity_peaks(series["t_s"].to_numpy(), series["a_omega"].to_numpy(),
                                 config, series["valid"].to_numpy())
    if len(peaks):
        tf = np.asarray(flight_df["t_s"], float)
        cols = SHIP_POSITION if frame == "ship" else SITE_POSITION
        for name, col in zip(("x_m", "y_m", "z_m"), cols, strict=True):
            peaks[name] = np.interp(peaks["t_s"].to_numpy(), tf,
                                    np.asarray(flight_df[col], float))
    _, unit = residual_axes(pred)
    settings = {"frame": frame, "cell_m": cell_m, "layer_m": layer_m,
                "min_seconds": min_seconds, **config.to_dict()}
    return IntensityMap(samples, cells, peaks, frame, settings, unit.strip("_"))


def calibrate_cells(cells: pd.DataFrame, rng: np.random.Generator,
                    min_seconds: float = SCORE_MIN_SECONDS) -> LineFit:
    """RANSAC line truth_turbulence_m_s ≈ slope · resid_std + offset over cells with
    >= min_seconds (§4.4.1)."""
    good = cells["seconds"].to_numpy() >= min_seconds - 1e-9
    return ransac_line(cells["resid_std"].to_numpy()[good],
                       cells["truth_turbulence_m_s"].to_numpy()[good], rng)


def _pearson(a: np.ndarray, b: np.ndarray) -> float:
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < 3 or np.std(a[ok]) == 0 or np.std(b[ok]) == 0:
        return float("nan")
    return float(np.corrcoef(a[ok], b[ok])[0, 1])


def _spearman(a: np.ndarray, b: np.ndarray) -> float:
    ok = np.isfinite(a) & np.isfinite(b)
    ra = pd.Series(a[ok]).rank().to_numpy()
    rb = pd.Series(b[ok]).rank().to_numpy()
    return _pearson(ra, rb)


def score_intensity(cells: pd.DataFrame, fit: LineFit | None = None,
                    min_seconds: float = SCORE_MIN_SECONDS) -> dict:
    """Correlation over cells (>= min_seconds) of A_ω and of the residual std with the
    truth turbulence (Pearson and Spearman); with a calibration, the calibrated map's
    error in m/s."""
    good = cells["seconds"].to_numpy() >= min_seconds - 1e-9
    truth = cells["truth_turbulence_m_s"].to_numpy()[good]
    out = {"cells": int(good.sum()), "min_seconds": min_seconds}
    for name in ("a_omega", "resid_std"):
        v = cells[name].to_numpy()[good]
        out[f"{name}_pearson"] = _pearson(v, truth)
        out[f"{name}_spearman"] = _spearman(v, truth)
    out["truth_turbulence_m_s_range"] = [float(np.min(truth)), float(np.max(truth))] \
        if truth.size else []
    if fit is not None:
        err = fit(cells["resid_std"].to_numpy()[good]) - truth
        out["turbulence_rms_error_m_s"] = float(np.sqrt(np.mean(err**2)))
        out["turbulence_mean_error_m_s"] = float(np.mean(err))
    return out


def write_intensity_map(amap: IntensityMap, out_dir, metadata: dict, title: str = "") -> dict:
    """map.parquet (cells + metadata), peaks.csv, intensity.png, residual_std.png (and
    turbulence.png when the cells carry turbulence_m_s, truth_turbulence.png with the
    truth); returns {name: path}."""
    from pathlib import Path

    from airwake.estimate.airwake_map import write_map
    from airwake.estimate.map_plots import ShipOutline, plot_cell_values

    out = Path(out_dir)
    paths = {"map": write_map(amap.cells, out, metadata)}
    paths["peaks"] = out / "peaks.csv"
    amap.peaks.to_csv(paths["peaks"], index=False)
    ship = ShipOutline() if amap.frame == "ship" else None
    cell_m = amap.settings["cell_m"]
    unit = amap.resid_unit.replace("_", "/").replace("rad/s2", "rad/s²")
    plots = [("intensity", "a_omega", "coolwarm", "A_ω (eq 2.4)", True),
             ("residual_std", "resid_std", "viridis", f"residual std ({unit})", False)]
    if "turbulence_m_s" in amap.cells.columns:
        plots.append(("turbulence", "turbulence_m_s", "viridis",
                      "calibrated turbulence (m/s)", False))
    if "truth_turbulence_m_s" in amap.cells.columns:
        plots.append(("truth_turbulence", "truth_turbulence_m_s", "viridis",
                      "simulator's turbulence ‖σ‖ (m/s)", False))
    for name, col, cmap, label, symmetric in plots:
        paths[name] = plot_cell_values(amap.cells, amap.cells[col], out / f"{name}.png",
                                       cell_m, amap.frame, ship, label,
                                       f"{title}{label}", cmap, symmetric)
    return paths
