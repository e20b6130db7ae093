"""Where a smoother estimate's steady error comes from, channel by channel
(`wind_bias_by_channel`): a steady offset put on one measured channel of a flight whose
wind is known shows up as that channel's misfit, and the estimate moves as its share
says; `airwake calibrate` writes the still-air table and prints it."""

from __future__ import annotations

import numpy as np
import pytest
from airwake.estimate.errors import WindEstimationError
from airwake.estimate.wind import WIND_NAMES, estimate_wind, wind_bias_by_channel
from airwake.record.flight_table import write_flight_table

from tests.estimate.conftest import CONSTANT_WIND

OFFSET_ACC_X = 0.05  # m/s^2, a body-fixed force the model misses (0.3 deg of thrust tilt)


def _bias(flight, tmp_path, name, offset=0.0):
    df = flight.df.copy()
    df["acc_x_m_s2"] = df["acc_x_m_s2"] + offset
    path = tmp_path / f"{name}.parquet"
    write_flight_table(df, path, flight.metadata)
    est = estimate_wind(path, model="table52", em_passes=1)
    known = np.tile(np.asarray(CONSTANT_WIND, float), (len(est.df), 1))
    return est, wind_bias_by_channel(est, known, burn_in_s=1.0)


def test_a_steady_channel_offset_is_that_channels_misfit_and_moves_the_wind_by_its_share(
        constant_wind_flight, tmp_path):
    _, clean = _bias(constant_wind_flight, tmp_path, "clean")
    _, off = _bias(constant_wind_flight, tmp_path, "offset", OFFSET_ACC_X)
    dm = np.subtract(off["misfit_mean"], clean["misfit_mean"])
    # the offset is acc_x's misfit, and no other channel's
    assert dm[0] == pytest.approx(OFFSET_ACC_X, rel=0.05)
    assert np.all(np.abs(dm[1:]) < 0.1 * OFFSET_ACC_X)
    # the estimate moves as the channels' shares say (the smoother is affine in the
    # measurements along its linearisation): acc_x's share carries the change
    d_err = np.subtract(off["error_mean"], clean["error_mean"])
    d_expl = np.subtract(off["explained"], clean["explained"])
    share_x = np.array([off["by_channel"][n][0] for n in WIND_NAMES])
    assert np.max(np.abs(d_err)) > 0.05  # a force the model misses does move the wind
    np.testing.assert_allclose(d_err, d_expl, atol=0.1 * np.max(np.abs(d_err)))
    np.testing.assert_allclose(d_expl, share_x - [clean["by_channel"][n][0]
                                                  for n in WIND_NAMES],
                               atol=0.1 * np.max(np.abs(d_err)))
    # and on the one flight, the shares' sum is the estimate's steady error
    err = np.asarray(off["error_mean"])
    np.testing.assert_allclose(off["explained"], err, atol=0.1 * np.max(np.abs(err)))
    # on the model's own flight at its wind, the steady misfit is the sensors' noise
    assert np.all(np.abs(clean["misfit_mean"]) < np.abs(dm[0]))


def test_an_estimate_without_the_smoother_or_with_a_misshapen_wind_is_refused(
        constant_wind_flight, tmp_path):
    est, _ = _bias(constant_wind_flight, tmp_path, "shape")
    with pytest.raises(WindEstimationError, match=r"known wind is \(3, 6\)"):
        wind_bias_by_channel(est, np.zeros((3, 6)))
    gap = np.zeros((len(est.df), 6))
    gap[5, 2] = np.nan
    with pytest.raises(WindEstimationError, match="non-finite values in 1 rows"):
        wind_bias_by_channel(est, gap)
    est.smoother = None
    with pytest.raises(WindEstimationError, match="needs the smoother's estimate"):
        wind_bias_by_channel(est)


def test_the_calibrate_report_names_the_channels_with_the_largest_shares_first():
    from airwake.calibrate.commands import print_wind_bias
    from airwake.heli.context import MEAS_CHANNELS

    shares = {n: [0.0] * 6 for n in WIND_NAMES}
    shares["wind_vx_m_s"] = [0.40, 0.01, -0.02, 0.0, 0.18, -0.5]
    bias = {"channels": list(MEAS_CHANNELS), "misfit_mean": [0.03, 0, 0, 0, 0.09, 0.1],
            "error_mean": [0.1] + [0.0] * 5, "explained": [0.07] + [0.0] * 5,
            "by_channel": shares}
    out = []
    print_wind_bias(bias, out.append)
    line = next(s for s in "".join(out).splitlines() if s.strip().startswith("wind_vx_m_s"))
    # largest magnitude first: rdot's -0.50, then acc_x's +0.40
    assert line.index("rdot_rad_s2 -0.50") < line.index("acc_x_m_s2 +0.40")
    assert "qdot" not in line and "+0.10" in line and "+0.07" in line
