"""LOSA slot tracking (slots.c) and the per-frame entry point (frame.c)."""

import ctypes as C

import awboards as A
import numpy as np
import peak_sim as S
from hypothesis import given, settings
from hypothesis import strategies as st


def raw_of(u: float) -> float:
    """Where an unwrapped position lands on the array: slots are 128 px apart."""
    return u - 128.0 * np.floor((u + 0.5) / 128.0)


@settings(max_examples=150, deadline=None)
@given(
    start=st.floats(0.0, 127.0),
    # <= 15 px a frame and <= 3 lost frames: < 64 px between valid peaks, anything
    # more is indistinguishable from a slot change (that is what the threshold means)
    steps=st.lists(st.floats(-15.0, 15.0), min_size=1, max_size=120),
    lost=st.lists(st.booleans(), min_size=120, max_size=120),
)
def test_slot_unwrapping_follows_any_smooth_path(lib, start, steps, lost):
    # Why: triangulation needs the unwrapped position; a wrong slot is a 128 px error.
    cfg = lib.losa_slot_default_cfg()
    state = A.LosaSlotState()
    lib.losa_slot_init(C.byref(state))
    slot, unwrapped = C.c_uint8(), C.c_float()
    u = start
    in_gap = 0
    for i, step in enumerate([0.0, *steps]):
        u = float(np.clip(u + step, -127.0, 254.0))  # three slots: [-128, 256)
        # short dropouts (up to 3 frames) while the peak moves on, as at the array ends
        invalid = lost[i % len(lost)] and in_gap < 3 and i > 0
        in_gap = in_gap + 1 if invalid else 0
        pk = A.LosaPeak(
            pos_px=raw_of(u), peak=500, background=40, flags=0 if invalid else A.LOSA_PEAK_VALID
        )
        lib.losa_slot_update(
            C.byref(state), C.byref(cfg), C.byref(pk), C.byref(slot), C.byref(unwrapped)
        )
        if not invalid:
            assert abs(unwrapped.value - u) < 1e-3, (i, u, unwrapped.value)
            assert slot.value == int(np.floor((u + 0.5) / 128.0)) + 1


def test_frame_tracks_peak_through_slot_change_with_noise(lib):
    # Why: at a slot change both ends of the array hold half a peak; the tracked
    # position must stay continuous, with the end peaks flagged.
    rng = np.random.default_rng(11)
    cfg = lib.losa_frame_default_cfg(10)
    state = A.LosaFrameState()
    lib.losa_frame_init(C.byref(state), C.byref(cfg), 400)
    lines = (A.U16LINE * 4)()
    out = (A.LosaSensorResult * 4)()
    sensor = S.Sensor(bits=10)
    centre_errs = []
    for u in np.arange(90.0, 170.0, 0.37):
        for s in range(4):
            r = raw_of(u + 3 * s)
            # the same image through two neighbouring slots, 128 px apart
            ideal = (
                S.ideal_line(r, 0.9) + S.ideal_line(r - 128.0, 0.9) + S.ideal_line(r + 128.0, 0.9)
            )
            signal = ideal * 0.4 + 0.04
            e = rng.poisson(signal * sensor.full_well_e)
            lines[s][:] = (
                np.clip(np.round(e / (sensor.full_well_e / 1023)), 0, 1023).astype(int).tolist()
            )
        lib.losa_frame_process(C.byref(state), C.byref(cfg), lines, out)
        for s in range(4):
            r = out[s]
            assert r.flags & A.LOSA_PEAK_VALID
            err = r.pos_px - (u + 3 * s)
            if r.flags & A.LOSA_PEAK_EDGE:
                assert abs(err) < 1.0
            else:
                centre_errs.append(err)
                assert r.slot == (1 if u + 3 * s < 127.5 else 2)
    assert np.sqrt(np.mean(np.square(centre_errs))) < 0.05
