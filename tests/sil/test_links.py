"""Link impairments counted exactly (`links.Impairment`) and the pty host ports."""

from __future__ import annotations

import errno
import os
import termios
import tty

import numpy as np
from airwake.link.decoder import StreamDecoder
from airwake.link.framing import encode_payload_frame
from airwake.link.messages import BY_NAME
from hypothesis import given, settings
from hypothesis import strategies as st

from hil_sim.boards.links import BASE_FORWARD_MAX, Impairment, PtyPort, frame_identity

NAMES = ("ins", "imu", "losa_peaks", "heartbeat", "tail_servo", "pilot_inputs")
BAD = ("crc_error", "cobs_error", "unknown_id", "def_mismatch", "oversize")


def make_frames(rng, n: int, origin: int) -> list[bytes]:
    out = []
    for i in range(n):
        info = BY_NAME[NAMES[rng.integers(len(NAMES))]]
        payload = rng.integers(0, 256, info.payload_size, dtype=np.uint8).tobytes()
        out.append(encode_payload_frame(info.id, payload, seq=i & 0xFF, flags=origin,
                                        board_time_us=int(rng.integers(0, 2**32))))
    return out


def chunks(rng, data: bytes, max_len: int):
    i = 0
    while i < len(data):
        k = int(rng.integers(1, max_len))
        yield data[i:i + k]
        i += k


def decode_all(data: bytes) -> tuple[StreamDecoder, set]:
    dec = StreamDecoder()
    got = set()
    for f in dec.feed(data):
        got.add((f.flags & 7, f.msg_id, f.seq, f.board_time_us))
    return dec, got


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), loss=st.sampled_from([0.0, 1e-3, 1e-2, 0.05]),
       flip=st.sampled_from([0.0, 1e-4, 1e-3, 1e-2]), max_chunk=st.integers(16, 600),
       outage=st.sampled_from([0.0, 0.02, 0.2]))
def test_receiver_errors_equal_the_bad_segments_counted_at_injection(seed, loss, flip,
                                                                       max_chunk, outage):
    # whatever is lost, flipped or cut, and however the stream is chunked: the receiver's
    # error count is the injector's bad-segment count, its frames the intact ones
    rng = np.random.default_rng(seed)
    imp = Impairment("x", loss_probability=loss, flip_probability=flip,
                     rng=np.random.default_rng(seed + 1), log_frames=True)
    out = bytearray()
    for c in chunks(rng, b"".join(make_frames(rng, 200, 3)), max_chunk):
        out += imp.feed(c, 0, bool(rng.random() < outage))
    dec, got = decode_all(bytes(out))
    c = imp.counters
    assert sum(dec.errors[k] for k in BAD) == c.bad_segments
    assert dec.frames_ok == c.frames_intact == len(imp.delivered)
    assert got == {i for _, i in imp.delivered}
    sent = {i for _, i, _ in imp.sent}
    touched = {i for _, i, t in imp.sent if t}
    assert sent - got <= touched  # nothing valid lost outside the corrupted spans
    assert c.bytes_in == c.bytes_out + c.bytes_lost + c.bytes_cut


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**31), n_resets=st.integers(0, 4))
def test_a_frame_cut_by_a_board_reset_is_counted_bad(seed, n_resets):
    # the board reboots while sending: the rest of that frame never leaves it
    rng = np.random.default_rng(seed)
    frames = make_frames(rng, 120, 1)
    cut_at = set(rng.choice(len(frames) - 1, size=n_resets, replace=False).tolist())
    imp = Impairment("x", rng=np.random.default_rng(seed))
    out = bytearray()
    for i, f in enumerate(frames):
        if i in cut_at:
            j = int(rng.integers(2, len(f) - 1))
            out += imp.feed(f[:j])
            imp.cut_open_segment()
        else:
            out += imp.feed(f)
    dec, _ = decode_all(bytes(out))
    assert sum(dec.errors[k] for k in BAD) == imp.counters.bad_segments == len(cut_at)
    assert dec.frames_ok == imp.counters.frames_intact == len(frames) - len(cut_at)
    assert imp.counters.reset_cuts == len(cut_at)


def forward_like_the_base(data: bytes, state: bytearray) -> bytes:
    """The base firmware's forwarder: each segment out as 0x00 seg 0x00, long ones in
    pieces of BASE_FORWARD_MAX (firmware/boards/base/board.c forward_rover)."""
    parts = (bytes(state) + data).split(b"\x00")
    out = bytearray()
    for seg in parts[:-1]:
        for i in range(0, len(seg), BASE_FORWARD_MAX):
            out += b"\x00" + seg[i:i + BASE_FORWARD_MAX] + b"\x00"
    tail = parts[-1]
    full = len(tail) - len(tail) % BASE_FORWARD_MAX
    for i in range(0, full, BASE_FORWARD_MAX):
        out += b"\x00" + tail[i:i + BASE_FORWARD_MAX] + b"\x00"
    state[:] = tail[full:]
    return bytes(out)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**31), base_loss=st.sampled_from([0.0, 1e-3, 2e-2]),
       outage=st.sampled_from([0.0, 0.05]))
def test_corruption_forwarded_by_the_base_is_counted_once(seed, base_loss, outage):
    # rover XBee link -> base forwarder -> base host link: the host's error count is the
    # base link's bad segments, those made upstream and passed on included
    rng = np.random.default_rng(seed)
    rover = Impairment("rover", loss_probability=0.02, flip_probability=2e-3,
                       rng=np.random.default_rng(seed + 1), piece_max=BASE_FORWARD_MAX)
    base = Impairment("base", loss_probability=base_loss, rng=np.random.default_rng(seed + 2),
                      upstream_bad=rover.bad_out)
    rover.publish_valid.append(base.valid)
    fwd = bytearray()
    state = bytearray()
    for c in chunks(rng, b"".join(make_frames(rng, 300, 3)), 300):
        fwd += forward_like_the_base(rover.feed(c), state)
    own = b"".join(make_frames(rng, 50, 4))
    out = bytearray()
    for c in chunks(rng, bytes(fwd) + own, 500):
        out += base.feed(c, 0, bool(rng.random() < outage))
    dec, _ = decode_all(bytes(out))
    assert sum(dec.errors[k] for k in BAD) == base.counters.bad_segments
    assert dec.frames_ok == base.counters.frames_intact
    assert rover.counters.bad_segments > 0


def test_frame_identity_reads_the_header():
    f = encode_payload_frame(BY_NAME["imu"].id, bytes(BY_NAME["imu"].payload_size), seq=9,
                             flags=2, board_time_us=123456)
    assert frame_identity(f.strip(b"\x00")) == (2, BY_NAME["imu"].id, 9, 123456)
    assert frame_identity(b"\x05\x01") is None


def _open_like_pyserial(path) -> int:
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
    tty.setraw(fd)
    return fd


def test_pty_port_is_raw_both_ways_behind_its_symlink(tmp_path):
    # a default pty turns CR into LF (and echoes): a binary link must pass every byte
    port = PtyPort(tmp_path / "base")
    try:
        assert (tmp_path / "base").is_symlink() and port.device.startswith("/dev/")
        host = _open_like_pyserial(tmp_path / "base")
        data = bytes(range(256)) + b"\r\n\r\x00\x11\x13"
        port.send(data)
        assert port.flush() == 0
        got = b""
        for _ in range(100):
            try:
                got += os.read(host, 4096)
            except BlockingIOError:
                pass
            if len(got) >= len(data):
                break
        assert got == data and port.unread() == 0
        os.write(host, b"\r\nhost\x00")
        back = b""
        for _ in range(100):
            back += port.receive()
            if len(back) >= 7:
                break
        assert back == b"\r\nhost\x00"
        os.close(host)
    finally:
        port.close()


def test_unplug_makes_the_host_read_fail_and_replug_brings_a_new_pty(tmp_path):
    # like a USB adapter pulled out: the open device errors, the path disappears; then a
    # new device appears behind the same path
    port = PtyPort(tmp_path / "losa")
    host = _open_like_pyserial(tmp_path / "losa")
    port.unplug()
    assert not (tmp_path / "losa").exists()
    try:
        gone = os.read(host, 10) == b""  # end of file ...
    except OSError as exc:
        gone = exc.errno == errno.EIO  # ... or an I/O error, as for a pulled USB adapter
    assert gone
    os.close(host)
    port.send(b"dropped while unplugged")
    assert not port.pending
    port.replug()
    try:
        host = _open_like_pyserial(tmp_path / "losa")
        port.send(b"\x00new\x00")
        port.flush()
        got = b""
        for _ in range(100):
            try:
                got += os.read(host, 100)
            except BlockingIOError:
                pass
            if got:
                break
        assert got == b"\x00new\x00" and port.replugs == 2
        assert termios.tcgetattr(port.master)[3] & termios.ECHO == 0
        os.close(host)
    finally:
        port.close()
