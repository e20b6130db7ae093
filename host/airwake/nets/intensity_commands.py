"""`airwake nets airwake FLIGHT --net NET.pt --out DIR`: the steps behind the command
(predict -> intensity -> map -> calibration -> score -> files), kept out of commands.py so
the parser stays a parser."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from airwake.nets.model import NetFileError

CALIBRATION_FORMAT = "airwake-turbulence-calibration/1"
NO_NET = "none"  # the net named in summaries and calibrations of a --no-net map


def _load_table(path):
    """A flight table with its metadata; only the columns present are checked (the map
    needs the net's inputs and a position, not the whole contract)."""
    from airwake.record.flight_table import load_flight_table

    return load_flight_table(path, required=())


def _is_simulated(table) -> bool:
    return isinstance(table.metadata.get("scenario_config"), dict) and "seed" in table.metadata


def zero_prediction(df: pd.DataFrame, source: str = "<table>") -> pd.DataFrame:
    """A `predict` frame with ω′ = 0 (`--no-net`): the residual is the measured rate, so
    A_ω = ω_s · ‖ω‖ and resid_std the gyro's own local std — the map any net must beat."""
    from airwake.record.flight_table import FlightTableError

    cols = ["t_s", "p_rad_s", "q_rad_s", "r_rad_s"]
    missing = [c for c in cols if c not in df.columns]
    if missing:
        raise FlightTableError(f"{source}: --no-net needs columns {missing}")
    out = {"t_s": np.asarray(df["t_s"], float)}
    for a in "pqr":
        out[f"{a}_pred_rad_s"] = np.zeros(len(df))
    for a in "pqr":
        out[f"{a}_resid_rad_s"] = np.asarray(df[f"{a}_rad_s"], float)
    bad = ~np.isfinite(np.column_stack([out[f"{a}_resid_rad_s"] for a in "pqr"])).all(axis=1)
    if bad.any():
        raise FlightTableError(f"{source}: --no-net: p/q/r_rad_s not finite at row "
                               f"{int(np.flatnonzero(bad)[0])}")
    out["history_valid"] = np.ones(len(df), np.int8)
    return pd.DataFrame(out)


def intensity_map_of(net, table, config, args, with_truth: bool):
    from airwake.nets.evaluate import predict
    from airwake.nets.intensity_map import build_intensity_map

    pred = zero_prediction(table.df, str(table.path or "<table>")) if net is None \
        else predict(net, table)
    return build_intensity_map(pred, table.df, config, args.cell_m, args.layer_m,
                               args.min_seconds, table.metadata if with_truth else None)


def _check_net_target(net, cal: dict, source: str) -> None:
    if (cal.get("net") == NO_NET) != (net is None):
        raise NetFileError(f"{source}: a calibration of "
                           + ("the --no-net map (gyro std), this map is a net's residual std"
                              if net is not None else
                              f"{cal.get('net')}'s residual std, this map is --no-net's"))
    if net is not None and cal.get("net_target") not in (None, net.card["target"]):
        raise NetFileError(f"{source}: a calibration of a {cal['net_target']} net, this net "
                           f"predicts {net.card['target']}")


def _net_name(args) -> str:
    return NO_NET if args.no_net else str(args.net)


def _target(net) -> str:
    return "rates" if net is None else net.card["target"]


def run_airwake(args) -> dict:
    """The command (module doc); returns its JSON summary."""
    import torch

    from airwake.estimate.airwake_map import write_json
    from airwake.nets.calibration import LineFit
    from airwake.nets.intensity import IntensityConfig
    from airwake.nets.intensity_map import calibrate_cells, score_intensity, write_intensity_map
    from airwake.nets.model import load_net
    from airwake.record.flight_table import FlightTableError

    torch.set_num_threads(1)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise NetFileError(f"--out {out}: exists and is not a folder")
    if not out.parent.is_dir():
        raise NetFileError(f"--out {out}: its parent folder does not exist")
    try:
        config = IntensityConfig(std_window_s=args.std_window_s)
    except ValueError as exc:
        raise NetFileError(f"--std-window-s: {exc}") from None
    net = None if args.no_net else load_net(args.net)
    if net is not None and net.card.get("target") == "wind":
        raise NetFileError(f"{args.net} is a wind net: A_ω needs a rate or acceleration "
                           "net's residuals")
    table = _load_table(args.flight)
    if args.score and not _is_simulated(table):
        raise FlightTableError(f"--score: {args.flight} is not a simulated flight (its metadata "
                               "has no scenario_config and seed)")
    amap = intensity_map_of(net, table, config, args, args.score)
    fit, cal = None, None
    if args.calibrate_on:
        cells = []
        for p in args.calibrate_on:
            t = _load_table(p)
            if not _is_simulated(t):
                raise FlightTableError(f"--calibrate-on: {p} is not a simulated flight")
            cells.append(intensity_map_of(net, t, config, args, True).cells)
        try:
            fit = calibrate_cells(pd.concat(cells, ignore_index=True),
                                  np.random.default_rng(args.seed))
        except ValueError as exc:
            raise NetFileError(f"--calibrate-on: {exc}") from None
        cal = {"format": CALIBRATION_FORMAT, "source": "ransac", **fit.to_dict(),
               "flights": [str(p) for p in args.calibrate_on], "net": _net_name(args),
               "net_target": _target(net), "resid_unit": amap.resid_unit,
               "intensity": config.to_dict(), "cell_m": args.cell_m, "seed": args.seed}
    elif args.calibration:
        try:
            cal = json.loads(Path(args.calibration).read_text())
            if cal.get("format") != CALIBRATION_FORMAT:
                raise ValueError(f"format {cal.get('format')!r}, expected {CALIBRATION_FORMAT}")
            fit = LineFit(float(cal["slope"]), float(cal["offset"]), np.zeros(0, bool),
                          float(cal.get("threshold", float("nan"))), int(cal.get("points", 0)))
        except (OSError, ValueError, KeyError) as exc:
            raise NetFileError(f"--calibration {args.calibration}: {exc}") from None
        _check_net_target(net, cal, args.calibration)
    if fit is not None:
        amap.cells["turbulence_m_s"] = fit(amap.cells["resid_std"].to_numpy())
        amap.samples["turbulence_m_s"] = fit(amap.samples["resid_std"].to_numpy())
    summary = {"flight": str(args.flight), "net": _net_name(args),
               "net_target": _target(net), "resid_unit": amap.resid_unit,
               "samples": len(amap.samples), "cells": len(amap.cells),
               "settings": amap.settings, "peaks": amap.peaks.to_dict("records"),
               "out": str(out)}
    if cal is not None:
        summary["calibration"] = cal
    if args.score:
        summary["score"] = score_intensity(amap.cells, fit)
        if args.calibrate_on and args.flight in args.calibrate_on:
            summary["score"]["note"] = "scored on a calibration flight (in-sample)"
    meta = {"kind": "airwake-intensity-map", **{k: v for k, v in summary.items()
                                                 if k not in ("peaks", "score")}}
    out.mkdir(exist_ok=True)
    title = f"{Path(args.flight).name}: "
    paths = write_intensity_map(amap, out, meta, title)
    if cal is not None and args.calibrate_on:
        write_json(cal, out / "calibration.json")
        paths["calibration"] = out / "calibration.json"
    summary["files"] = {k: str(v) for k, v in paths.items()}
    write_json(summary, out / "summary.json")
    return summary
