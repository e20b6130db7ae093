"""Fly a simulated campaign and write it out for `airwake campaign`.

    summary = generate("DIR", flights=12, betas=(0, 15, 30), seed=7)

DIR/scenarios/<flight>.toml (each flight's scenario, `plan`), DIR/flights/<flight>.parquet,
DIR/calibration/calibration_<heli>.parquet and DIR/calibration/still_air_<heli>.parquet
(the still-air cruise legs its still-air wind net also learns from; none with
`still_air_s` = 0) (the truth world's flight tables, truth columns included, with a
`campaign` metadata table: beta_deg, helicopter, day, role), and DIR/campaign.toml: its
estimate is the still-air net's mean flow anchoring the calibrated model's smoother
(`airwake.campaign.spec`), the plain smoother without still-air cruise flights. Every
scenario is loaded (validated) before the first flight flies; the flights fly on a Dask
LocalCluster (`workers`; 0 = one after another here).
"""

from __future__ import annotations

import os
from pathlib import Path

from hil_sim.campaign.plan import (
    STILL_AIR_S,
    calibration_scenario,
    flight_scenario,
    helicopter_names,
    plan_flights,
    still_air_scenario,
)

DAY = "sim"
# the campaign file's step options: the demo's calibration (24 windows); the model report
# without open-loop simulation windows or the sparse regression (seconds per flight, not
# minutes: run `airwake model report` on the flights that need them)
STEP_OPTIONS = {"calibrate": {"max_windows": 24}, "report": {"windows": 0, "sindy": False}}


def fly_one(scenario_path: str, out_path: str, campaign_meta: dict) -> dict:
    """Fly one scenario file into a flight table (written via a temp file)."""
    import time

    from airwake.record.flight_table import write_flight_table

    from hil_sim.world.run import run_scenario
    from hil_sim.world.scenario import load_scenario

    t0 = time.perf_counter()
    built = run_scenario(load_scenario(scenario_path)).flight_table()
    meta = {**built.metadata, "campaign": campaign_meta}
    out = Path(out_path)
    tmp = out.with_name(f".{out.name}.tmp{out.suffix}")
    write_flight_table(built.df, tmp, meta)
    os.replace(tmp, out)
    return {"flight": out.stem, "rows": int(len(built.df)),
            "duration_s": float(built.df["t_s"].iloc[-1] - built.df["t_s"].iloc[0]),
            "seconds": time.perf_counter() - t0}


def _write_toml(table: dict, path: Path) -> None:
    import tomli_w

    path.write_text(tomli_w.dumps(table))


def campaign_file(name: str, description: str, helicopters: list[str],
                  still_air: bool = True) -> dict:
    run = ["calibrate", *(["still_air_net"] if still_air else []), "estimate", "map",
           "report"]
    return {"name": name, "description": description,
            "steps": {"run": run, **STEP_OPTIONS},
            "helicopters": {h: {"model": "table52",
                                "calibration": f"calibration/calibration_{h}.parquet",
                                **({"still_air": [f"calibration/still_air_{h}.parquet"]}
                                   if still_air else {})}
                            for h in helicopters},
            "flights": [{"path": "flights/*.parquet"}]}


def check_out_dir(out: Path) -> None:
    from hil_sim.world.scenario import ScenarioError

    if out.exists() and (not out.is_dir() or (any(out.iterdir())
                                              and not (out / "campaign.toml").exists())):
        raise ScenarioError(f"--out {out}: exists and is not an earlier simulated campaign "
                            "(no campaign.toml): refusing to write into it")


def generate(out, flights: int, betas, seed: int, *, truth: str | None = None,
             helicopters: int = 1, duration_s: float | None = None,
             calibration_s: float | None = None, still_air_s: float = STILL_AIR_S,
             speed_m_s: float = 0.6, workers: int | None = None,
             progress: bool = True) -> dict:
    """Plan, validate, fly and write the campaign (module docstring); its summary."""
    from airwake.progress import Progress

    from hil_sim.world.scenario import ScenarioError, load_scenario

    out = Path(out)
    check_out_dir(out)
    if not (still_air_s >= 0):
        raise ScenarioError(f"--still-air-s {still_air_s}: must be >= 0 (0: none)")
    try:
        planned = plan_flights(flights, betas, seed, helicopters, speed_m_s)
        jobs = []
        for d in ("scenarios", "flights", "calibration"):
            (out / d).mkdir(parents=True, exist_ok=True)
        for h_i, h in enumerate(helicopter_names(helicopters)):
            table = calibration_scenario(h, seed * 1000 + 900 + h_i, truth, calibration_s)
            jobs.append((f"calibration_{h}", table, out / "calibration",
                         {"role": "calibration", "helicopter": h, "day": DAY}))
            if still_air_s > 0:
                table = still_air_scenario(h, seed * 1000 + 950 + h_i, truth, still_air_s)
                jobs.append((f"still_air_{h}", table, out / "calibration",
                             {"role": "still_air", "helicopter": h, "day": DAY}))
        for f in planned:
            jobs.append((f.name, flight_scenario(f, truth, duration_s), out / "flights",
                         {"role": "flight", "beta_deg": f.beta_deg, "helicopter": f.helicopter,
                          "day": DAY, "stations_x_m": list(f.stations_x_m),
                          "height_m": f.height_m}))
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None
    for old in (out / "flights").glob("*.parquet"):  # a smaller re-generation leaves none
        old.unlink()
    paths = []
    for name, table, where, meta in jobs:
        scen = out / "scenarios" / f"{name}.toml"
        _write_toml(table, scen)
        load_scenario(scen)  # every scenario valid before the first flight flies
        paths.append((str(scen), str(where / f"{name}.parquet"), meta))
    bar = Progress("sim campaign", len(paths), " flights", enabled=progress)
    done = []
    if workers == 0:
        for i, p in enumerate(paths):
            done.append(fly_one(*p))
            bar.update(i + 1)
    else:
        from airwake.campaign.cluster import open_client
        from distributed import as_completed

        with open_client(workers) as client:
            futs = [client.submit(fly_one, *p, pure=False) for p in paths]
            for i, fut in enumerate(as_completed(futs)):
                done.append(fut.result())
                bar.update(i + 1)
    bar.finish()
    betas_text = ", ".join(f"{b:g}" for b in sorted({f.beta_deg for f in planned}))
    _write_toml(campaign_file(
        f"sim campaign seed {seed}",
        f"{flights} simulated flights at beta {betas_text} deg, lateral sweeps over the deck "
        f"area (airwake sim campaign --flights {flights} --seed {seed})"
        + (f", truth helicopter {truth}" if truth else ""),
        helicopter_names(helicopters), still_air=still_air_s > 0), out / "campaign.toml")
    own = ("calibration_", "still_air_")
    return {"out": str(out), "campaign": str(out / "campaign.toml"),
            "flights": [d for d in done if not d["flight"].startswith(own)],
            "calibrations": [d for d in done if d["flight"].startswith("calibration_")],
            "still_air": [d for d in done if d["flight"].startswith("still_air_")],
            "sim_seconds": sum(d["seconds"] for d in done)}
