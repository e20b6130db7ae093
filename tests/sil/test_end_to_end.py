"""End to end, stepped: truth world -> native boards -> ptys -> daemon -> recording -> export.

One 12 s flight of still_air_calibration with all four boards (`clean_flight`), scored
against the truth world it was fed from."""

from __future__ import annotations

import json

import numpy as np
from airwake.link.messages import MESSAGES
from airwake.record.reader import open_recording
from conftest import CLEAN_S
from frame_sets import recorded_frames
from sil_harness import (
    BAD_KINDS,
    as_set,
    delivered_frames,
    frame_logs,
    load_export,
    sent_frames,
    sim_time,
    summary,
)
from truths import effect_truth

BOARDS = {"losa", "marker", "rover", "base"}
# what each board must deliver in a hall flight (no GNSS indoors, no ship INS)
REQUIRED = {"losa": ("losa_peaks", "imu"), "marker": ("marker_attitude", "imu"),
            "rover": ("ins", "rotor_speed", "tail_servo"), "base": ("pilot_inputs",)}


def test_every_board_is_detected_identified_and_clean(clean_flight):
    # the daemon identified all four boards from their heartbeats, schema OK, no errors
    s = summary(clean_flight)
    st = s["daemon_status"]
    assert s["daemon_exit"] == 0 and all(c == 0 for c in s["board_exit"].values())
    assert set(st["boards"]) == BOARDS
    for name, b in st["boards"].items():
        assert b["identified"] and b["schema_ok"] and b["boot_count"] == 0, (name, b)
        assert sum(b.get("seq_lost", {}).values()) == 0, (name, b["seq_lost"])
    for role, p in st["ports"].items():
        assert sum(p["errors"][k] for k in BAD_KINDS) == 0, (role, p["errors"])
        assert p["opens"] == 1
    rec = open_recording(clean_flight / "rec")
    assert rec.complete and set(rec.boards) == BOARDS
    assert s["drained"] is True
    # and it read nothing but its ports in mid-flight: the lockstep's byte count is exact
    assert s["lockstep"] == {"other_read_bytes": 0, "other_reads": 0}


def test_message_rates_are_within_5_percent_of_nominal(clean_flight):
    # rates in board time from the recording: every periodic message at >= 10 Hz
    rec = open_recording(clean_flight / "rec")
    tables = rec.tables([t for t in rec.decoded_topics() if not t.startswith("/host/")])
    nominal = {(b, m.name): float(r) for m in MESSAGES for b, r in m.rate_hz.items()}
    checked = set()
    for topic, t in tables.items():
        board, name = topic.strip("/").split("/")
        rate = nominal.get((board, name), 0.0)
        if rate < 10 or name in ("schema_entry",):
            continue
        us = t.rows["board_us"].astype(np.int64)
        measured = (len(us) - 1) / ((us[-1] - us[0]) / 1e6)
        assert abs(measured / rate - 1) <= 0.05, (topic, measured, rate)
        checked.add((board, name))
    for board, names in REQUIRED.items():
        for name in names:
            assert (board, name) in checked, (board, name, sorted(checked))
    for board in BOARDS:  # 1 Hz heartbeats: one per second of the flight
        n = len(tables[f"/{board}/heartbeat"])
        assert abs(n - CLEAN_S) <= 1, (board, n)


def test_every_frame_the_boards_sent_was_recorded_and_nothing_else(clean_flight):
    # clean links: the recording holds exactly the frames delivered on the ptys, and those
    # are every frame the boards sent but the rover's last few, still on the XBee hop
    logs = frame_logs(clean_flight)
    delivered = delivered_frames(logs)
    rec = open_recording(clean_flight / "rec")
    assert recorded_frames(rec) == delivered
    sent, touched = sent_frames(logs)
    assert len(sent) > 12_000 and delivered <= sent and not touched
    rover = logs["rover_sent"]
    in_flight = as_set(rover[rover[:, 0] >= CLEAN_S * 1e6 - summary(clean_flight)["rig"][
        "xbee_latency_us"] - 1000])
    assert sent - delivered <= in_flight


def test_ins_frames_carry_the_vn200_samples_bit_for_bit(clean_flight):
    # the VN200 model's packets, parsed by the rover firmware, forwarded by the base,
    # decoded by the daemon: the same float32 values, every sample, in order
    rec = open_recording(clean_flight / "rec")
    ins = rec.table("/rover/ins").rows
    with np.load(clean_flight / "truth.npz") as z:
        t_ns, ypr = z["vn_time_startup_ns"], z["vn_ypr_deg"]
        rates, acc = z["vn_rates_rad_s"], z["vn_accel_m_s2"]
    idx = np.searchsorted(t_ns, ins["time_startup_ns"].astype(np.int64))
    assert np.array_equal(t_ns[idx], ins["time_startup_ns"].astype(np.int64))
    assert len(ins) >= len(t_ns) - 2  # the last packet may still be on the wire
    assert np.array_equal(ins["ypr_deg"], ypr[idx].astype(np.float32))
    assert np.array_equal(ins["angular_rate_frd_rad_s"], rates[idx].astype(np.float32))
    assert np.array_equal(ins["accel_frd_m_s2"], acc[idx].astype(np.float32))


def _truth_at(z, t: np.ndarray, key: str) -> np.ndarray:
    a = z[key]
    a = a[:, None] if a.ndim == 1 else a
    return np.column_stack([np.interp(t, z["t_s"], a[:, j]) for j in range(a.shape[1])])


def _rms(x: np.ndarray) -> np.ndarray:
    return np.sqrt(np.mean(np.square(x), axis=0))


def _noise(scenario_name: str):
    """Expected RMS of the VN200's errors per axis from the configured noise: white noise
    (density x sqrt(rate)) and the rotor vibration (sum of sine amplitudes^2 / 2)."""
    from hil_sim.world.scenario import load_scenario, vibration_for

    sc = effect_truth(load_scenario(scenario_name))
    vn = sc.sensors.vn200
    imu = vn.imu
    vib = vibration_for(sc.sensors)

    def total(density, a1, a2):
        white = density * np.sqrt(vn.rate_hz)
        return np.sqrt(white**2 + (np.square(a1) + np.square(a2)) / 2)

    gyro = total(imu.gyro_noise_density_rad_s_rthz, vib.gyro_1p_rad_s, vib.gyro_2p_rad_s)
    acc = total(imu.accel_noise_density_m_s2_rthz, vib.accel_1p_m_s2, vib.accel_2p_m_s2)
    att = np.radians(np.asarray(vn.attitude_error_deg, float))  # (roll, pitch, yaw) sigma
    return sc, gyro, acc, att


def test_exported_flight_table_matches_the_truth_within_sensor_noise(clean_flight):
    # the exported table on the simulator's timeline, against the truth at the same times:
    # each channel's RMS error within what its configured noise (and the frames' known
    # transport delay, a few ms) allows
    df, meta, extra = load_export(clean_flight)
    t = sim_time(df["t_s"].to_numpy(), meta, extra)
    assert t[0] < 0.1 and t[-1] > CLEAN_S - 0.2 and len(df) > 140 * CLEAN_S
    # the boards boot at t = 0 with the rotor already turning: the rover's first rotor
    # speed comes with the second blade pulse (~20 ms); score from 0.2 s on
    df, t = df[t > 0.2], t[t > 0.2]
    sc, gyro, acc, att = _noise("still_air_calibration")
    delay_s = 0.5e-3  # what the clock fit leaves (the declared stamp latencies removed)
    with np.load(clean_flight / "truth.npz") as z:
        tr = {k: _truth_at(z, t, k) for k in ("euler_rad", "rates_rad_s",
                                              "imu_specific_force_m_s2",
                                              "rotor_speed_rad_s", "applied_rad")}
        rate_dot = np.gradient(z["rates_rad_s"], z["t_s"], axis=0)
        cmd_dot = np.gradient(z["applied_rad"], z["t_s"], axis=0)
    report = {}

    def check(name, diff, tol):
        err = _rms(diff)
        report[name] = (np.round(err, 5).tolist(), np.round(tol, 5).tolist())
        assert np.all(err <= tol), (name, err, tol)

    euler = df[["roll_rad", "pitch_rad", "yaw_rad"]].to_numpy()
    d_euler = euler - tr["euler_rad"]
    d_euler[:, 2] = np.angle(np.exp(1j * d_euler[:, 2]))
    # Gauss-Markov attitude error: a 12 s flight sees ~one correlated draw: 3 sigma
    check("attitude", d_euler, 3 * att + 1e-4)
    timing = _rms(rate_dot) * delay_s
    check("rates", df[["p_rad_s", "q_rad_s", "r_rad_s"]].to_numpy() - tr["rates_rad_s"],
          1.5 * np.sqrt(gyro**2 + timing**2))
    check("specific force", df[["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]].to_numpy()
          - tr["imu_specific_force_m_s2"], 1.5 * acc + 0.01)
    # pilot inputs: 1 us PWM steps (2.8e-4 rad/us cyclic); each RC frame stamped at its
    # start, so no more than the clock fit's fraction of a millisecond behind the command
    gains = np.array([2.618e-4, 2.793e-4, 2.793e-4, 6.981e-4])
    cols = ["delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad"]
    check("pilot inputs", df[cols].to_numpy() - tr["applied_rad"],
          gains + _rms(cmd_dot) * delay_s + 1e-5)
    # rotor speed: 5 us tachometer jitter on ~20 ms blade intervals, 48 MHz capture
    omega = tr["rotor_speed_rad_s"][:, 0]
    interval = np.pi / np.mean(omega)
    check("rotor speed", df["rotor_speed_rad_s"].to_numpy()[:, None] - omega[:, None],
          np.array([2 * np.mean(omega) * 5e-6 * np.sqrt(2) / interval + 0.02]))
    (clean_flight / "truth_report.json").write_text(json.dumps(report))


def test_losa_tracks_the_marker_through_the_closed_led_loop(clean_flight):
    # marker LEDs (PWM) -> LOSA optics -> LOSA firmware peaks -> daemon triangulation and
    # intensity feedback -> marker: after its 5 s calibration the marker tracks, the
    # tracker's positions follow the lit LED to the centimetre at 2.5 m
    rec = open_recording(clean_flight / "rec")
    att = rec.table("/marker/marker_attitude").rows
    assert att["mode"][-1] == 3 and att["active_led"][-1] == 0  # tracking, LED 0
    cmds = rec.table("/host/marker_command").rows
    assert len(cmds) > 50 * (CLEAN_S - 1)
    assert cmds["pos_valid"][-50:].all()
    df, meta, extra = load_export(clean_flight)
    valid = df["tracker_valid"].to_numpy() > 0.5
    assert valid[-150:].all() and valid.sum() > 150 * 4
    t = sim_time(df["t_s"].to_numpy(), meta, extra)[valid]
    got = df[["tracker_pos_x_m", "tracker_pos_y_m", "tracker_pos_z_m"]].to_numpy()[valid]
    from hil_sim.sensors.losa import MARKER_LED_DIRECTIONS, LosaConfig
    from hil_sim.world.kinematics import rotate

    with np.load(clean_flight / "truth.npz") as z:
        centre = _truth_at(z, t, "marker_pos_tracker_m")
        quat = _truth_at(z, t, "marker_quat_tracker")
    led = centre + LosaConfig().led_radius_m * rotate(quat / np.linalg.norm(
        quat, axis=1, keepdims=True), MARKER_LED_DIRECTIONS[0])
    err = np.linalg.norm(got - led, axis=1)
    assert np.sqrt(np.mean(err**2)) < 0.02 and np.percentile(err, 95) < 0.04, err


def test_host_clock_is_the_simulator_clock_and_board_times_map_onto_it(clean_flight):
    # stepped: the daemon's host time = offset + simulator time, so the export's clock fit
    # puts every INS row at the instant the rover parsed its packet (VN200 sample + 0.5 ms
    # latency + 88 bytes at 921600 baud: the rover stamps a packet when its last byte is
    # in), through the rover's crystal error and the base's forwarding, and the export
    # then removes those 1.455 ms the rover declares: each row at its VN200 sample instant,
    # to a fraction of a millisecond
    s = summary(clean_flight)
    df, meta, extra = load_export(clean_flight)
    assert s["clock"]["host"] == "simulator"
    t = sim_time(df["t_s"].to_numpy(), meta, extra)
    assert abs((t[-1] - t[0]) - (CLEAN_S - 1 / 150)) < 0.05
    with np.load(clean_flight / "truth.npz") as z:
        vn_t = z["vn_t_s"]
    k = np.clip(np.searchsorted(vn_t, t), 1, vn_t.size - 1)
    nearest = np.where(np.abs(vn_t[k - 1] - t) < np.abs(vn_t[k] - t), k - 1, k)
    err_ms = (t - vn_t[nearest]) * 1e3
    (epoch,) = meta["clock"]["rover"]["epochs"]
    assert abs(np.median(err_ms)) < 0.3, np.percentile(err_ms, [0, 50, 100])
    assert np.max(np.abs(err_ms)) < 0.5, (epoch, np.percentile(err_ms, [0, 50, 100]))
    for board, c in meta["clock"].items():
        (epoch,) = c["epochs"]
        assert epoch["two_sided"] and epoch["bound_ms"] < 10.0, (board, epoch)
