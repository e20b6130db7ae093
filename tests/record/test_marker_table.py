"""The marker pose in the export: `build_flight_table`'s `marker_*` columns and the
helicopter-less marker table (`build_marker_table`) for a hand-carried anemometer."""

import numpy as np
import pytest
from airwake.record.flight_builder import (
    FlightBuildConfig,
    FlightBuildError,
    build_marker_table,
    message_table,
)
from airwake.record.marker_pose import POSE_COLUMNS, TrackerPlacement

from tests.tracking.sim_data import message_streams, simulate_flight

TRACKER_NED_M = (-3.0, 0.5, -1.2)


@pytest.fixture(scope="module")
def marker_streams():
    flight = simulate_flight(12.0, seed=11)
    streams = message_streams(flight, 11)
    t_an = np.arange(0.0, flight.imu_t_s[-1], 0.01)
    streams["marker/anemometer"] = message_table(
        "anemometer", t_an, wind_uvw_inst_m_s=np.array([1.0, -0.5, 0.2]), sonic_temp_c=21.0)
    return flight, streams


def test_marker_table_follows_the_marker_in_ned(marker_streams):
    # a hand-carried anemometer has no rover INS: the table's rows are the marker IMU's,
    # and the tracker-frame pose lands in NED through the tracker's placement
    flight, streams = marker_streams
    cfg = FlightBuildConfig(tracker_placement=TrackerPlacement(TRACKER_NED_M, 0.0, 0.0))
    built = build_marker_table(streams, cfg)
    df = built.df
    assert set(POSE_COLUMNS) | {"marker_valid", "anemo_u_m_s"} <= set(df.columns)
    assert not df.isna().any().any()
    truth = flight.truth.at(df["t_s"].to_numpy())
    est = df[["marker_pos_n_m", "marker_pos_e_m", "marker_pos_d_m"]].to_numpy()
    ok = df["marker_valid"].to_numpy() > 0.5
    assert ok.mean() > 0.9
    err = np.linalg.norm(est - (truth.pos_ned_m + TRACKER_NED_M), axis=1)[ok]
    assert np.sqrt(np.mean(err ** 2)) < 0.015
    np.testing.assert_allclose(df["anemo_u_m_s"], 1.0)
    assert built.metadata["table"] == "marker" and built.metadata["missing_streams"] == []


def test_marker_table_without_losa_is_refused_in_one_line(marker_streams):
    _, streams = marker_streams
    with pytest.raises(FlightBuildError, match="lack losa/losa_peaks") as e:
        build_marker_table({k: v for k, v in streams.items() if k != "losa/losa_peaks"})
    assert "\n" not in str(e.value)
