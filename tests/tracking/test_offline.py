"""The pose EKF over message tables shaped as a recording's (`record.export`)."""

import numpy as np
import pytest
from airwake.tracking.errors import TrackingError
from airwake.tracking.marker import LED_DIRECTIONS_BODY, LED_RADIUS_M
from airwake.tracking.offline import track_streams

from hil_sim.sensors.losa import MARKER_LED_DIRECTIONS, LosaConfig
from tests.tracking.sim_data import message_streams as _streams
from tests.tracking.sim_data import simulate_flight


def test_track_streams_follows_the_marker_from_its_message_tables():
    # The offline path (recording -> streams -> EKF) must reach the same accuracy as the
    # direct one: frames, LED lever arms and the calibration row wired correctly.
    flight = simulate_flight(20.0, seed=7)
    track = track_streams(_streams(flight, 7))
    pos, _ = flight.truth_in_tracker(track.t_s)
    err = np.linalg.norm(track.pos_ref_m - pos, axis=1)
    assert np.sqrt(np.mean(err**2)) < 0.015, np.sqrt(np.mean(err**2))
    assert np.mean(track.losa_outcome == "accepted") > 0.95
    smoothed = track_streams(_streams(flight, 7), smooth=True)
    err_s = np.linalg.norm(smoothed.pos_ref_m - pos, axis=1)
    assert np.sqrt(np.mean(err_s**2)) < np.sqrt(np.mean(err**2))


def test_missing_streams_and_uncalibrated_marker_are_named():
    flight = simulate_flight(4.0, seed=8)
    streams = _streams(flight, 8)
    with pytest.raises(TrackingError, match="marker/imu"):
        track_streams({k: v for k, v in streams.items() if k != "marker/imu"})
    att = streams["marker/marker_attitude"]
    att.data["mode"] = 1
    with pytest.raises(TrackingError, match="never finished its calibration"):
        track_streams(streams)


def test_marker_led_geometry_matches_the_simulator():
    # Two copies of the tetrahedron (host and simulator) must not drift apart.
    np.testing.assert_array_equal(LED_DIRECTIONS_BODY, MARKER_LED_DIRECTIONS)
    assert LED_RADIUS_M == LosaConfig().led_radius_m
