"""`make demo`'s driver end to end on short flights of the blade-element truth: every step
runs as the command a user types (calibrate, diagnose, add, fly, export, estimate, map), and
it ends with a report led by the airwake map, whose figures exist, whose verdicts follow
the numbers (the model section's, and which wind components the intervals fail), and
specs that load."""

import json
import subprocess
import sys
from html import escape as html_escape

import pytest
from airwake.heli import load_spec, spec_calibration
from browser import images_loaded
from sil_harness import REPO

from hil_sim.boards.demo import bound_verdict, estimate_verdict, truth_arguments


def test_demo_runs_every_step_and_prints_where_the_map_and_report_are(tmp_path):
    out = tmp_path / "demo"
    done = subprocess.run(
        [sys.executable, "-m", "hil_sim.boards.demo", "--out", str(out), "--duration", "10",
         "--calibration-s", "20", "--cruise-s", "30"], cwd=REPO, capture_output=True,
        text=True, timeout=900)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    report = out / "report" / "index.html"
    assert f"report       {report}" in done.stdout
    assert f"airwake map  {out / 'map' / 'map.parquet'}" in done.stdout
    html = report.read_text()
    # the truth is the independent blade-element machine, and the report says so
    run = json.loads((out / "recording" / "sil" / "run.json").read_text())
    assert run["helicopter"] == {"model": "blade_element", "pilot": "crossover"}
    assert "the independent blade-element machine" in html
    # the headline is the map
    assert html.index("Airwake map") < html.index("The model on this flight")
    # the model section's verdict follows the numbers: the estimated wind as the model's
    # input either takes the residual to its floor (the airwake) or it does not
    still = json.loads((out / "compare_still_air.json").read_text())["channels"]
    wind = json.loads((out / "compare_with_wind.json").read_text())["channels"]
    worst_still = max(c["rms_over_noise"] for c in still.values())
    worst_wind = max(c["rms_over_noise"] for c in wind.values())
    explains = worst_wind <= 8.0 and worst_still > 2 * worst_wind
    assert ("The residual of this flight is the airwake" in html) == explains
    assert ("The estimated wind does not account for the residual" in html) == (not explains)
    # the still-air diagnosis of the ship flight names the airwake, not a model effect
    diag = json.loads((out / "diagnose_still_air.json").read_text())
    assert diag["verdict"]["kind"] == "wind", diag["verdict"]
    assert diag["candidates"][0]["effect"] == "unmodelled_wind"
    assert "The residual is unmodelled wind" in html
    # the estimate's paragraph names every component whose intervals miss the truth
    comp = json.loads((out / "wind_estimate.json").read_text())["score"]["components"]
    paragraph = estimate_verdict(comp)
    assert html_escape(paragraph) in html
    for name, c in comp.items():
        short = {"wind_vx_m_s": "v_x", "wind_vy_m_s": "v_y", "wind_vz_m_s": "v_z",
                 "wind_wx_rad_s": "ω_x", "wind_wy_rad_s": "ω_y", "wind_wz_rad_s": "ω_z"}[name]
        assert (f"{short} ({100 * c['coverage_90']:.0f} %" in paragraph) == (
            c["coverage_90"] < 0.8), (name, c["coverage_90"], paragraph)
    # the Cramer-Rao bound at the truth is a bound on this airframe: the model's own misfit
    # (coloured) and the air's turbulence in it. It is a Bayesian bound, an average over
    # winds of the air's statistics, so one flight can fall below it by its own luck, not
    # far: 0.79 the lowest measured (v_y, the 60 s demo flight) with the per-channel AR(4)
    # misfit, against 0.53-0.57 of the white-noise bound it replaced on the blade-element
    # ship flights; the vector AR misfit (2026-11-28) lowers the bound, 0.95 the lowest
    # measured since on six ship flights
    est = json.loads((out / "wind_estimate.json").read_text())["score"]
    assert est["crlb"]["at"] == "truth" and "VAR(" in est["crlb"]["noise_model"]
    for name, c in comp.items():
        assert c["crlb_std"] > 0 and c["error_over_crlb"] >= 0.7, (name, c)
    # and the report says what limits the estimate, from those ratios
    assert bound_verdict(comp) and html_escape(bound_verdict(comp)) in html
    # the mean flow with no model: the still-air net, its mean flow scored beside the
    # smoother's, its rotation not estimated (not in the table)
    from hil_sim.boards.demo import net_rows

    net = json.loads((out / "wind_estimate_still_air_net.json").read_text())
    # the model the wind is estimated with: the sequence's last step's
    final = json.loads((out / "steady_step.json").read_text())["model"]
    assert net["method"] == "net" and net["held_out"]
    # its interval: the still-air error widened by the model's smoother, said so
    assert net["interval_model"] == final
    assert "above 0.1 Hz" in net["std_is"]
    assert all(v > 0 for v in net["interval_fast_std_median_m_s"].values())
    # and the fast wind the smoother did not see either, from its learned turbulence
    assert all(v > 0 for v in net["interval_unseen_std_median_m_s"].values())
    assert len(net["interval_turbulence_sigma_m_s"]) == 3
    assert "did not see either" in html
    rows = net_rows(net, json.loads((out / "wind_estimate.json").read_text()))
    assert [r[0] for r in rows] == ["wind_vx_m_s", "wind_vy_m_s", "wind_vz_m_s"] + [
        f"{n} (the model, given it)" for n in ("wind_wx_rad_s", "wind_wy_rad_s",
                                                "wind_wz_rad_s")]
    # the rotation given the net's mean flow: the smoother anchored on the net's table
    anchored = net["anchored"]
    assert anchored["method"] == "smoother" and "crlb" not in anchored["score"]
    assert anchored["anchor"] == str(out / "wind_still_air_net.parquet")
    assert (out / "wind_anchored.parquet").is_file()
    # its intervals carry what the model's own estimate erred beyond them in still air
    excess = spec_calibration(final)["still_air_wind_error"]
    assert anchored["still_air_wind_error"] == excess["anchored"]
    assert len(excess["smoother"]) == 6 and min(excess["smoother"]) >= 0
    assert "a still-air wind net" in html
    for row in rows:
        assert "".join(f"<td>{html_escape(c)}</td>" for c in row) in html
    # calibrate -> diagnose -> add, as docs/calibration.md has a user do it
    step = json.loads((out / "discrepancy_step.json").read_text())
    assert step["diagnosis"] in html or html_escape(step["diagnosis"]) in html
    model = load_spec(step["model"])
    if step["added"]:
        assert step["model"] == str(out / "model.toml")
        assert step["added"] in model.effect_names
        assert f"RMS, with {step['added']}" in html
        assert not [c for c in step["before"]
                    if step["after"][c] > step["before"][c] * 1.01]
    else:
        assert step["model"] == str(out / "baseline.toml")
    # then the same on the cruise legs, from that model, its misfit measured on the
    # calibration flight (the wind estimator's floor for a flight that manoeuvres)
    steady = json.loads((out / "steady_step.json").read_text())
    assert html_escape(steady["diagnosis"]) in html and "still-air cruise legs" in html
    if steady["added"]:
        assert final == str(out / "steady.toml")
        assert steady["added"] in load_spec(final).effect_names
        assert set(step["added"] and [step["added"]] or []) <= set(
            load_spec(final).effect_names)
        table = spec_calibration(final)
        assert table["model_error_flight"] == str(out / "calibration.parquet")
        assert table["added_effects"][-1] == steady["added"]
        assert f"RMS, with {steady['added']}" in html
    else:
        assert final == step["model"]
    # the calibrated model's steady wind error in still air, and the channels that make it
    from hil_sim.boards.demo import still_air_bias_section

    bias = spec_calibration(out / "baseline.toml")["still_air_wind_bias"]
    assert len(bias["by_channel"]) == 6
    section = still_air_bias_section(bias)
    assert section.count("<tr>") == 7 and section in html
    for f in ("mean_flow.png", "turbulence.png", "coverage.png"):
        assert (out / "report" / f).stat().st_size > 0 and f in html
    # a real browser opens the report and the map's page with every figure loaded
    assert images_loaded(report) == (3, 3)
    assert images_loaded(out / "map" / "index.html") == (3, 3)
    assert "http://" not in html and "https://" not in html and "<script" not in html
    summary = json.loads((out / "map" / "summary.json").read_text())
    assert summary["frame"] == "ship" and summary["cells"] > 0 and "score" in summary
    # the map is made from the best wind this airframe gives: the smoother anchored on the
    # still-air net's mean flow, and its summary says so
    assert summary["estimate"]["method"] == "smoother"
    assert summary["estimate"]["anchor"] == str(out / "wind_still_air_net.parquet")
    assert summary["headline"] in html
    base, t52 = load_spec(out / "baseline.toml"), load_spec("table52")

    def profile_drag(m):  # delta_0 / a0: what the loads see of the blade's profile drag
        p = m["main_rotor"].parameters()
        return p["drag_delta0"] / p["lift_slope_per_rad"]

    assert abs(profile_drag(base) / profile_drag(t52) - 1) > 0.5  # calibrated, not Table 5.2
    assert spec_calibration(out / "baseline.toml")["start"] == "table52"
    assert (out / "recording").is_dir() and (out / "wind.parquet").stat().st_size > 0


def test_estimate_verdict_names_exactly_the_components_whose_intervals_miss():
    comp = {n: {"coverage_90": cov, "error_mean": bias} for n, cov, bias in (
        ("wind_vx_m_s", 0.16, 0.71), ("wind_vy_m_s", 0.92, -0.2), ("wind_vz_m_s", 0.79, -0.4),
        ("wind_wx_rad_s", 1.0, 0.0), ("wind_wy_rad_s", 0.8, 0.3), ("wind_wz_rad_s", 0.5, 0.1))}
    text = estimate_verdict(comp)
    assert "v_x (16 %, bias +0.71)" in text and "v_z (79 %, bias -0.40)" in text
    assert "ω_z (50 %, bias +0.10)" in text
    assert "v_y" not in text and "ω_x" not in text and "ω_y" not in text
    for c in comp.values():
        c["coverage_90"] = 0.9
    assert estimate_verdict(comp).startswith("The 90 % intervals hold the truth at least 80 %")


def test_bound_verdict_names_the_components_the_estimator_limits():
    comp = {n: {"error_over_crlb": r} for n, r in (
        ("wind_vx_m_s", 4.46), ("wind_vy_m_s", 1.11), ("wind_vz_m_s", 3.51),
        ("wind_wx_rad_s", 1.5), ("wind_wy_rad_s", 1.51), ("wind_wz_rad_s", 0.97))}
    text = bound_verdict(comp)
    assert "the error is 1.0–4.5x the bound" in text
    assert "v_x (4.5x)" in text and "v_z (3.5x)" in text and "ω_y (1.5x)" in text
    assert "v_y" not in text and "ω_x" not in text and "ω_z" not in text
    near = {n: {"error_over_crlb": 1.2} for n in comp}
    assert "the information in this flight, not the estimator" in bound_verdict(near)
    assert bound_verdict({n: {"error_over_crlb": None} for n in comp}) == ""


def test_truth_arguments_fly_each_truth_with_its_pilot():
    assert truth_arguments("blade_element") == ["--truth", "blade_element", "--pilot",
                                                "crossover"]
    # the shipped scenarios name the crossover pilot: our own model gets its LQR back
    assert truth_arguments("effects") == ["--truth", "effects", "--pilot", "full_state"]
    with pytest.raises(ValueError, match="'jsbsim'"):
        truth_arguments("jsbsim")


def test_a_step_that_fails_stops_the_demo_and_the_flight_beside_it(tmp_path):
    """The ship flight runs beside the model steps: when one of those fails, the demo
    stops with the failing command named and leaves no flight running."""
    import os
    from pathlib import Path

    out = tmp_path / "demo"
    done = subprocess.run(
        [sys.executable, "-m", "hil_sim.boards.demo", "--out", str(out), "--duration", "10",
         "--calibration-s", "-5"], cwd=REPO, capture_output=True, text=True, timeout=300)
    assert done.returncode != 0
    assert "demo: `airwake sim table` failed" in done.stderr, done.stderr[-1000:]
    left = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            cmd = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
        except OSError:
            continue
        if str(out) in cmd and "sim run" in cmd.replace("'", ""):
            left.append(cmd)
    assert not left, left
