"""Faults from a scenario's [faults] table, injected on the SIL links (`fault_flight`).

Injected (conftest.FAULT_SCENARIO), 12 s, four boards: LOSA link byte loss 0.2 % and bit
flips 2e-4/bit, stalled 0.5 s at 7 s; marker link throttled to 57600 baud; rover XBee
link byte loss 0.1 % and flips 1e-4/bit; base pty unplugged at 4 s for 1 s; rover reset
at 6 s. Checked against the daemon's counters and the recording."""

from __future__ import annotations

import numpy as np
from airwake.record.reader import open_recording
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


def _events(s, kind):
    return [e for e in s["faults"]["events"] if e["kind"] == kind]


def test_faults_were_injected_as_configured_and_recorded_in_the_sidecar(fault_flight):
    # REC/sil/run.json says exactly what each link did
    s = summary(fault_flight)
    assert s["daemon_exit"] == 0 and all(c == 0 for c in s["board_exit"].values())  # no crash
    links = s["faults"]["links"]
    losa, rover, marker = links["losa"], links["rover"], links["marker"]
    assert losa["loss_probability"] == 0.002 and losa["flip_probability"] == 0.0002
    assert abs(losa["bytes_lost"] / losa["bytes_in"] - 0.002) < 0.001
    assert abs(losa["bits_flipped"] / (8 * losa["bytes_in"]) - 2e-4) < 1e-4
    assert rover["bytes_lost"] > 0 and rover["bits_flipped"] > 0
    assert marker["bytes_lost"] == marker["bits_flipped"] == marker["bad_segments"] == 0
    assert s["rig"]["host_baud"]["marker"] == 460800  # the fault, not the rig, throttles
    assert s["faults"]["config"]["boards"]["marker"]["throttle_baud"] == 57600
    (unplug,) = _events(s, "unplug")
    assert unplug["board"] == "base" and unplug["at_s"] == 4.0 and unplug["end_s"] == 5.0
    assert 5.0 <= unplug["reopened_s"] < 7.5  # the daemon's reopen backoff
    (stall,) = _events(s, "stall")
    assert stall["board"] == "losa" and (stall["at_s"], stall["end_s"]) == (7.0, 7.5)
    assert links["base"]["bytes_cut"] > 0 and links["losa"]["bytes_cut"] > 0
    (reset,) = _events(s, "reset")
    assert reset == {"kind": "reset", "board": "rover", "at_s": 6.0}
    assert {"board": "rover", "t_s": 6.0, "cause": "external", "boot_count": 1} in s["boots"]


def test_daemon_error_counters_match_the_injected_corruption_exactly(fault_flight):
    # every run of bytes the links corrupted (loss, flips, outage cuts, a frame cut by
    # the reset; the rover's through the base's forwarder) is one error at the daemon
    s = summary(fault_flight)
    st = s["daemon_status"]
    links = s["faults"]["links"]
    for port in ("losa", "marker", "base"):
        errors = st["ports"][port]["errors"]
        assert sum(errors[k] for k in BAD_KINDS) == links[port]["bad_segments"], (port, errors)
    assert links["losa"]["bad_segments"] > 20
    assert links["base"]["upstream_bad_in"] > 5  # rover XBee corruption, forwarded


def test_no_valid_frame_is_lost_outside_the_corrupted_spans(fault_flight):
    # the recording holds exactly the frames delivered intact; every frame a board sent
    # that is missing had a byte (or a delimiter next to it) impaired on its way
    logs = frame_logs(fault_flight)
    delivered = delivered_frames(logs)
    rec = open_recording(fault_flight / "rec")
    assert recorded_frames(rec) == delivered
    sent, touched = sent_frames(logs)
    lost = sent - delivered
    rover = logs["rover_sent"]
    in_flight = as_set(rover[rover[:, 0] >= 12e6 - 6000])  # still on the XBee at the end
    assert len(lost) > 50
    assert lost - in_flight <= touched, sorted(lost - touched - in_flight)[:5]


def test_throttled_link_drops_whole_frames_at_the_board(fault_flight):
    # 57600 baud cannot carry the marker's ~14 kB/s: the firmware drops whole frames
    # (counted in its heartbeat), the host sees no corruption, and the heartbeats, schema
    # entries and time-sync replies keep their room
    s = summary(fault_flight)
    st = s["daemon_status"]
    marker = st["boards"]["marker"]
    assert marker["board_counters"]["tx_bytes_dropped"] > 10_000
    assert sum(st["ports"]["marker"]["errors"][k] for k in BAD_KINDS) == 0
    rec = open_recording(fault_flight / "rec")
    att = rec.table("/marker/marker_attitude").rows
    rate = (len(att) - 1) / ((att["board_us"][-1] - att["board_us"][0]) / 1e6)
    assert 10 < rate < 100  # well below the nominal 120 Hz
    assert len(rec.table("/marker/heartbeat")) >= 11
    assert marker["clock"]["two_sided"]


def test_unplugged_port_is_reopened_and_the_recording_continues(fault_flight):
    # the base's pty destroyed for 1 s and recreated behind the same symlink: the daemon
    # reopens it, the base and the rover behind it come back, the exported table has a
    # gap of about the outage and rows on both sides
    s = summary(fault_flight)
    port = s["daemon_status"]["ports"]["base"]
    assert port["opens"] == 2 and port["losses"] == 1
    rec = open_recording(fault_flight / "rec")
    kinds = [m.json()["kind"] for m in rec.messages(["/daemon/events"])]
    assert kinds.count("port_lost") == 1 and kinds.count("port_open") == 4
    df, meta, extra = load_export(fault_flight)
    t = sim_time(df["t_s"].to_numpy(), meta, extra)
    (unplug,) = _events(s, "unplug")
    before, after = t[t < unplug["at_s"]], t[t > unplug["reopened_s"]]
    assert before.size > 140 * 3.5 and after.size > 140 * 4
    gap = after[0] - before[-1]
    assert unplug["reopened_s"] - unplug["at_s"] - 0.05 < gap < unplug["reopened_s"] \
        - unplug["at_s"] + 0.1, gap


def test_board_reset_starts_a_new_epoch_and_the_table_continues(fault_flight):
    # the rover reset at 6 s: new heartbeat boot count, a new clock epoch, sequence
    # numbers restart without false gaps, and its frames map onto the same timeline
    s = summary(fault_flight)
    rover = s["daemon_status"]["boards"]["rover"]
    assert rover["boot_count"] == 1 and rover["clock"]["epochs"] == 2
    df, meta, extra = load_export(fault_flight)
    epochs = meta["clock"]["rover"]["epochs"]
    assert [e["boot_count"] for e in epochs] == [0, 1]
    t = sim_time(df["t_s"].to_numpy(), meta, extra)
    after = t[t > 6.0]
    assert after.size > 140 * 5 and np.all(np.diff(t) > 0)
    # the rows after the reset are as close to the truth as before it
    with np.load(fault_flight / "truth.npz") as z:
        roll = np.interp(t, z["t_s"], z["euler_rad"][:, 0])
    err = np.abs(df["roll_rad"].to_numpy() - roll)
    assert err[t > 6.5].max() < 0.02 and err[(t > 0.5) & (t < 4)].max() < 0.02


def test_stalled_link_goes_quiet_and_comes_back(fault_flight):
    # the LOSA link delivers nothing for 0.5 s: no LOSA frames received in that span of
    # host time, the other boards are undisturbed, LOSA frames flow again after it
    s = summary(fault_flight)
    (stall,) = _events(s, "stall")
    rec = open_recording(fault_flight / "rec")
    meta = rec.metadata
    h0 = s["clock"]["host_offset_ns"]

    def rx_sim_s(topic):
        return (rec.table(topic).publish_ns - h0) / 1e9

    peaks = rx_sim_s("/losa/losa_peaks")
    inside = (peaks > stall["at_s"] + 0.011) & (peaks < stall["end_s"])
    assert not inside.any() and (peaks > stall["end_s"] + 0.1).sum() > 250 * 4
    marker = rx_sim_s("/marker/marker_attitude")
    quiet = np.diff(marker[(marker > stall["at_s"] - 0.5) & (marker < stall["end_s"] + 0.5)])
    assert quiet.max() < 0.15
    assert meta["format"].startswith("airwake-recording")
