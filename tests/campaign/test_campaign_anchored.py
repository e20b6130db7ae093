"""A campaign with still-air flights estimates as `make demo` does on a helicopter its model
was not written for: the calibrated model diagnosed and the effect it names added, one
still-air wind net per helicopter (its calibration flight and its still-air cruise legs),
every flight's mean flow from that net with its interval widened by
the calibrated model, and the model's smoother anchored on it for the rotation; the net
and the estimates are the same on a second run from an empty store (content-addressed
results must not depend on the run)."""

import numpy as np
import pytest
from airwake.campaign import load_campaign, run_campaign
from airwake.campaign.store import Store
from airwake.heli import load_spec
from airwake.record.flight_table import read_flight_table
from campaigns import assert_same_results, outputs, write_campaign

V = ("wind_vx_m_s", "wind_vy_m_s", "wind_vz_m_s")


@pytest.mark.slow
def test_anchored_campaign_trains_a_net_per_helicopter_and_anchors_every_estimate(
        sim_campaign, tmp_path):
    camp = load_campaign(write_campaign(
        tmp_path / "campaign.toml", sim_campaign,
        flights=("flights/beta0_01.parquet", "flights/beta15_01.parquet"),
        steps=("calibrate", "still_air_net", "estimate", "map"), still_air=True,
        calibrate={"discrepancy": True}))
    run = run_campaign(camp, tmp_path / "a", workers=0, show=False)
    assert not run.failed, [r["error"] for r in run.records.values() if r["error"]]
    store = Store(run.out / "store")
    # the model the wind is estimated with: calibrate -> diagnose -> add (the verdict's
    # effect, unless it made a channel worse: then the calibrated model)
    cal = run.records[run.plan.by_subject["heli1"]["calibrate"]]
    assert cal["summary"]["diagnosis"] and cal["summary"]["why"]
    model = load_spec(store.output(cal, "model"))
    if cal["summary"]["added"]:
        assert cal["outputs"]["model"] == "added.toml"
        assert cal["summary"]["added"] in model.effect_names
    else:
        assert cal["outputs"]["model"] == "calibrated.toml"
    net = run.records[run.plan.by_subject["heli1"]["still_air_net"]]
    assert net["summary"]["flights"] == ["calibration_heli1.parquet", "still_air_heli1.parquet"]
    assert sorted(net["summary"]["validation_rms"]) == sorted(V)  # the mean flow only
    assert store.output(net, "net").stat().st_size > 0
    for name in ("beta0_01", "beta15_01"):
        rec = run.records[run.plan.by_subject[name]["estimate"]]
        assert rec["summary"]["method"] == "anchored"
        assert 0.0 <= rec["summary"]["net_training_envelope_inside"] <= 1.0
        wind, meta = read_flight_table(store.output(rec, "wind"))
        mean_flow, mmeta = read_flight_table(store.output(rec, "mean_flow"))
        assert mmeta["method"] == "net" and "above 0.1 Hz" in mmeta["std_is"]
        assert meta["method"] == "smoother" and "still-air net" in meta["anchor"]
        t = wind["t_s"].to_numpy()
        for n in V:
            net_v = np.interp(t, mean_flow["t_s"], mean_flow[n])
            net_std = np.interp(t, mean_flow["t_s"], mean_flow[f"{n}_std"])
            # the model does not narrow the net's interval, and the mean flow is the net's
            # within it (the smoother reads the rotation given it)
            assert np.all(wind[f"{n}_std"].to_numpy() >= 0.95 * net_std), n
            assert np.sqrt(np.mean((wind[n].to_numpy() - net_v) ** 2)) < np.median(net_std), n
        # the rotation is the model's, given it: estimated, with intervals
        assert np.isfinite(wind["wind_wx_rad_s"]).all() and (wind["wind_wz_rad_s_std"] > 0).all()
    assert (run.summary.loc[run.summary["role"] == "flight", "map_cells"] > 0).all()
    # a second campaign from an empty store gets the same net and the same winds
    again = run_campaign(camp, tmp_path / "b", workers=0, show=False)
    assert_same_results(outputs(run), outputs(again))
    # and the first store, run again, runs nothing
    rerun = run_campaign(camp, tmp_path / "a", workers=0, show=False)
    assert rerun.ran == 0
