"""The pose EKF over message tables shaped as a recording's (`record.export`)."""

import numpy as np
import pytest
from airwake.link.messages import BY_NAME
from airwake.record.flight_builder import MessageTable
from airwake.tracking.errors import TrackingError
from airwake.tracking.marker import LED_DIRECTIONS_BODY, LED_RADIUS_M
from airwake.tracking.offline import track_streams

from hil_sim.sensors.losa import MARKER_LED_DIRECTIONS, LosaConfig
from tests.tracking.sim_data import simulate_flight


def _rows(name: str, n: int) -> np.ndarray:
    return np.zeros(n, dtype=np.dtype(list(BY_NAME[name].dtype_descr)))


def _streams(flight, seed: int) -> dict:
    imu = _rows("imu", flight.imu_t_s.size)
    imu["gyro_frd_rad_s"], imu["accel_frd_m_s2"] = flight.gyro_rad_s, flight.accel_m_s2
    lp = _rows("losa_peaks", flight.losa_t_s.size)
    lp["peak_px"] = np.where(flight.losa_valid, flight.losa_peak_px, np.nan)
    lp["slot"], lp["sensor_flags"] = flight.losa_slot, flight.losa_valid.astype(np.uint8)
    # The marker's attitude messages at 120 Hz: calibrating during the rest, then
    # tracking; gravity from the mean accelerometer at rest, the line of sight from its
    # LED scan (truth + 0.3 deg: the simulator has no model of the scan).
    t_att = np.arange(0.0, flight.imu_t_s[-1], 1 / 120)
    att = _rows("marker_attitude", t_att.size)
    t_cal = flight.rest_s - 0.2
    att["mode"] = np.where(t_att >= t_cal, 3, 1)
    rest = flight.imu_t_s < t_cal
    g = -flight.accel_m_s2[rest].mean(axis=0)
    att["gravity_frd_unit"] = g / np.linalg.norm(g)
    pos, rot = flight.truth_in_tracker(t_att)
    los = np.einsum("kji,kj->ki", rot, -pos / np.linalg.norm(pos, axis=1, keepdims=True))
    att["los_frd_unit"] = los + 0.005 * np.random.default_rng(seed).standard_normal(los.shape)
    att["gyro_bias_frd_rad_s"] = flight.gyro_rad_s[rest].mean(axis=0)
    k = np.clip(np.searchsorted(flight.losa_t_s, t_att), 0, flight.losa_t_s.size - 1)
    att["active_led"] = flight.led_index[k]
    return {"marker/imu": MessageTable(flight.imu_t_s, imu),
            "losa/losa_peaks": MessageTable(flight.losa_t_s, lp),
            "marker/marker_attitude": MessageTable(t_att, att)}


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
