"""Recordings in a campaign go through `airwake export` first: the flight table in the store
is the one the command writes, and a re-run (the recording unchanged) skips it."""

import importlib.util
from pathlib import Path

import tomli_w
from airwake.campaign import load_campaign, run_campaign
from airwake.campaign.store import Store
from airwake.record.export import export_recording
from airwake.record.flight_table import read_flight_table
from airwake.record.reader import open_recording


def _write_synthetic():
    """tests/record/test_export.py's recording writer (boards with known clocks)."""
    path = Path(__file__).resolve().parents[1] / "record" / "test_export.py"
    spec = importlib.util.spec_from_file_location("_record_test_export", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.write_synthetic


def test_a_recording_is_exported_once_like_the_export_command(tmp_path):
    rec = tmp_path / "recordings" / "may20_a"
    _write_synthetic()(rec, duration_s=6.0)
    table = {"steps": {"run": ["export"]}, "helicopters": {"h": {"model": "table52"}},
             "flights": [{"path": "recordings/may20_*", "beta_deg": 30.0}]}
    (tmp_path / "campaign.toml").write_text(tomli_w.dumps(table))
    camp = load_campaign(tmp_path / "campaign.toml")
    assert [(f.name, f.source.kind, f.beta_deg) for f in camp.flights] == [
        ("may20_a", "recording", 30.0)]

    run = run_campaign(camp, tmp_path / "out", workers=0, show=False)
    (rec_,) = run.records.values()
    assert rec_["status"] == "done" and rec_["step"] == "export"
    got, meta = read_flight_table(Store(run.out / "store").output(rec_, "flight"))
    want = export_recording(open_recording(rec), {})
    assert got.equals(want.df.reset_index(drop=True))
    assert meta["recording"] == str(rec)
    row = run.summary.set_index("flight").loc["may20_a"]
    assert row["status"] == "done" and row["beta_deg"] == 30.0

    again = run_campaign(camp, tmp_path / "out", workers=0, show=False)
    assert again.ran == 0 and next(iter(again.records.values()))["cached"]
