"""The campaign's steps: each calls the public API of the command a user would run by hand
(`airwake export`, `calibrate`, `nets train --target wind --still-air`, `wind estimate`,
`wind map`, `model report`) and writes into the task's scratch directory.

    summary, outputs = STEPS[task.step](task, inputs, out_dir)

`inputs` maps a role ("flight", "model", "wind", "map <flight>") to the path of the
upstream output it names; `outputs` maps names to paths relative to `out_dir`; `summary`
is the JSON-able numbers the campaign summary and index page show.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from airwake.campaign.merge import merge_beta


def _has_truth(df) -> bool:
    from airwake.record.flight_table import TRUTH_WIND

    return all(c in df.columns for c in TRUTH_WIND)


def export(task, inputs: dict, out: Path):
    from airwake.record.export import export_recording
    from airwake.record.flight_table import write_flight_table
    from airwake.record.reader import open_recording

    opts = dict(task.args["options"])
    keep_latency = opts.pop("remove_stamp_latency", True)
    built = export_recording(open_recording(task.args["recording"]), opts,
                             remove_stamp_latency=keep_latency)
    write_flight_table(built.df, out / "flight.parquet", built.metadata)
    m = built.metadata
    return ({"rows": len(built.df), "rate_hz": m.get("rate_hz"),
             "span_s": m["trimmed"]["end_s"] - m["trimmed"]["start_s"],
             "missing_streams": m["missing_streams"],
             "recording_complete": m["recording_complete"]},
            {"flight": "flight.parquet"})


def calibrate(task, inputs: dict, out: Path):
    """`airwake calibrate` of the helicopter's still-air flight, then (option `discrepancy`,
    default on) `model diagnose` on it and `model add` of the effect its verdict names
    (`airwake.calibrate.sequence`: docs/calibration.md's sequence, what `make demo` does):
    the model output is the one the wind is estimated with."""
    from airwake.calibrate import calibrate as fit
    from airwake.calibrate.commands import calibration_table
    from airwake.calibrate.sequence import discrepancy_step
    from airwake.discrepancy.errors import DiscrepancyError
    from airwake.heli import save_spec
    from airwake.heli.context import MEAS_CHANNELS

    flight = inputs["flight"]
    start = task.args["start"]
    opts = dict(task.args["options"])
    discrepancy = opts.pop("discrepancy", True)
    result = fit(flight, model=start, **opts)
    save_spec(result.model, out / "calibrated.toml",
              description=f"calibrated by airwake campaign from {Path(flight).name} "
              f"(start {start})", calibration=calibration_table(result, flight, start))
    summary = {"method": result.method, "samples": result.info.get("samples"),
               "free_parameters": list(result.names),
               "rms_before": dict(zip(MEAS_CHANNELS, map(float, result.rms_before),
                                      strict=True)),
               "rms_after": dict(zip(MEAS_CHANNELS, map(float, result.rms_after),
                                     strict=True)),
               "notes": list(result.notes), "added": None}
    model = "calibrated.toml"
    if discrepancy:
        try:
            step = discrepancy_step(flight, out / "calibrated.toml", out / "added.toml")
        except DiscrepancyError as exc:  # the calibrated model stands; the reason is kept
            step = {"diagnosis": "", "added": None,
                    "why": f"the discrepancy step failed ({exc}): the calibrated model is used"}
        summary.update(diagnosis=step["diagnosis"], added=step["added"], why=step["why"])
        if step["added"]:
            model = "added.toml"
            # `model add`'s own comparison over the flight (not the fit's windows)
            summary["added_rms_before"] = {c: float(v) for c, v in step["before"].items()}
            summary["added_rms_after"] = {c: float(v) for c, v in step["after"].items()}
    return summary, {"model": model, "calibrated": "calibrated.toml"}


def still_air_net(task, inputs: dict, out: Path):
    """The helicopter's still-air wind net (`airwake nets train --target wind --still-air`)
    on its still-air flights: the mean flow with no model (docs/networks.md)."""
    from airwake.estimate.net_interval import MEAN_FLOW
    from airwake.nets.model import save_net
    from airwake.nets.wind_net import train_wind_net

    flights = {**task.args["flights"],
               **{r: p for r, p in inputs.items() if r.startswith("flight ")}}
    roles = sorted(flights, key=lambda r: int(r.split()[1]))  # "flight 0", "flight 1", ...
    paths = [flights[r] for r in roles]
    net = train_wind_net(paths, still_air=True, **task.args["options"])
    save_net(net, out / "still_air_net.pt")
    card = net.card
    rms = {o: card["validation_rms"][o]["net"] for o in MEAN_FLOW}  # it reads no rotation
    names = {r: Path(p).name for r, p in task.args["flights"].items()}
    return ({"flights": [names.get(r, f"{r} (exported)") for r in roles],
             "validation_rms": rms,
             "training_rows": card["training_rows"]},
            {"net": "still_air_net.pt"})


def estimate(task, inputs: dict, out: Path):
    """`airwake wind estimate`; anchored (spec.ANCHORED): the still-air net's mean flow
    with its interval widened by the model (`--method net --interval-model`), written as
    mean_flow.parquet, then the model's smoother anchored on it (`--anchor`)."""
    from airwake.calibrate import load_flight
    from airwake.campaign.spec import ANCHORED
    from airwake.estimate import estimate_wind, score_wind, write_wind

    ft = load_flight(inputs["flight"])
    opts = dict(task.args["options"])
    outputs = {"wind": "wind.parquet"}
    mean_flow = None
    if opts.get("method") == ANCHORED:
        opts.pop("method")
        # the front end and the INS error the user set hold for the net's interval too
        shared = {k: opts[k] for k in ("cutoff_hz", "rate_hz", "em_passes", "airspeed_m_s",
                                        "ins_velocity_std") if k in opts}
        mean_flow = estimate_wind(ft, method="net", net=inputs["net"],
                                  interval_model=inputs["model"], **shared)
        write_wind(mean_flow, out / "mean_flow.parquet")
        outputs["mean_flow"] = "mean_flow.parquet"
        est = estimate_wind(ft, model=inputs["model"], anchor=mean_flow.df, **opts)
        est.metadata["anchor"] = "mean_flow.parquet (the still-air net's, this task's)"
    else:
        est = estimate_wind(ft, model=inputs["model"], **opts)
    write_wind(est, out / "wind.parquet")
    summary = {"samples": int(len(est.df)), "flight_rows": int(len(ft.df)),
               "duration_s": float(ft.df["t_s"].iloc[-1] - ft.df["t_s"].iloc[0]),
               "method": task.args["options"].get("method", "smoother"),
               "realtime_factor": float(est.metadata["realtime_factor"])}
    if mean_flow is not None:
        summary["realtime_factor"] = float(
            summary["duration_s"] / (est.seconds + mean_flow.seconds))
        # how far the net can be trusted on this flight (its training's air velocities)
        summary["net_training_envelope_inside"] = mean_flow.metadata.get(
            "training_envelope_inside")
    if _has_truth(ft.df):
        comps = score_wind(est.df, ft.df)["components"]
        summary["wind_error"] = {n: {k: c[k] for k in ("error_mean", "error_std", "error_rms",
                                                        "coverage_90")}
                                 for n, c in comps.items()}
    return summary, outputs


def map_flight(task, inputs: dict, out: Path):
    """The flight's own map page (`airwake wind map`) and its cells on the campaign grid
    with no minimum time (the merge adds flights up cell by cell), with the simulator's
    field at each cell centre when the flight is simulated."""
    from airwake.estimate.airwake_map import FLOW_NAMES, ROT_NAMES, build_map, score_map
    from airwake.estimate.map_report import make_map
    from airwake.record.flight_table import load_flight_table, write_flight_table

    grid = task.args["grid"]
    opts = dict(task.args["options"])
    wind = load_flight_table(inputs["wind"], required=())
    flight = load_flight_table(inputs["flight"], required=("t_s",))
    truth = _has_truth(flight.df) and opts.pop("score", True)
    opts.pop("score", None)
    page = make_map(wind, flight, out / "map", cell_m=grid.cell_m, layer_m=grid.layer_m,
                    score=truth, ship=grid.ship(), wind_name=Path(inputs["wind"]).name,
                    flight_name=Path(inputs["flight"]).name, **opts)
    amap = build_map(wind.df, flight.df, wind_meta=wind.metadata, cell_m=grid.cell_m,
                     layer_m=grid.layer_m, min_seconds=0.0, u_ref=opts.get("u_ref"))
    cells = amap.cells.copy()
    if truth:
        field = np.asarray(score_map(amap, flight.df, flight.metadata,
                                     min_seconds=0.0)["truth_cells"]["field"], float)
        for j, name in enumerate((*FLOW_NAMES, *ROT_NAMES)):
            cells[f"truth_{name}"] = field[:, j]
    write_flight_table(cells, out / "cells.parquet",
                       {"source": "airwake campaign map", **amap.settings})
    deck = set(grid.deck_cells())
    enough = cells["seconds"].to_numpy() >= grid.min_seconds - 1e-9
    keys = list(zip(cells["ix"], cells["iy"], cells["iz"], strict=True))
    summary = {"cells": int(enough.sum()), "seconds": float(cells["seconds"].sum()),
               "deck_cells": len(deck),
               "deck_cells_covered": int(sum(1 for k, e in zip(keys, enough, strict=True)
                                             if e and k in deck)),
               "reference_speed_m_s": amap.settings["reference_speed_m_s"],
               "headline": page["headline"]}
    if truth:
        err = cells.loc[enough, list(FLOW_NAMES)].to_numpy() - cells.loc[
            enough, [f"truth_{n}" for n in FLOW_NAMES]].to_numpy()
        summary["field_rms"] = {n: float(np.sqrt(np.mean(err[:, j] ** 2))) if len(err) else
                                float("nan") for j, n in enumerate(FLOW_NAMES)}
    return summary, {"page": "map/index.html", "cells": "cells.parquet"}


def report(task, inputs: dict, out: Path):
    from airwake.discrepancy.report import write_report
    from airwake.discrepancy.settings import AnalysisSettings

    opts = dict(task.args["options"])
    sindy = opts.pop("sindy", True)
    res = write_report(inputs["flight"], inputs["model"], out / "report",
                       settings=AnalysisSettings(**opts), wind=inputs.get("wind"),
                       sindy=sindy)
    fit = {c: {"rms": float(m["rms"]), "rms_over_noise": float(m["rms_over_noise"])}
           for c, m in res["compare"]["channels"].items()}
    return ({"fit": fit, "verdict": res["verdict"]["text"], "after": res["after"]},
            {"page": "report/index.html"})


def merge(task, inputs: dict, out: Path):
    cells = {role.split(" ", 1)[1]: path for role, path in inputs.items()
             if role.startswith("map ")}
    missing = sorted(role.split(" ", 1)[1] for role in task.deps
                     if role.startswith("map ") and role not in inputs)
    summary = merge_beta(cells, task.args["beta_deg"], task.args["grid"], out, missing)
    return summary, {"page": "index.html", "map": "map.parquet"}


STEPS = {"export": export, "calibrate": calibrate, "still_air_net": still_air_net,
         "estimate": estimate, "map": map_flight,
         "report": report, "merge": merge}
