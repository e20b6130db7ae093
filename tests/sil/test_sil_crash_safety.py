"""Crash safety in SIL: the daemon killed with SIGKILL mid-flight (`crash_flight`: rover +
base, wall-paced, killed after 4 s)."""

from __future__ import annotations

import json

import numpy as np
from airwake.link.batch import decode_capture
from airwake.record.export import export_recording
from airwake.record.reader import open_recording


def test_sigkill_leaves_a_recording_missing_at_most_the_last_second(crash_flight):
    # the recording opens (recovery path), and its raw bytes are exactly what the pty
    # delivered, up to at least everything delivered 1 s (wall) before the kill
    extra = json.loads((crash_flight / "extra.json").read_text())
    kill_ns = extra["kill_ns"]
    rec = open_recording(crash_flight / "rec")
    assert not rec.complete and rec.summary is None
    assert rec.segments[-1].recovered_bytes > 0
    delivered = (crash_flight / "delivered-base.bin").read_bytes()
    raw = rec.raw("base").data
    assert delivered.startswith(raw)
    log = np.array(extra["delivered"]["base"], dtype=np.int64)  # (wall ns, bytes so far)
    due = log[log[:, 0] <= kill_ns - 1_000_000_000, 1]
    assert due.size > 100
    assert len(raw) >= due[-1], (len(raw), due[-1], len(delivered))
    # the decoded frames are those of the raw bytes, and the flight exports up to there
    cap = decode_capture(raw)
    assert len(rec.table("/rover/ins")) == len(cap.tables["ins"][cap.tables["ins"]["origin"]
                                                                   == 3])
    built = export_recording(rec)
    assert built.metadata["recording_complete"] is False
    assert len(built.df) > 140 * 2.5
