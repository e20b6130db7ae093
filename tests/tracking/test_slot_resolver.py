"""LOSA slot re-acquisition (`losa.SlotResolver`, `PoseEkf.candidate_nis`): a marker the
firmware picks up off-centre is unwrapped from the wrong slot (it assumes the central
one, firmware/boards/losa/slots.h) and triangulates metres away; the filter's prediction
picks the right slots back, and the correction holds for the frames after."""

from __future__ import annotations

import numpy as np
from airwake.tracking.losa import (
    DEFAULT_GEOMETRY,
    WIRE_PIXELS,
    SlotResolver,
    triangulate,
)
from airwake.tracking.pose_ekf import PoseEkf
from hypothesis import given, settings
from hypothesis import strategies as st

G = DEFAULT_GEOMETRY


def wire_peaks(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(unwrapped peak_px (4,), true slot (4,)) of a point light at p (tracker frame),
    by the pinhole-slot geometry: the ray from p through slot s reaches the array at
    u_img; the slot is the one whose image lands on the 128 pixels."""
    centre, u, n, _ = G.module_frames()
    px, slots = np.empty(4), np.empty(4, dtype=int)
    for m in range(4):
        pu, pz = (p - centre[m]) @ u[m], p @ n[m]
        for s in (-1, 0, 1):
            us = -s * G.slot_spacing_m
            u_img = us + (us - pu) * G.focal_height_m / (pz - G.focal_height_m)
            raw = u_img / G.pixel_pitch_m + (G.n_pixels - 1) / 2.0
            if 0.0 <= raw < G.n_pixels:
                px[m], slots[m] = raw + WIRE_PIXELS * s, s
                break
        else:
            raise ValueError("outside the field of view")
    return px, slots


points = st.tuples(st.floats(-0.6, 0.6), st.floats(-0.6, 0.6), st.floats(1.5, 5.0))


def _visible(p):
    try:
        return wire_peaks(np.asarray(p))
    except ValueError:
        return None


@settings(max_examples=80, deadline=None)
@given(points, st.lists(st.integers(-2, 2), min_size=4, max_size=4),
       st.tuples(st.floats(-0.15, 0.15), st.floats(-0.15, 0.15), st.floats(-0.15, 0.15)))
def test_the_prediction_picks_the_true_slots_back(p, wrong, pred_err):
    p = np.asarray(p)
    seen = _visible(p)
    if seen is None:
        return
    px, slot = seen
    valid = np.ones(4, bool)
    # what the firmware reports after a re-acquisition from the wrong slot: the same
    # array pixel, unwrapped from another slot in -1..+1
    fw_slot = np.clip(slot + np.asarray(wrong), -1, 1)
    fw_px = px + WIRE_PIXELS * (fw_slot - slot)
    r = SlotResolver()
    pred = p + np.asarray(pred_err)
    got = r.position(fw_px, fw_slot, valid,
                     choose=lambda c: np.linalg.norm(c - pred, axis=1))
    np.testing.assert_allclose(got, p, atol=1e-6)
    assert np.array_equal(fw_slot + np.asarray(r.shift), slot)
    # the correction holds for the next frames (the marker moved a little)
    q = p + np.array([0.01, -0.01, 0.02])
    seen_q = _visible(q)
    if seen_q is not None and np.array_equal(seen_q[1], slot):
        qpx = seen_q[0] + WIRE_PIXELS * (fw_slot - slot)
        np.testing.assert_allclose(r.position(qpx, fw_slot, valid), q, atol=1e-6)


def test_a_wrong_slot_is_metres_off_and_self_consistent():
    # why nothing in one frame can tell: a common slot error on a pair keeps the planes
    # consistent, the point moves by metres
    p = np.array([0.45, 0.0, 1.6])
    px, slot = wire_peaks(p)
    assert np.any(slot[:2] != 0)  # off-centre: outside the central slot of a module
    fw_slot = np.zeros(4, dtype=int)
    fw_px = px - WIRE_PIXELS * slot
    wrong, ok = triangulate(fw_px, fw_slot, np.ones(4, bool))
    assert ok and np.linalg.norm(wrong - p) > 0.5
    right, ok = triangulate(px, slot, np.ones(4, bool))
    np.testing.assert_allclose(right, p, atol=1e-9)


def test_filter_prediction_chooses_the_slots_by_nis():
    # with the filter where the marker really is, candidate_nis ranks the true point first
    p = np.array([0.45, 0.05, 1.6])
    px, slot = wire_peaks(p)
    ekf = PoseEkf(0.0, p + 0.02, np.array([1.0, 0.0, 0.0, 0.0]))
    r = SlotResolver()
    got = r.position(px - WIRE_PIXELS * slot, np.zeros(4, dtype=int), np.ones(4, bool),
                     choose=lambda c: ekf.candidate_nis(0.0, c))
    np.testing.assert_allclose(got, p, atol=1e-6)
    assert r.resolved == 1
    assert not ekf.in_dropout(0.1) and ekf.in_dropout(1.0)


def test_a_choice_without_a_clear_winner_stays_doubtful_until_motion_confirms_it():
    # after a long dropout the prediction fits several corrections: the best is taken,
    # flagged ambiguous; a clear choice from that same track proves nothing; a 0.3 m move
    # with every update accepted confirms it, a rejected update restarts the count
    p = np.array([0.45, 0.05, 1.6])
    px, slot = wire_peaks(p)
    fw_px, fw_slot, valid = px - WIRE_PIXELS * slot, np.zeros(4, dtype=int), np.ones(4, bool)
    r = SlotResolver(confirm_move_m=0.3)
    far = np.array([0.0, 0.0, 50.0])  # a prediction that explains nothing
    r.position(fw_px, fw_slot, valid, choose=lambda c: 1e-3 * np.linalg.norm(c - far, axis=1))
    assert r.ambiguous and r.ambiguous_choices == 1
    r.position(fw_px, fw_slot, valid, choose=lambda c: np.linalg.norm(c - p, axis=1) * 1e3)
    assert r.ambiguous  # clear, but on the doubtful track
    r.confirm(p + [0.0, 0.0, 0.2], accepted=True)
    assert r.ambiguous
    r.confirm(p + [0.0, 0.0, 0.25], accepted=False)  # gated: start again from here
    r.confirm(p + [0.0, 0.0, 0.5], accepted=True)
    assert r.ambiguous
    r.confirm(p + [0.0, 0.0, 0.56], accepted=True)
    assert not r.ambiguous
    r.position(fw_px, fw_slot, valid, choose=lambda c: np.linalg.norm(c - p, axis=1) * 1e3)
    assert not r.ambiguous  # a clear choice on a confirmed track
