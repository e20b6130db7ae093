"""Live A_ω (the daemon's `--net`) gives what the offline map code gives for the same
samples, and refuses nets it cannot feed."""

import math
from collections import namedtuple

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main
from airwake.nets import load_net, predict
from airwake.nets.intensity import IntensityConfig, intensity_series
from airwake.nets.live import LiveIntensity
from airwake.nets.model import NetFileError
from airwake.record.rigging import BLADE_PITCH_COLUMNS, DEFAULT_RIGGING

Ins = namedtuple("Ins", "ypr_deg angular_rate_frd_rad_s")
Pilot = namedtuple("Pilot", "pwm_us valid_mask")


@pytest.fixture(scope="module")
def rate_net(truth_world_flight, tmp_path_factory):
    still = truth_world_flight("still_air_calibration", 5, 60.0)
    net = tmp_path_factory.mktemp("live") / "rates.pt"
    assert main(["nets", "train", str(still), "--out", str(net), "--quiet"]) == 0
    return load_net(net), still


def test_live_intensity_equals_the_offline_series_once_its_history_is_filled(rate_net):
    # the channel the daemon records must be the A_ω the map is built from
    net, path = rate_net
    df = pd.read_parquet(path).iloc[:1500].reset_index(drop=True)
    pwm = df[[f"pwm_ch{c}_us" for c in range(1, 6)]].to_numpy()
    # the live path derives the blade pitch from the pulse widths through the rigging
    pitch = DEFAULT_RIGGING.pwm_to_blade_pitch(pwm)
    for j, name in enumerate(BLADE_PITCH_COLUMNS):
        df[name] = pitch[:, j]
    cfg = IntensityConfig(std_window_s=0.5)
    offline = intensity_series(predict(net, df), cfg)
    live = LiveIntensity(net, cfg, batch_s=0.1)
    out = []
    for row in df.itertuples():
        live.on_pilot_inputs(row.t_s, Pilot(tuple(pwm[row.Index]), 0x1F))
        live.on_ins(row.t_s, Ins((math.degrees(row.yaw_rad), math.degrees(row.pitch_rad),
                                  math.degrees(row.roll_rad)),
                                 (row.p_rad_s, row.q_rad_s, row.r_rad_s)))
        out += live.step()
    out += live.step(force=True)
    assert len(out) == len(df)
    got = pd.DataFrame(out)
    valid = got["valid"].to_numpy()
    assert valid[-1] and not valid[0]
    assert np.allclose(got["t_s"], df["t_s"])
    for col in ("a_omega", "resid_std", "omega_s"):
        assert np.allclose(got[col].to_numpy()[valid], offline[col].to_numpy()[valid],
                           rtol=1e-6, atol=1e-9), col
    assert offline["valid"].to_numpy()[valid].all()


Baseline = namedtuple("Baseline", "baseline_ned_mm")


def test_live_samples_carry_the_track_in_the_ship_frame(rate_net):
    # the live view draws A_ω along the track: the RTK baseline (rover - base, NED) turned
    # by the base INS heading, plus the base antenna's place on the ship
    net, path = rate_net
    df = pd.read_parquet(path).iloc[:300].reset_index(drop=True)
    live = LiveIntensity(net, IntensityConfig(std_window_s=0.5), batch_s=0.1)
    live.base_antenna_ship_m = (-3.0, 1.0)
    pwm = df[[f"pwm_ch{c}_us" for c in range(1, 6)]].to_numpy()
    out = []
    for row in df.itertuples():
        if row.Index == 100:  # ship heading 90 deg (east), rover 10 m east, 2 m south
            live.on_ship_ins(row.t_s, Ins((90.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
            live.on_baseline(row.t_s, Baseline((-2000, 10000, -500)))
        live.on_pilot_inputs(row.t_s, Pilot(tuple(pwm[row.Index]), 0x1F))
        live.on_ins(row.t_s, Ins((0.0, 0.0, 0.0), (row.p_rad_s, row.q_rad_s, row.r_rad_s)))
        out += live.step()
    out += live.step(force=True)
    assert len(out) == len(df)
    assert all("ship_x_m" not in o for o in out[:100])  # not before both are known
    for o in out[100:]:
        # 10 m ahead of the base antenna along the heading, 2 m to starboard (south of a
        # ship heading east)
        assert o["ship_x_m"] == pytest.approx(-3.0 + 10.0)
        assert o["ship_y_m"] == pytest.approx(1.0 + 2.0)


def test_live_intensity_refuses_an_acceleration_net(truth_world_flight, tmp_path):
    still = truth_world_flight("still_air_calibration", 5, 60.0)
    path = tmp_path / "accel.pt"
    assert main(["nets", "train", str(still), "--target", "accel", "--out", str(path),
                 "--quiet"]) == 0
    with pytest.raises(NetFileError, match="rate net"):
        LiveIntensity(load_net(path))


def test_no_row_before_the_first_valid_pilot_input(rate_net):
    # without the pilot's inputs there is nothing to compensate: no fabricated rows
    net, _ = rate_net
    live = LiveIntensity(net)
    live.on_pilot_inputs(0.0, Pilot((1500,) * 5, 0x0E))  # channel 1 invalid
    live.on_ins(0.0, Ins((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    # a row waits for the pilot frame after it (the base's port may be late) ...
    assert live.step(force=True) == [] and live.status()["skipped"] == 0
    # ... at most max_wait_s of newer INS rows: then, with no pilot frame yet, it is dropped
    live.on_ins(live.max_wait_s + 0.01, Ins((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    assert live.step(force=True) == [] and live.status()["skipped"] == 1


def test_rows_take_the_pilot_inputs_at_their_time_whatever_port_comes_first(rate_net):
    # the base's frames arrive over another port, often after the rover's rows they
    # bracket: a row waits for the frame after it, then gets the export's interpolation
    net, _ = rate_net
    live = LiveIntensity(net)
    row = Ins((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    live.on_pilot_inputs(0.00, Pilot((1400, 1500, 1500, 1500, 1500), 0x1F))
    for t in (0.005, 0.010, 0.015):  # rover rows before the next pilot frame arrives
        live.on_ins(t, row)
    live._complete()
    assert live.pending == 0 and len(live.waiting) == 3
    live.on_pilot_inputs(0.02, Pilot((1600, 1500, 1500, 1500, 1500), 0x1F))
    live._complete()
    assert live.pending == 3 and not live.waiting and live.status()["held"] == 0
    want = DEFAULT_RIGGING.pwm_to_blade_pitch(
        np.array([[1400 + 200 * t / 0.02, 1500, 1500, 1500, 1500] for t in (0.005, 0.01, 0.015)]))
    got = np.array(live.rows)[:, 1:5]
    np.testing.assert_allclose(got, want[:, [BLADE_PITCH_COLUMNS.index(c) for c in (
        "delta_lat_rad", "delta_lon_rad", "delta_col_rad", "delta_ped_rad")]], atol=1e-12)
    # the base lost: after max_wait_s of newer rows a row holds the last frame's inputs
    live.on_ins(0.03, row)
    live.on_ins(0.03 + live.max_wait_s + 0.01, row)
    live._complete()
    assert live.status()["held"] == 1 and len(live.waiting) == 1


def test_a_live_net_that_raises_is_turned_off_and_the_recording_goes_on(tmp_path):
    # the daemon's loop over its live nets: a net that fails is switched off loudly, the
    # other nets and the recording go on
    import io

    from airwake.daemon.daemon import Daemon, DaemonOptions
    from airwake.record.reader import open_recording

    class Broken:
        def step(self):
            raise RuntimeError("boom")

    class Fine:
        def step(self):
            return [{"t_s": 1.0, "wind_vx_m_s": 0.5, "valid": True}]

    err = io.StringIO()
    d = Daemon(DaemonOptions(ports=[], out=tmp_path / "rec", view=False, track=False),
               stderr=err)
    d.intensity, d.wind = Broken(), Fine()
    d.nets = [("intensity", "/host/airwake_intensity", {"type": "object"}, "airwake intensity"),
              ("wind", "/host/wind", {"type": "object"}, "wind")]
    d._live_nets()
    d._live_nets()
    assert d.intensity is None and isinstance(d.wind, Fine)
    assert [e["kind"] for e in d.events].count("intensity_failed") == 1
    assert "live airwake intensity: RuntimeError: boom" in err.getvalue()
    d.recorder.close()
    topics = open_recording(tmp_path / "rec").topics()
    assert topics["/host/wind"] == 2 and "/host/airwake_intensity" not in topics
