"""Campaign files for the tests, written next to a simulated campaign's flights."""

from pathlib import Path

import numpy as np
import pandas as pd
import tomli_w

# cheap steps: a short calibration (4 windows, 8 evaluations) without the discrepancy step
# (diagnose + add: tests/campaign/test_campaign_anchored.py runs it); the model report
# without its open-loop windows and sparse regression
FAST = {"calibrate": {"max_windows": 4, "max_nfev": 8, "discrepancy": False},
        "report": {"windows": 0, "sindy": False}}


def write_campaign(path: Path, sim: Path, flights=("flights/*.parquet",),
                   steps=("calibrate", "estimate", "map"), extra: list | None = None,
                   still_air: bool = False, calibrate: dict | None = None) -> Path:
    """A campaign file at `path` over the simulated campaign `sim`'s flights (globs relative
    to `sim`), the fast step options, plus `extra` [[flights]] entries; `still_air`: the
    helicopter's still-air cruise flight listed for its still-air net; `calibrate`:
    options that replace the fast calibration's."""
    heli = {"model": "table52",
            "calibration": str(sim / "calibration" / "calibration_heli1.parquet")}
    if still_air:
        heli["still_air"] = [str(sim / "calibration" / "still_air_heli1.parquet")]
    table = {"name": "test campaign",
             "steps": {"run": list(steps), **FAST,
                       "calibrate": {**FAST["calibrate"], **(calibrate or {})}},
             "helicopters": {"heli1": heli},
             "flights": [{"path": str(sim / f)} for f in flights] + list(extra or [])}
    path.write_text(tomli_w.dumps(table))
    return path


def broken_flight(sim: Path, out: Path) -> Path:
    """A copy of one flight without its x acceleration: it passes the campaign file's
    checks (they read metadata only) and fails in the wind estimate."""
    from airwake.record.flight_table import read_flight_table, write_flight_table

    df, meta = read_flight_table(sorted((sim / "flights").glob("beta0_*.parquet"))[0])
    out.mkdir(parents=True, exist_ok=True)
    path = out / "beta0_broken.parquet"
    write_flight_table(df.drop(columns=["acc_x_m_s2"]), path, meta)
    return path


def outputs(run) -> dict:
    """key -> {output name: content} of every finished task (tables as DataFrames, text
    files as text; pages and figures left out) and its summary without timings."""
    from airwake.campaign.store import Store

    store = Store(run.out / "store")
    out = {}
    for rec in run.records.values():
        if rec["status"] != "done":
            continue
        got = {}
        for name in rec["outputs"]:
            p = store.output(rec, name)
            if p.suffix == ".parquet":
                got[name] = pd.read_parquet(p)
            elif p.suffix == ".toml":
                got[name] = p.read_text()
        summary = {k: v for k, v in rec["summary"].items() if k != "realtime_factor"}
        out[rec["key"]] = (got, summary)
    return out


def assert_same_results(a: dict, b: dict) -> None:
    assert sorted(a) == sorted(b)
    for key in a:
        (ga, sa), (gb, sb) = a[key], b[key]
        assert sorted(ga) == sorted(gb), key
        for name in ga:
            if isinstance(ga[name], pd.DataFrame):
                pd.testing.assert_frame_equal(ga[name], gb[name], check_exact=True,
                                              obj=f"{key}/{name}")
            else:
                assert ga[name] == gb[name], f"{key}/{name}"
        assert _nan_equal(sa, sb), key


def _nan_equal(a, b) -> bool:
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(
            _nan_equal(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return isinstance(b, list) and len(a) == len(b) and all(map(_nan_equal, a, b))
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (np.isnan(a) and np.isnan(b))
    return a == b
