"""Crash safety in SIL: the daemon killed with SIGKILL mid-flight (`crash_flight`: rover +
base, wall-paced, killed after 4 s). What a crash may cost, end to end: the writer's
chunk in progress (`record.recording.FLUSH_S`, 0.1 s), the bytes the daemon had not read
yet, and the export's edges (docs/daemon.md, "Crash safety"): at most LOSS_S."""

from __future__ import annotations

import json

import numpy as np
import pytest
from airwake.link.batch import decode_capture
from airwake.record.export import export_recording
from airwake.record.reader import open_recording

# a wall-paced flight timed against the wall clock: `make test` runs it alone, after the
# parallel suite, so CPU-heavy tests on the other worker cannot starve it
pytestmark = pytest.mark.wall_clock

LOSS_S = 0.5  # the promise: a crash costs at most the last half second of the flight
INS_HZ = 150.0
ROVER = 3  # origin id of the rover's frames (forwarded by the base)


def _kill_and_delivered(crash_flight):
    extra = json.loads((crash_flight / "extra.json").read_text())
    delivered = (crash_flight / "delivered-base.bin").read_bytes()
    return extra, delivered


def test_sigkill_leaves_a_recording_missing_at_most_the_last_half_second(crash_flight):
    # the recording opens (recovery path), and its raw bytes are exactly what the pty
    # delivered, up to at least everything delivered LOSS_S (wall) before the kill
    extra, delivered = _kill_and_delivered(crash_flight)
    kill_ns = extra["kill_ns"]
    rec = open_recording(crash_flight / "rec")
    assert not rec.complete and rec.summary is None
    last = rec.segments[-1]
    # recovery reads every whole record; a kill inside the writer's one write() per flush
    # could leave a torn tail, at most that flush's bytes (a few kB)
    assert 0 < last.recovered_bytes <= last.size < last.recovered_bytes + 64 * 1024, last
    raw = rec.raw("base").data
    assert delivered.startswith(raw)
    log = np.array(extra["delivered"]["base"], dtype=np.int64)  # (wall ns, bytes so far)
    due = log[log[:, 0] <= kill_ns - LOSS_S * 1e9, 1]
    assert due.size > 100
    assert len(raw) >= due[-1], (len(raw), due[-1], len(delivered))
    # the decoded frames are those of the raw bytes
    cap = decode_capture(raw)
    assert len(rec.table("/rover/ins")) == len(cap.tables["ins"][cap.tables["ins"]["origin"]
                                                                   == ROVER])


def test_sigkill_costs_the_flight_table_at_most_the_last_half_second(crash_flight):
    # the exported flight table of the killed recording ends within LOSS_S of the kill on
    # the flight's timeline, and every row before is there, in order, bit for bit
    extra, delivered = _kill_and_delivered(crash_flight)
    built = export_recording(open_recording(crash_flight / "rec"))
    df, meta = built.df, built.metadata
    assert meta["recording_complete"] is False
    t = df["t_s"].to_numpy()
    kill_s = (extra["kill_ns"] - meta["t0_monotonic_ns"]) / 1e9
    lost_s = kill_s - t[-1]
    assert 0.0 < lost_s <= LOSS_S, (lost_s, meta["trimmed"])
    # the export trims the tail only to where every required stream has data: within a
    # pilot-input period (50 Hz) of the last INS sample
    assert meta["trimmed"]["ins_end_s"] - meta["trimmed"]["end_s"] <= 0.021, meta["trimmed"]
    # nothing lost inside, no gaps, every required column finite
    assert meta["gaps"] == [] and meta["rows_dropped_in_gaps"] == 0
    dt = np.diff(t)
    assert dt.min() > 0 and dt.max() < 2.0 / INS_HZ, (dt.min(), dt.max())
    required = ["p_rad_s", "q_rad_s", "r_rad_s", "acc_x_m_s2", "roll_rad", "pdot_rad_s2",
                "pwm_ch1_us", "pwm_ch2_us", "pwm_ch3_us", "pwm_ch4_us", "rotor_speed_rad_s"]
    assert np.isfinite(df[required].to_numpy()).all()
    # the rows are consecutive rover INS samples exactly as the pty delivered them
    cap = decode_capture(delivered)
    ins = cap.tables["ins"][cap.tables["ins"]["origin"] == ROVER]
    sent = np.concatenate([ins["angular_rate_frd_rad_s"], ins["accel_frd_m_s2"],
                           ins["vel_ned_m_s"]], axis=1).astype(float)
    got = df[["p_rad_s", "q_rad_s", "r_rad_s", "acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2",
              "vel_n_m_s", "vel_e_m_s", "vel_d_m_s"]].to_numpy()
    first = np.flatnonzero((sent == got[0]).all(axis=1))
    assert first.size == 1
    i0 = int(first[0])
    assert i0 <= meta["trimmed"]["rows_dropped_head"] + 2
    assert np.array_equal(sent[i0:i0 + len(got)], got)
    # what the kill cost in samples agrees with the time: the INS frames delivered after
    # the table's last row span at most LOSS_S
    after = len(sent) - (i0 + len(got))
    assert 0 < after <= LOSS_S * INS_HZ + 2, after
    assert len(df) > INS_HZ * (kill_s - LOSS_S - 1.0)
