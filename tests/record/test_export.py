"""Export: a recording written with known board clocks and delays -> a flight table whose
host times and values are right (no ptys: the raw byte channels are written directly)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from airwake.cli import main
from airwake.daemon.fake_boards import BoardSim
from airwake.link.framing import encode_frame
from airwake.link.messages import TimeSyncReply
from airwake.record.export import export_recording
from airwake.record.flight_table import load_flight_table
from airwake.record.reader import open_recording
from airwake.record.recording import RecordingWriter

T0_NS = 7_000_000_000_000


def write_synthetic(directory, duration_s: float = 30.0, reboot_at_s: float | None = None,
                    seed: int = 0, lose_clock_frames_s: float = 0.0,
                    stamp_latency_us: dict | None = None):
    """The base port (base + forwarded rover) as the daemon would record it;
    `stamp_latency_us` {board: {message: us}}: stamps that much late, and declared."""
    rng = np.random.default_rng(seed)
    lat = stamp_latency_us or {}
    rover = BoardSim("rover", drift_ppm=80.0, clock_offset_us=(1 << 32) - 9_000_000,
                     stamp_latency_us=lat.get("rover"))
    base = BoardSim("base", drift_ppm=-40.0, clock_offset_us=12_000_000,
                    stamp_latency_us=lat.get("base"))
    start_us = T0_NS / 1000 + 200_000
    for sim in (rover, base):
        sim.boot(start_us)
    w = RecordingWriter(directory, {"start_monotonic_ns": T0_NS,
                                    "base_antenna_height_above_deck_m": 1.5})
    events = []  # (rx_us, bytes)
    t_us = start_us
    next_sync = start_us
    rebooted = False
    while t_us < start_us + duration_s * 1e6:
        if reboot_at_s is not None and not rebooted and t_us >= start_us + reboot_at_s * 1e6:
            rover.boot_count += 1
            rover.boot(t_us)
            rebooted = True
        chunk = b""
        for sim in (rover, base):
            for msg, board_us, is_data in sim.due(t_us):
                wire, _ = sim.frame(msg, board_us)
                if (rebooted and sim is rover and not is_data
                        and t_us < start_us + (reboot_at_s + lose_clock_frames_s) * 1e6):
                    continue  # the reset's heartbeat and schema entries lost on the radio
                chunk += wire
        if t_us >= next_sync:  # the host's request, answered by both boards
            next_sync += 500_000
            host_tx = t_us - 300.0
            for sim in (rover, base):
                b_rx = sim.board_us(t_us - 200.0 + rng.exponential(50.0))
                b_tx = sim.board_us(t_us)
                wire, _ = sim.frame(TimeSyncReply(1, int(host_tx), b_rx, b_tx), b_tx)
                chunk += wire
        if chunk:
            # delivered in reads of random size, each stamped with its receive time
            rx = t_us + 300.0 + rng.exponential(800.0)
            events.append((rx, chunk))
        t_us += 2000.0
    for rx, chunk in sorted(events, key=lambda e: e[0]):
        w.raw("/raw/base", int(rx * 1000), chunk)
    w.close({})
    return rover, base


def test_export_maps_board_times_onto_the_host_timeline(tmp_path):
    rover, base = write_synthetic(tmp_path / "rec")
    rec = open_recording(tmp_path / "rec")
    built = export_recording(rec)
    df = built.df
    # t_s of each row against the truth of the rover's clock (its INS stamps the rows)
    ins_t = (rover.boot_mono_us + np.arange(0, 30, 1 / 150) * 1e6 - T0_NS / 1000) / 1e6
    t = df["t_s"].to_numpy()
    i = np.clip(np.searchsorted(ins_t, t), 1, len(ins_t) - 1)
    err = np.minimum(np.abs(ins_t[i] - t), np.abs(ins_t[i - 1] - t))
    assert np.max(err) < 0.5e-3 and len(df) > 0.95 * 150 * 30
    clock = built.metadata["clock"]["rover"]["epochs"][0]
    assert clock["two_sided"] and abs(clock["drift_ppm"] - 80.0) < 5.0
    assert abs(built.metadata["clock"]["base"]["epochs"][0]["drift_ppm"] + 40.0) < 5.0
    # the deck offset from the recording's metadata: 1.5 - baseline_d (-3 m +- 0.1)
    h = df["height_agl_m"].to_numpy()
    known = np.isfinite(h)  # inf only after the last 10 Hz RTK epoch
    assert known.mean() > 0.98 and np.all((h[known] > 4.39) & (h[known] < 4.61))


def _ins_truth_s(rover, duration_s: float) -> np.ndarray:
    """The rover's INS sample instants on the table's timeline (s)."""
    return (rover.boot_mono_us + np.arange(0, duration_s, 1 / 150) * 1e6 - T0_NS / 1000) / 1e6


def _nearest_error_s(truth: np.ndarray, t: np.ndarray) -> np.ndarray:
    i = np.clip(np.searchsorted(truth, t), 1, len(truth) - 1)
    return np.where(np.abs(truth[i] - t) < np.abs(truth[i - 1] - t), truth[i] - t,
                    truth[i - 1] - t)


def test_export_removes_exactly_the_stamp_latencies_the_boards_declare(tmp_path):
    # Why: a board that stamps its INS rows at the packet's last byte makes every state
    # late against the pilot inputs, which the analysis reads as servo lag
    declared = {"rover": {"ins": 1455}, "base": {"pilot_inputs": 7000}}
    rover, _ = write_synthetic(tmp_path / "rec", duration_s=20.0, stamp_latency_us=declared)
    rec = open_recording(tmp_path / "rec")
    fixed = export_recording(rec)
    raw = export_recording(rec, remove_stamp_latency=False)
    truth = _ins_truth_s(rover, 20.0)
    err_fixed = _nearest_error_s(truth, fixed.df["t_s"].to_numpy())
    err_raw = _nearest_error_s(truth, raw.df["t_s"].to_numpy())
    assert np.max(np.abs(err_fixed)) < 0.5e-3
    assert abs(np.median(err_raw) + 1.455e-3) < 0.1e-3  # rows 1.455 ms late as stamped
    # the same clock fit, every row moved by exactly the declared latency (the pilot
    # inputs, moved by 7 ms, may cover one row less or more at the ends)
    n = min(len(fixed.df), len(raw.df))
    assert abs(len(fixed.df) - len(raw.df)) <= 1 and n > 0.95 * 150 * 20
    np.testing.assert_allclose(raw.df["t_s"].to_numpy()[:n] - fixed.df["t_s"].to_numpy()[:n],
                               1.455e-3, atol=1e-9)
    meta = fixed.metadata["stamp_latency"]
    assert meta == {"removed": True, "note": None, "streams": {
        "base/pilot_inputs": {"latency_ms": 7.0, "stamp_event": "peer_packet_end"},
        "rover/ins": {"latency_ms": 1.455, "stamp_event": "peer_packet_end"}}}
    assert raw.metadata["stamp_latency"]["removed"] is False
    assert "not removed" in raw.metadata["stamp_latency"]["note"]


def test_remove_latencies_shifts_each_declared_stream_and_nothing_else():
    from airwake.link.messages import BY_NAME
    from airwake.record.flight_builder import message_table
    from airwake.record.latency import declared_latencies, remove_latencies

    t = np.arange(0.0, 2.0, 0.02)
    streams = {
        "base/pilot_inputs": message_table("pilot_inputs", t, valid_mask=0x1F),
        "rover/ins": message_table("ins", t),
        "rover/rotor_speed": message_table("rotor_speed", t),
        "rover/stamp_latency": message_table(
            "stamp_latency", [0.5, 1.5], msg_id=BY_NAME["ins"].id, latency_us=[1400, 1455],
            stamp_event=1, entry_count=1),
        "base/stamp_latency": message_table(
            "stamp_latency", [0.5], msg_id=BY_NAME["pilot_inputs"].id, latency_us=250,
            stamp_event=2, entry_count=2),
    }
    declared = declared_latencies(streams)
    assert set(declared) == {"rover/ins", "base/pilot_inputs"}
    assert declared["rover/ins"].latency_us == 1455  # the latest declaration
    assert declared["rover/ins"].values_us == (1400, 1455)
    assert declared["base/pilot_inputs"].stamp_event == "rc_frame_start"
    out = remove_latencies(streams, declared)
    np.testing.assert_array_equal(out["rover/ins"].t_s, t - 1455e-6)
    np.testing.assert_array_equal(out["base/pilot_inputs"].t_s, t - 250e-6)
    assert out["rover/rotor_speed"] is streams["rover/rotor_speed"]
    assert out["rover/ins"].data is streams["rover/ins"].data


def test_export_of_a_recording_without_declarations_is_unchanged_with_a_note(tmp_path,
                                                                            capsys):
    # recordings from boards that declared nothing export as they always did
    write_synthetic(tmp_path / "rec", duration_s=12.0)
    rec = open_recording(tmp_path / "rec")
    a = export_recording(rec)
    b = export_recording(rec, remove_stamp_latency=False)
    np.testing.assert_array_equal(a.df["t_s"], b.df["t_s"])
    assert a.metadata["stamp_latency"]["removed"] is False
    assert a.metadata["stamp_latency"]["streams"] == {}
    assert main(["export", str(tmp_path / "rec"), "--out", str(tmp_path / "f.csv")]) == 0
    notes = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("note:")]
    assert len(notes) == 1 and "no stamp_latency frames" in notes[0]


def test_export_command_can_keep_the_boards_stamps(tmp_path, capsys):
    write_synthetic(tmp_path / "rec", duration_s=12.0,
                    stamp_latency_us={"rover": {"ins": 2000}})
    for flag, removed in (([], True), (["--no-latency-correction"], False)):
        out = tmp_path / f"f{len(flag)}.parquet"
        assert main(["export", str(tmp_path / "rec"), "--out", str(out), *flag]) == 0
        meta = load_flight_table(out).metadata["stamp_latency"]
        assert meta["removed"] is removed
        assert meta["streams"]["rover/ins"]["latency_ms"] == 2.0
    assert "--no-latency-correction" in capsys.readouterr().out


def test_export_across_a_rover_reset(tmp_path):
    # the rover resets at 20 s and its first heartbeat/schema entries are lost: the data
    # frames before its next clock frame cannot be placed and are dropped, not misplaced
    rover, _ = write_synthetic(tmp_path / "rec", duration_s=40.0, reboot_at_s=20.0,
                               lose_clock_frames_s=0.3)
    built = export_recording(open_recording(tmp_path / "rec"))
    clock = built.metadata["clock"]["rover"]
    assert len(clock["epochs"]) == 2 and "went back" in clock["epochs"][1]["reason"]
    assert clock["frames_dropped_implausible_time"] >= 5  # until a sync reply anchors the run
    t = built.df["t_s"].to_numpy()
    assert np.all(np.diff(t) > 0) and t[-1] - t[0] > 38.0
    # rows are where the rover's INS really was: compare with the truth of both runs
    truth = np.concatenate([(rover.boot_mono_us - 20e6 + np.arange(0, 20, 1 / 150) * 1e6),
                            (rover.boot_mono_us + np.arange(0, 20, 1 / 150) * 1e6)])
    truth = (truth - T0_NS / 1000) / 1e6
    i = np.clip(np.searchsorted(truth, t), 1, len(truth) - 1)
    err = np.minimum(np.abs(truth[i] - t), np.abs(truth[i - 1] - t))
    assert np.max(err) < 1e-3
    assert len(built.metadata["gaps"]) <= 1


@pytest.mark.parametrize("ext", ["parquet", "csv"])
def test_export_command_writes_a_loadable_table(tmp_path, ext, capsys):
    write_synthetic(tmp_path / "rec", duration_s=12.0)
    out = tmp_path / f"flight.{ext}"
    assert main(["export", str(tmp_path / "rec"), "--out", str(out),
                 "--base-antenna-height-m", "0.5"]) == 0
    ft = load_flight_table(out)
    assert ft.metadata["source"] == "recorder"
    assert ft.metadata["builder"]["base_antenna_height_above_deck_m"] == 0.5
    assert math.isclose(ft.metadata["rate_hz"], 150.0, rel_tol=0.01)
    assert "rows at" in capsys.readouterr().out


def test_export_without_rover_is_a_clear_error(tmp_path, capsys):
    w = RecordingWriter(tmp_path / "rec", {})
    base = BoardSim("base")
    wire, _ = base.frame(base.heartbeat(0), 0)
    w.raw("/raw/base", 1, wire)
    w.close({})
    assert main(["export", str(tmp_path / "rec"), "--out", str(tmp_path / "f.csv")]) == 2
    assert "no rover INS" in capsys.readouterr().err


def test_recording_info_and_recover_commands(tmp_path, capsys):
    write_synthetic(tmp_path / "rec", duration_s=3.0)
    assert main(["recording", "info", str(tmp_path / "rec")]) == 0
    assert "/raw/base" in capsys.readouterr().out
    assert main(["recording", "recover", str(tmp_path / "rec"), "--out",
                 str(tmp_path / "copy")]) == 0
    assert open_recording(tmp_path / "copy").complete
    assert main(["recording", "info", str(tmp_path / "missing")]) == 2
    assert "not found" in capsys.readouterr().err


def test_encode_frame_round_trip_sanity():
    # the synthetic writer relies on encode_frame producing delimited frames
    wire = encode_frame(TimeSyncReply(1, 2, 3, 4), 0, 3, 4)
    assert wire[0] == 0 and wire[-1] == 0 and 0 not in wire[1:-1]
