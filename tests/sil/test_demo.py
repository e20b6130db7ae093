"""`make demo`'s driver end to end on short flights: every step runs as the command a user
types, and it ends with a report whose figures exist and a baseline spec that loads."""

import subprocess
import sys

from airwake.heli import load_spec
from sil_harness import REPO


def test_demo_runs_every_step_and_prints_where_the_report_is(tmp_path):
    out = tmp_path / "demo"
    done = subprocess.run(
        [sys.executable, "-m", "hil_sim.boards.demo", "--out", str(out), "--duration", "8",
         "--calibration-s", "12"], cwd=REPO, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    report = out / "report" / "index.html"
    assert f"report       {report}" in done.stdout
    assert report.stat().st_size > 0 and list((out / "report").glob("*.png"))
    assert "id=candidates" in report.read_text()
    base = load_spec(out / "baseline.toml")
    assert base["main_rotor"].parameters()["drag_delta0"] != 0.0702  # calibrated, not Table 5.2
    assert (out / "recording").is_dir() and (out / "flight.parquet").stat().st_size > 0
