"""The daemon's live airwake intensity (`--net`) on a SIL flight: rover + base firmware
-> daemon, a rate net trained on a truth-world table, A_ω per rover INS sample on
`/host/airwake_intensity`, against the same net run offline on the exported flight."""

from __future__ import annotations

import numpy as np
import pytest
from airwake.cli import main

SIL_S = 6.0
SCENARIO = """
extends = "still_air_calibration"
description = "SIL live A_omega: hover, then the lateral chirp"

[[pilot.segments]]
type = "hover"
duration_s = 1.0

[[pilot.segments]]
type = "chirp"
channel = "lat"
amplitude_deg = 0.7
f0_hz = 0.3
f1_hz = 4.0
duration_s = 10.0
"""


@pytest.fixture(scope="module")
def net_flight(truth_world_flight, tmp_path_factory):
    from airwake.record.export import export_recording
    from airwake.record.reader import open_recording

    from hil_sim.boards.rig import rig_for
    from hil_sim.boards.sil import SilRun
    from hil_sim.world.scenario import load_scenario

    d = tmp_path_factory.mktemp("sil-net")
    net = d / "rates.pt"
    still = truth_world_flight("still_air_calibration", 5, 60.0)
    assert main(["nets", "train", str(still), "--out", str(net), "--quiet"]) == 0

    class NetSilRun(SilRun):
        def daemon_command(self, build_config):
            return super().daemon_command(build_config) + ["--net", str(net)]

    (d / "sc.toml").write_text(SCENARIO)
    sc = load_scenario(d / "sc.toml")
    run = NetSilRun(sc, out=d / "rec", duration_s=SIL_S, rig=rig_for(sc, ("rover", "base")))
    try:
        run.start()
        while not run.done:
            run.step()
        run.finish()
    except BaseException:
        run._abort()
        raise
    rec = open_recording(d / "rec")
    return net, rec, export_recording(rec)


def test_daemon_records_a_omega_per_rover_ins_sample(net_flight):
    # the recording carries the intensity an operator would have seen, sample by sample
    _, rec, built = net_flight
    samples = [m.json() for m in rec.messages(["/host/airwake_intensity"])]
    assert rec.metadata["live_net"]["target"] == "rates"
    t = np.array([s["t_s"] for s in samples])
    # one per INS sample after the first pilot-input frame (150 Hz), none twice
    assert len(samples) > 0.8 * 150 * (SIL_S - 1.0)
    assert np.all(np.diff(t) > 0)
    valid = np.array([s["valid"] for s in samples])
    assert valid.mean() > 0.6 and not valid[0]
    a = np.array([s["a_omega"] for s in samples])
    assert np.all(np.isfinite(a))
    assert len(samples) <= len(built.df) + 5


def test_live_prediction_matches_the_offline_net_on_the_exported_flight(net_flight):
    # the same net on the same samples: only the pilot inputs differ (held live,
    # interpolated by the export)
    from airwake.nets import load_net, predict

    path, rec, built = net_flight
    samples = [m.json() for m in rec.messages(["/host/airwake_intensity"])]
    live_t = np.array([s["t_s"] for s in samples])
    live_pred = np.array([s["pred_rad_s"] for s in samples])
    valid = np.array([s["valid"] for s in samples])
    pred = predict(load_net(path), built.df)
    # live t_s is the mapped INS stamp (as /host/pose); the export's t_s is relative to the
    # recording's start and has the INS's declared stamp latency (1.5 ms) removed
    off_t = pred["t_s"].to_numpy() + built.metadata["t0_monotonic_ns"] / 1e9
    k = np.clip(np.searchsorted(off_t, live_t), 1, off_t.size - 1)
    k = np.where(np.abs(off_t[k - 1] - live_t) < np.abs(off_t[k] - live_t), k - 1, k)
    ok = valid & (np.abs(off_t[k] - live_t) < 2.5e-3)
    assert ok.sum() > 0.5 * valid.sum(), "live and exported samples do not line up"
    off = pred[["p_pred_rad_s", "q_pred_rad_s", "r_pred_rad_s"]].to_numpy()[k[ok]]
    err = np.abs(live_pred[ok] - off)
    assert np.sqrt(np.mean(err ** 2)) < 0.01, np.sqrt(np.mean(err ** 2, axis=0))
