"""Native boards on the sim channel (hil_sim/boards/channel.py, docs/sim-channel.md).

Each test starts the ASan/UBSan build of a real board, drives it in stepped mode and
decodes what it sent with the host's decoder (airwake.link) — the plumbing the SIL
runs on. Simulated time only: nothing here depends on the machine's speed.
"""

from __future__ import annotations

import re
import struct
import subprocess
from binascii import crc_hqx
from pathlib import Path

import numpy as np
import pytest
from airwake.link.decoder import StreamDecoder
from airwake.link.framing import encode_frame, flags_for
from airwake.link.messages import BY_ID

from hil_sim.boards import channel
from hil_sim.boards.channel import NativeBoard, RawPty

REPO = Path(__file__).resolve().parents[2]
FRAME_PERIOD_US = 3125  # LOSA_FRAME_PERIOD_US, 320 Hz


def by_name(name: str):
    return next(m for m in BY_ID.values() if m.name == name)


def decode(data: bytes):
    dec = StreamDecoder()
    frames = dec.feed(data)
    return frames, dec


def gaussian_rate(centre_px: float, peak_counts_per_us: float, sigma_px: float = 1.6):
    x = np.arange(channel.PIXELS)
    return peak_counts_per_us * np.exp(-0.5 * ((x - centre_px) / sigma_px) ** 2)


def run_losa(board: NativeBoard, seconds: float, rates, dark=40.0, step_us=10_000) -> bytes:
    out = bytearray()
    for k in range(int(seconds * 1e6) // step_us):
        t = board.now_us
        if k == 0:
            for s, rate in enumerate(rates):
                board.line(t, s, rate, dark)
        out += board.advance(t + step_us).uart.get("host", b"")
    return bytes(out)


# ---- the channel contract: one definition in C, mirrored in Python ----

def test_channel_constants_match_the_c_headers():
    # channel.py mirrors sim_proto.h and hal.h; a drift would mis-route every record
    proto = (REPO / "firmware/hal/native/sim_proto.h").read_text()
    defines = {name: int(value, 16)
               for name, value in re.findall(r"#define (SIM_\w+) (0x[0-9A-Fa-f]+)u", proto)}
    for name in ("ADVANCE", "LINE", "IMU", "EDGE", "UART", "RESET", "HELLO", "IDLE", "PWM",
                 "UART_TX", "BOOT", "MAGIC"):
        assert getattr(channel, name) == defines[f"SIM_{name}"], name
    assert channel.MAX_PACKET == int(re.search(r"SIM_MAX_PACKET (\d+)u", proto)[1])
    assert channel.HEADER.size == int(re.search(r"SIM_HEADER_LEN (\d+)u", proto)[1])
    hal = (REPO / "firmware/hal/hal.h").read_text()

    def enum(prefix):
        return [m.lower() for m in re.findall(rf"HAL_{prefix}_(\w+) = \d+", hal)]

    assert tuple(enum("PORT")) == channel.PORTS
    assert tuple(enum("CAPTURE")) == channel.CAPTURES
    assert tuple(enum("PWM")) == channel.PWMS


def test_board_says_hello_with_its_name_and_mode():
    with NativeBoard("rover", flavour="asan") as board:
        assert board.hello == channel.Hello("rover", 3, "stepped", 0)


# ---- LOSA: irradiance in, peaks out ----

def test_losa_peaks_come_at_320_hz_where_the_light_falls():
    truth = (20.3, 47.75, 64.0, 101.6)
    with NativeBoard("losa", ports={"host": "sim"}, flavour="asan") as board:
        data = run_losa(board, 1.0, [gaussian_rate(c, 1.5) for c in truth])
    frames, dec = decode(data)
    assert dec.counters()["errors"]["crc_error"] == 0
    peaks = [f for f in frames if f.name == "losa_peaks"]
    times = np.array([f.board_time_us for f in peaks])
    assert set(np.diff(times)) == {FRAME_PERIOD_US}
    assert len(peaks) >= 280  # 1 s minus the ~110 ms IMU start-up
    for f in peaks:
        assert np.all(np.abs(np.array(f.msg.peak_px) - truth) < 0.1)
        assert all(flag & 1 for flag in f.msg.sensor_flags)


def test_same_inputs_give_the_same_bytes():
    # stepped mode is deterministic: the SIL's results must not depend on scheduling
    rates = [gaussian_rate(30 + 20 * s, 0.8) for s in range(4)]
    outputs = []
    for _ in range(2):
        with NativeBoard("losa", ports={"host": "sim"}, flavour="asan") as board:
            outputs.append(run_losa(board, 0.5, rates, step_us=7_000))
    assert len(outputs[0]) > 5000 and outputs[0] == outputs[1]


def test_exposure_control_pulls_a_saturated_line_back_into_range():
    # the native TSL1401 integrates irradiance over the board's own exposure, so the
    # board's exposure control closes its loop through the model
    with NativeBoard("losa", ports={"host": "sim"}, flavour="asan") as board:
        data = run_losa(board, 0.6, [gaussian_rate(64.0, 20.0)] * 4)  # 20 counts/us
    peaks = [f for f in decode(data)[0] if f.name == "losa_peaks"]
    first, last = peaks[0].msg, peaks[-1].msg
    assert first.sensor_flags[0] & 2  # saturated at the initial 1 ms
    assert not last.sensor_flags[0] & 2
    assert last.exposure_us[0] < first.exposure_us[0]
    # the reported intensity scales with the exposure it reports (rate x exposure + dark)
    expected = 40 + 20.0 * last.exposure_us[0]
    assert abs(last.intensity_counts[0] - expected) <= 0.02 * expected + 2


def test_clock_drift_and_offset_shape_the_board_clock():
    # the host maps board clocks onto its own; the SIL must give it a real drift to map
    rates = [gaussian_rate(64.0, 1.0)] * 4
    with NativeBoard("losa", ports={"host": "sim"}, flavour="asan",
                     clock_drift_ppm=200.0, clock_offset_us=5_000_000) as board:
        data = run_losa(board, 2.0, rates)
    peaks = [f for f in decode(data)[0] if f.name == "losa_peaks"]
    t = np.array([f.board_time_us for f in peaks], dtype=np.int64)
    assert t[0] > 5_000_000
    # the board schedules frames on its own clock: 3125 board-us apart, whatever the drift
    assert set(np.diff(t)) == {FRAME_PERIOD_US}
    # ... so in simulator time they come 3125 / (1 + 200e-6) apart: count them over 2 s
    sim_span_us = (len(peaks) - 1) * FRAME_PERIOD_US / (1 + 200e-6)
    assert sim_span_us < 2_000_000


def test_host_port_on_a_pty_carries_decodable_frames():
    pty = RawPty()
    try:
        with NativeBoard("losa", ports={"host": pty.path}, flavour="asan") as board:
            data = bytearray()
            for k in range(50):
                board.advance((k + 1) * 10_000)
                data += pty.read()
        frames, dec = decode(bytes(data))
    finally:
        pty.close()
    names = {f.name for f in frames}
    assert {"heartbeat", "schema_entry", "imu", "losa_peaks"} <= names
    assert sum(dec.counters()["errors"].values()) == 0


def test_host_frames_reach_the_board_and_time_sync_is_answered():
    req_msg = by_name("time_sync_request").record(request_id=9, host_time_us=42)
    with NativeBoard("losa", ports={"host": "sim"}, flavour="asan") as board:
        board.advance(200_000)
        board.uart(200_000, "host", encode_frame(req_msg, flags=flags_for(0)))
        out = board.advance(210_000)
    replies = [f for f in decode(out.uart["host"])[0] if f.name == "time_sync_reply"]
    assert len(replies) == 1
    r = replies[0].msg
    assert r.request_id == 9 and r.host_time_us == 42
    assert 200_000 <= r.board_rx_time_us <= r.board_tx_time_us <= 210_000


def test_a_throttled_link_drops_whole_frames_and_counts_them():
    # 320 Hz peaks do not fit 115200 baud: the board must drop frames whole and say so
    rates = [gaussian_rate(64.0, 1.0)] * 4
    with NativeBoard("losa", ports={"host": "sim@115200"}, flavour="asan") as board:
        out = bytearray()
        for k in range(300):
            if k == 0:
                for s in range(4):
                    board.line(0, s, rates[s], 40.0)
            res = board.advance((k + 1) * 10_000)
            for _, _, data in res.uart_records:
                out += data
    frames, dec = decode(bytes(out))
    assert len(out) <= 11_520 * 3.0 + 64  # 3 s at 115200 baud, 10 bits per byte
    errors = dec.counters()["errors"]
    assert sum(v for k, v in errors.items() if k != "seq_lost") == 0  # no torn frames
    beats = [f.msg for f in frames if f.name == "heartbeat"]
    assert beats[-1].tx_bytes_dropped > 0
    assert errors["seq_lost"] > 0  # the host sees the gaps


def test_reset_pin_reboots_the_board_and_the_host_sees_it():
    with NativeBoard("losa", ports={"host": "sim"}, flavour="asan") as board:
        first = board.advance(300_000)
        board.reset(300_000)
        second = board.advance(700_000)
    assert first.boots == [(0, "power_on", 0)]
    assert second.boots == [(300_000, "external", 1)]
    beats = [f.msg for f in decode(first.uart["host"] + second.uart["host"])[0]
             if f.name == "heartbeat"]
    assert beats[0].reset_cause == 0 and beats[-1].reset_cause == 4  # power_on, pin
    assert beats[-1].boot_count == beats[0].boot_count + 1
    assert beats[-1].uptime_ms < 400  # the board clock restarted at the reset


# ---- marker: IMU in, LEDs and attitude out ----

def test_marker_lights_one_led_at_a_time_and_reports_pwm_changes():
    with NativeBoard("marker", ports={"host": "sim"}, flavour="asan") as board:
        duty = {name: 0 for name in channel.PWMS}
        max_lit = 0
        data = bytearray()
        for k in range(300):  # 3 s: part of the 5 s calibration sweep
            t = k * 10_000
            for j in range(10):
                board.imu(t + 1000 * j, (0.0, 0.0, 0.0), (0.0, 0.0, -9.81), (20.0, 0.0, 40.0))
            out = board.advance(t + 10_000)
            data += out.uart.get("host", b"")
            for _, name, value in out.pwm:
                duty[name] = value
                max_lit = max(max_lit, sum(v > 0 for v in duty.values()))
    assert max_lit == 1
    frames = decode(bytes(data))[0]
    att = [f for f in frames if f.name == "marker_attitude"]
    assert 345 <= len(att) <= 350  # 120 Hz over 3 s minus the 110 ms IMU start-up
    assert att[-1].msg.mode == 2  # calibrate_leds


# ---- rover / base: peers on sim ports ----

def vn200_packet(t_ns: int, yaw_deg: float) -> bytes:
    """VN200 binary output, group 1, mask 0x11E9 (the rover/base configuration)."""
    body = bytes([0x01]) + struct.pack("<H", 0x11E9) + struct.pack(
        "<Q3f3f3d3f3fH", t_ns, yaw_deg, 1.0, -2.0, 0.1, 0.2, 0.3, 47.5, 8.5, 410.0,
        1.0, 0.0, -0.5, 0.0, 0.0, -9.8, 0x0002)
    return b"\xfa" + body + struct.pack(">H", crc_hqx(body, 0))


def test_rover_forwards_vn200_packets_from_its_ins_port():
    with NativeBoard("rover", ports={"host": "sim", "ins": "sim"}, flavour="asan") as board:
        for k in range(150):
            board.uart(k * 6_667, "ins", vn200_packet(k * 1_000_000, float(k)))
        out = board.advance(1_000_000)
    ins = [f for f in decode(out.uart["host"])[0] if f.name == "ins"]
    assert len(ins) == 150
    assert [f.msg.ypr_deg[0] for f in ins] == [float(k) for k in range(150)]
    assert ins[0].msg.lat_deg == 47.5 and ins[0].origin == 3


def test_base_forwards_rover_frames_unchanged_between_its_own():
    rover_frames = [encode_frame(by_name("rotor_speed").record(
        rotor_speed_rad_s=150.0, pulse_interval_us=10_000, pulse_count=k, rejected_pulses=0),
        seq=k % 256, flags=flags_for(3), board_time_us=k * 1000) for k in range(400)]
    with NativeBoard("base", ports={"host": "sim", "rover": "sim"}, flavour="asan") as board:
        stream = b"".join(rover_frames)
        for i in range(0, len(stream), 333):  # XBee-sized chunks
            board.uart(i * 50, "rover", stream[i:i + 333])
        out = board.advance(1_200_000)
    host = out.uart["host"]
    assert all(f in host for f in rover_frames)
    frames, dec = decode(host)
    assert sum(dec.counters()["errors"].values()) == 0
    assert [f.msg.pulse_count for f in frames if f.origin == 3] == list(range(400))
    assert {f.name for f in frames if f.origin == 4} >= {"heartbeat", "pilot_inputs"}


def test_base_measures_rc_pulses_from_edges():
    widths = (1100, 1300, 1500, 1700, 1900)
    with NativeBoard("base", ports={"host": "sim"}, flavour="asan") as board:
        for frame in range(50):
            t = frame * 20_000
            for c, w in enumerate(widths):
                board.edge(t + 2_500 * c, f"rc{c + 1}", 1)
                board.edge(t + 2_500 * c + w, f"rc{c + 1}", 0)
        out = board.advance(1_000_000)
    pilot = [f.msg for f in decode(out.uart["host"])[0] if f.name == "pilot_inputs"]
    assert 48 <= len(pilot) <= 51
    assert pilot[-1].valid_mask == 0x1F and tuple(pilot[-1].pwm_us) == widths


def test_advance_refuses_to_go_back_in_time():
    with NativeBoard("base", flavour="asan") as board:
        board.advance(10_000)
        with pytest.raises(ValueError):
            board.advance(5_000)
        board.imu(20_000, (0, 0, 0), (0, 0, 0))
        with pytest.raises(ValueError):
            board.advance(15_000)


def test_rover_answers_host_time_sync_through_the_base():
    # the host maps the rover's clock too: its requests cross the base to the rover and
    # the rover's reply comes back among the forwarded frames
    request = encode_frame(by_name("time_sync_request").record(request_id=31, host_time_us=7))
    with NativeBoard("base", ports={"host": "sim", "rover": "sim"}, flavour="asan") as base, \
            NativeBoard("rover", ports={"host": "sim"}, flavour="asan",
                        clock_offset_us=1_000_000) as rover:
        host = bytearray()
        for k in range(1, 60):  # the XBee link: one 5 ms step of latency each way
            t = k * 5_000
            if t == 100_000:
                base.uart(t, "host", request)
            to_rover = base.advance(t).uart
            host += to_rover.get("host", b"")
            if to_rover.get("rover"):
                rover.uart(t, "host", to_rover["rover"])
            from_rover = rover.advance(t).uart.get("host", b"")
            if from_rover:
                base.uart(t, "rover", from_rover)
        host += base.advance(300_000).uart.get("host", b"")
    replies = {f.origin: f.msg for f in decode(bytes(host))[0] if f.name == "time_sync_reply"}
    assert set(replies) == {3, 4}  # rover and base both answered request 31
    assert replies[3].request_id == replies[4].request_id == 31
    assert replies[3].board_rx_time_us > 1_000_000  # on the rover's own (offset) clock
    assert replies[4].board_rx_time_us < 200_000


def test_wall_mode_runs_on_the_monotonic_clock_and_talks_on_a_pty():
    # the wall-paced SIL: the board follows CLOCK_MONOTONIC, inputs apply when due
    pty = RawPty()
    try:
        with NativeBoard("losa", ports={"host": pty.path}, mode="wall", flavour="asan") as board:
            assert board.hello.mode == "wall"
            now = board.clock_us()
            for s in range(4):
                board.line(now, s, gaussian_rate(70.0, 1.0), 40.0)
            board.send()
            data = bytearray()
            deadline = now + 600_000
            while board.clock_us() < deadline:
                data += pty.read(timeout_s=0.05)
            out = board.poll()
    finally:
        pty.close()
    frames, dec = decode(bytes(data))
    assert sum(v for k, v in dec.counters()["errors"].items() if k != "seq_lost") == 0
    peaks = [f.msg for f in frames if f.name == "losa_peaks"]
    assert peaks and any(abs(p.peak_px[0] - 70.0) < 0.1 for p in peaks)
    assert out.boots == [] or out.boots[0][1] == "power_on"


def test_bad_command_line_is_one_clear_error_and_status_2():
    exe = channel.executable("losa", "asan")
    proc = subprocess.run([str(exe), "--port", "gps=/dev/null"], capture_output=True, text=True,
                          timeout=30)
    assert proc.returncode == 2
    assert "unknown role" in proc.stderr and "gps" in proc.stderr
    proc = subprocess.run([str(exe), "--stepped"], capture_output=True, text=True, timeout=30)
    assert proc.returncode == 2 and "--sim" in proc.stderr


def test_two_boards_stepped_together_send_what_they_send_one_after_the_other():
    # advance_begin/advance_end: the SIL runs boards whose steps are independent side by
    # side; the bytes must be those of plain advance(), step for step
    rates = [gaussian_rate(50.0 + 10 * s, 1.0) for s in range(4)]

    def fly(together: bool) -> list[bytes]:
        out = []
        with NativeBoard("losa", ports={"host": "sim"}, flavour="asan") as a, \
                NativeBoard("losa", ports={"host": "sim"}, flavour="asan") as b:
            for k in range(40):
                t1 = (k + 1) * 10_000
                if k == 0:
                    for s in range(4):
                        a.line(0, s, rates[s], 40.0)
                        b.line(0, s, rates[3 - s], 40.0)
                if together:
                    pa, pb = a.advance_begin(t1), b.advance_begin(t1)
                    ra, rb = a.advance_end(pa), b.advance_end(pb)
                else:
                    ra, rb = a.advance(t1), b.advance(t1)
                out += [ra.uart.get("host", b""), rb.uart.get("host", b"")]
            with pytest.raises(channel.ChannelError, match="in flight"):
                a.advance_begin(500_000)
                a.advance_begin(510_000)
        return out

    alone, together = fly(False), fly(True)
    assert together == alone and sum(map(len, alone)) > 1000
