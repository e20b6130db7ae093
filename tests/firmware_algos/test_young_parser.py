"""The marker's Young 81000 line parser (firmware/boards/marker/young81000.c) against
the simulator's anemometer stream and its reference decoder: every line of the
simulated serial output comes out with the same numbers (W negated to z down), in any
chunking, and garbage between lines costs only the lines it touches."""

from __future__ import annotations

import ctypes as C

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from hil_sim.sensors.anemometer import parse_ascii_lines

LINE_MAX = 64


class YoungSample(C.Structure):
    _fields_ = [("uvw_m_s", C.c_float * 3), ("temp_c", C.c_float), ("status", C.c_uint8),
                ("t_us", C.c_uint64)]


class YoungParser(C.Structure):
    _fields_ = [("line", C.c_char * (LINE_MAX + 1)), ("len", C.c_uint8),
                ("overflow", C.c_bool), ("line_t_us", C.c_uint64), ("lines_ok", C.c_uint32),
                ("lines_bad", C.c_uint32), ("bytes", C.c_uint32)]


def _parser(lib):
    lib.young_init.argtypes = [C.POINTER(YoungParser)]
    lib.young_feed.restype = C.c_size_t
    lib.young_feed.argtypes = [C.POINTER(YoungParser), C.c_char_p, C.c_size_t, C.c_uint64,
                               C.POINTER(YoungSample), C.c_size_t, C.POINTER(C.c_size_t)]
    p = YoungParser()
    lib.young_init(C.byref(p))
    return p


def _feed_all(lib, p, chunks):
    """Samples (K, 4: u, v, w_down, T) and their stamps from the chunks (t = chunk index)."""
    out, stamps = [], []
    buf = (YoungSample * 8)()
    for t, chunk in enumerate(chunks):
        off = 0
        while off < len(chunk):
            used = C.c_size_t(0)
            n = lib.young_feed(C.byref(p), chunk[off:], len(chunk) - off, t, buf, 8,
                               C.byref(used))
            off += used.value
            for s in buf[:n]:
                out.append([*s.uvw_m_s, s.temp_c])
                stamps.append(s.t_us)
    return np.asarray(out, dtype=float).reshape(-1, 4), stamps


def _lines(values) -> bytes:
    return b"".join(f"{u:7.2f} {v:7.2f} {w:7.2f} {tc:7.2f}\r\n".encode()
                    for u, v, w, tc in values)


wind = st.floats(-40.0, 40.0, allow_nan=False)
rows = st.lists(st.tuples(wind, wind, wind, st.floats(-30.0, 50.0)), min_size=1, max_size=30)


@settings(max_examples=60, deadline=None)
@given(rows, st.lists(st.integers(1, 40), min_size=1, max_size=50))
def test_every_line_decodes_as_the_reference_in_any_chunking(lib, values, cuts):
    data = _lines(values)
    chunks, pos, k = [], 0, 0
    while pos < len(data):
        n = cuts[k % len(cuts)]
        chunks.append(data[pos:pos + n])
        pos += n
        k += 1
    got, stamps = _feed_all(lib, _parser(lib), chunks)
    ref = parse_ascii_lines(data) * np.array([1.0, 1.0, -1.0, 1.0])
    assert got.shape == ref.shape
    np.testing.assert_allclose(got, ref, atol=1e-5, rtol=1e-6)
    # each sample is stamped with the chunk that held its line's first byte
    starts = np.cumsum([0] + [len(c) for c in chunks])
    line_starts = [0] + [i + 1 for i, b in enumerate(data) if b == ord("\n")][:-1]
    expect = [int(np.searchsorted(starts, s, side="right") - 1) for s in line_starts]
    assert stamps == expect


@settings(max_examples=60, deadline=None)
@given(rows, st.binary(min_size=1, max_size=80), st.integers(0, 29))
def test_garbage_costs_only_the_lines_it_touches(lib, values, garbage, where):
    where = min(where, len(values))
    good = _lines(values)
    lines = good.split(b"\r\n")[:-1]
    data = b"".join(l + b"\r\n" for l in lines[:where]) + garbage + b"\r\n" + \
        b"".join(l + b"\r\n" for l in lines[where:])
    p = _parser(lib)
    got, _ = _feed_all(lib, p, [data])
    ref = parse_ascii_lines(good) * np.array([1.0, 1.0, -1.0, 1.0])
    # every good line comes out (the garbage's own lines may, if they happen to be valid)
    kept = ref.tolist()
    assert len(got) >= len(kept)
    missing = [r for r in kept if not np.any(np.all(np.abs(got - r) < 1e-5, axis=1))]
    assert not missing
    assert p.lines_ok == len(got)


def test_simulated_anemometer_stream_round_trips(lib):
    from hil_sim.sensors.anemometer import Anemometer
    from hil_sim.world.kinematics import Trajectory

    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 2.0, 401)
    traj = Trajectory.from_states(t, np.zeros((t.size, 3)), np.zeros((t.size, 3)),
                                  np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1)),
                                  np.zeros((t.size, 3)))

    class Uniform:
        def velocity_ned(self, tt, pos):
            return np.tile([3.0, -1.0, 0.5], (len(tt), 1))

    dev = Anemometer(rng=rng)
    s = dev.measure(traj, Uniform())
    stream = dev.ascii_stream(s)
    got, _ = _feed_all(lib, _parser(lib), [bytes(stream.data)])
    assert got.shape == (len(s), 4)
    np.testing.assert_allclose(got[:, :3], s.wind_sensor_m_s, atol=6e-3)
    np.testing.assert_allclose(got[:, 3], s.sonic_temperature_c, atol=6e-3)
