"""`airwake windmap` end to end: a table with anemometer and pose -> MAPDIR, all or nothing.

    summary = make_windmap(table, "MAPDIR", score=True)

MAPDIR holds grid.parquet (the 5 cm grid, `airwake.windmap.grid`, with the settings as
metadata), locations.parquet (the locations and their eq 3.15 / eq 5.3 fits), the PNG
slices (`plots`) and summary.json (settings, model error, score). It is written to a
temporary sibling directory that replaces MAPDIR only once complete (the airwake map's
`publish_dir`): a failure leaves the previous MAPDIR, or none.

Score (`score=True`, simulated tables): the map against the simulator's time-averaged
field (`airwake.estimate.truth`), at the grid points whose 5 cm voxel holds a sample
("where sampled") and at the locations: per-component RMS / mean / max |error| and the
RMS of the error vector's length, for the measured map and both models. Target: the
measured map within 0.2 m/s RMS of the field where sampled (`map_within_target`: the
error vector's RMS length, stricter than each component's RMS).
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np

from airwake.windmap.compensate import compensate
from airwake.windmap.errors import WindMapError
from airwake.windmap.grid import FLOW, build_windmap

SCORE_TARGET_M_S = 0.2


def _errors(est: np.ndarray, truth: np.ndarray) -> dict:
    e = est - truth
    out = {}
    for j, n in enumerate(FLOW):
        out[n] = {"rms": float(np.sqrt(np.mean(e[:, j] ** 2))),
                  "mean": float(np.mean(e[:, j])), "max_abs": float(np.max(np.abs(e[:, j])))}
    out["vector_rms_m_s"] = float(np.sqrt(np.mean(np.sum(e * e, axis=1))))
    return out


def score_windmap(wmap, metadata: dict) -> dict:
    """The map against the simulator's mean field (module docstring)."""
    from airwake.errors import AirwakeError
    from airwake.estimate.truth import truth_field

    try:
        field = truth_field(metadata)
        g = wmap.grid[wmap.grid["sampled"]]
        truth_g = field.mean_flow_ned(g[["x_m", "y_m", "z_m"]].to_numpy())
        loc = wmap.locations
        truth_l = field.mean_flow_ned(loc[["x_m", "y_m", "z_m"]].to_numpy())
    except AirwakeError as exc:
        raise WindMapError(str(exc)) from None
    except ValueError as exc:
        raise WindMapError(f"--score: {exc}") from None
    out = {"target_rms_m_s": SCORE_TARGET_M_S, "sampled_points": len(g),
           "locations": len(loc), "truth": "time-averaged field (no turbulence)"}
    for key, pre in (("map", ""), ("eq_3_15", "m12_"), ("eq_5_3", "m6_")):
        names = [f"{pre}{n}" for n in FLOW]
        out[key] = {"where_sampled": _errors(g[names].to_numpy(float), truth_g),
                    "at_locations": _errors(loc[names].to_numpy(float), truth_l)}
    # the stricter reading of "within 0.2 m/s RMS": the error vector's length, not each
    # component
    out["map_within_target"] = bool(out["map"]["where_sampled"]["vector_rms_m_s"]
                                    <= SCORE_TARGET_M_S)
    return out


def headline(wmap) -> str:
    g, me = wmap.grid, wmap.model_error["eq_3_15"]
    text = (f"anemometer wind map ({wmap.settings['pose']} pose): {len(wmap.locations)} "
            f"locations, {len(g)} grid points of {wmap.settings['grid_m']:g} m "
            f"({int(g['sampled'].sum())} sampled); speed {g['speed_m_s'].min():.2f} ... "
            f"{g['speed_m_s'].max():.2f} m/s; eq 3.15 model error median "
            f"{me['median_pct']:.1f} % of {wmap.settings['source_speed_m_s']:g} m/s "
            f"({100 * me['fraction_3_to_11_pct']:.0f} % of points in 3-11 %, "
            f"{100 * me['fraction_below_11_pct']:.0f} % below 11 %)")
    if wmap.score is not None:
        m = wmap.score["map"]["where_sampled"]
        text += ("; map - field RMS where sampled "
                 + "/".join(f"{m[n]['rms']:.3f}" for n in FLOW) + " m/s (u/v/w)")
    return text


def make_windmap(table, out_dir, *, pose: str = "auto", lever_arm_m=None, score: bool = False,
                 source_name: str = "table", mount_quat_wxyz=None, **settings) -> dict:
    """Compensate, map, score (optionally) and write (module docstring). `table`:
    FlightTable-like (df, metadata); `settings`: `build_windmap`'s keywords."""
    from airwake.estimate.airwake_map import write_json
    from airwake.estimate.map_report import check_map_dir, publish_dir
    from airwake.record.flight_table import write_flight_table
    from airwake.windmap.plots import plot_windmap

    out = Path(out_dir)
    if not out.parent.is_dir():
        raise WindMapError(f"cannot write {out}: directory {out.parent} does not exist")
    check_map_dir(out, WindMapError, ("grid.parquet", "summary.json"))
    samples = compensate(table.df, table.metadata, pose=pose, lever_arm_m=lever_arm_m,
                         mount_quat_wxyz=mount_quat_wxyz)
    wmap = build_windmap(samples, **settings)
    if score:
        wmap.score = score_windmap(wmap, table.metadata)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}-", dir=out.parent))
    try:
        meta = {"source": "airwake windmap", "input": source_name, **wmap.settings}
        write_flight_table(wmap.grid, tmp / "grid.parquet", meta)
        write_flight_table(wmap.locations, tmp / "locations.parquet", meta)
        figs = plot_windmap(wmap, tmp)
        summary = {"headline": headline(wmap), "out": str(out), "input": source_name,
                   **wmap.settings, "locations": len(wmap.locations),
                   "grid_points": len(wmap.grid),
                   "sampled_points": int(wmap.grid["sampled"].sum()),
                   "model_error": wmap.model_error,
                   "figures": sorted(p.name for p in figs.values())}
        if wmap.score is not None:
            summary["score"] = wmap.score
        write_json(summary, tmp / "summary.json")
        publish_dir(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return summary
