"""`make demo`'s driver end to end on short flights: every step runs as the command a user
types, and it ends with a report led by the airwake map, whose figures exist, whose model
section says the residual is the airwake, and a baseline spec that loads."""

import json
import subprocess
import sys

from airwake.heli import load_spec, spec_calibration
from browser import images_loaded
from sil_harness import REPO


def test_demo_runs_every_step_and_prints_where_the_map_and_report_are(tmp_path):
    out = tmp_path / "demo"
    done = subprocess.run(
        [sys.executable, "-m", "hil_sim.boards.demo", "--out", str(out), "--duration", "10",
         "--calibration-s", "20"], cwd=REPO, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    report = out / "report" / "index.html"
    assert f"report       {report}" in done.stdout
    assert f"airwake map  {out / 'map' / 'map.parquet'}" in done.stdout
    html = report.read_text()
    # the headline is the map; the model section does not blame an effect for the wind
    assert html.index("Airwake map") < html.index("The model on this flight")
    # ... because the estimated wind, given to the model, takes the residual to its floor
    still = json.loads((out / "compare_still_air.json").read_text())["channels"]
    wind = json.loads((out / "compare_with_wind.json").read_text())["channels"]
    worst_still = max(c["rms_over_noise"] for c in still.values())
    worst_wind = max(c["rms_over_noise"] for c in wind.values())
    assert worst_wind <= 8.0 and worst_still > 2 * worst_wind, (worst_still, worst_wind)
    assert "The residual of this flight is the airwake" in html
    assert "best explained by" not in html
    # the diagnosis, with no wind given, names the wind, not a model effect
    diag = json.loads((out / "diagnose_still_air.json").read_text())
    assert diag["verdict"]["kind"] == "wind", diag["verdict"]
    assert diag["candidates"][0]["effect"] == "unmodelled_wind"
    assert "The residual is unmodelled wind" in html
    for f in ("mean_flow.png", "turbulence.png", "coverage.png"):
        assert (out / "report" / f).stat().st_size > 0 and f in html
    # a real browser opens the report and the map's page with every figure loaded
    assert images_loaded(report) == (3, 3)
    assert images_loaded(out / "map" / "index.html") == (3, 3)
    assert "http://" not in html and "https://" not in html and "<script" not in html
    summary = json.loads((out / "map" / "summary.json").read_text())
    assert summary["frame"] == "ship" and summary["cells"] > 0 and "score" in summary
    assert summary["headline"] in html
    base, t52 = load_spec(out / "baseline.toml"), load_spec("table52")

    def profile_drag(m):  # delta_0 / a0: what the loads see of the blade's profile drag
        p = m["main_rotor"].parameters()
        return p["drag_delta0"] / p["lift_slope_per_rad"]

    assert abs(profile_drag(base) / profile_drag(t52) - 1) > 0.5  # calibrated, not Table 5.2
    assert spec_calibration(out / "baseline.toml")["start"] == "table52"
    assert (out / "recording").is_dir() and (out / "wind.parquet").stat().st_size > 0
