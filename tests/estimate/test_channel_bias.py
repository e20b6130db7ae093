"""The model's slow misfit as the smoother's own channel-bias states (`--model-error
states`, the default with an anchor): on a model-generated flight with a known constant
wind (tests/estimate/conftest.py) and a steady force added to one accelerometer channel —
a force the model misses, as a calibrated model of a foreign airframe does — anchored on
the true mean flow, the bias state takes the force and the rotation is read as on the
clean flight; with the force only considered, the rotation takes it."""

from __future__ import annotations

import numpy as np
import pytest
from airwake.estimate.errors import WindEstimationError
from airwake.estimate.smoother import WindSmoother
from airwake.estimate.wind import estimate_wind
from airwake.heli import WIND_NAMES
from airwake.record.flight_table import write_flight_table

from tests.estimate.conftest import CONSTANT_WIND
from tests.estimate.test_anchor import _anchor_table

W = list(WIND_NAMES[3:])
FORCE_M_S2 = 0.15  # on a_x: ~1 % of g, a tenth of a degree of thrust tilt


@pytest.fixture(scope="module")
def flights(constant_wind_flight, tmp_path_factory):
    d = tmp_path_factory.mktemp("bias")
    clean, pushed = d / "clean.parquet", d / "pushed.parquet"
    write_flight_table(constant_wind_flight.df, clean, constant_wind_flight.metadata)
    df = constant_wind_flight.df.copy()
    df["acc_x_m_s2"] = df["acc_x_m_s2"] + FORCE_M_S2
    write_flight_table(df, pushed, constant_wind_flight.metadata)
    return clean, pushed


def _run(path, mode, offset=(FORCE_M_S2, 0, 0, 0, 0, 0)):
    first = estimate_wind(path, "table52", em_passes=1, ins_velocity_std=0.0)
    anchor = _anchor_table(first.df["t_s"].to_numpy(), CONSTANT_WIND[:3], 0.02)
    mode = {} if mode is None else {"model_error": mode}  # None: the default
    return estimate_wind(path, "table52", em_passes=2, ins_velocity_std=0.0, anchor=anchor,
                         calibration={"model_error_offset": list(offset)}, **mode)


@pytest.fixture(scope="module")
def runs(flights):
    clean, pushed = flights
    return {"clean": _run(clean, "states"), "states": _run(pushed, "states"),
            "consider": _run(pushed, None)}


def test_the_bias_state_takes_a_steady_force_the_rotation_would_have_taken(runs):
    ref = runs["clean"].df[W].to_numpy()
    moved = {m: np.abs(runs[m].df[W].to_numpy() - ref).mean(axis=0)
             for m in ("states", "consider")}
    # considered, the force lands in the rotation (w_y: a pitching wind reads as a_x)
    assert moved["consider"].max() > 0.05, moved
    # estimated, it moves the rotation by less than a third of that on every component
    assert (moved["states"] < moved["consider"] / 3 + 0.005).all(), moved
    meta = runs["states"].metadata
    assert meta["model_error"] == "states"
    assert meta["channel_bias"]["tau_s"] == 30.0
    assert meta["channel_bias"]["sigma"] == pytest.approx([FORCE_M_S2, 0, 0, 0, 0, 0])
    # the state found the force (its mean over the flight)
    assert meta["channel_bias"]["mean"][0] == pytest.approx(FORCE_M_S2, abs=0.04)
    assert meta["channel_bias"]["mean"][1:] == [0.0] * 5
    # the clean flight's state stays near zero
    assert abs(runs["clean"].metadata["channel_bias"]["mean"][0]) < 0.04
    # considered (the default): no states, the force's effect in the intervals instead
    assert runs["consider"].metadata["model_error"] == "consider"
    assert runs["consider"].metadata["channel_bias"] is None
    assert runs["consider"].metadata["offset_std"][0] == pytest.approx(FORCE_M_S2)


def test_the_cli_takes_the_mode_and_a_bad_one_is_named(flights, tmp_path, capsys):

    from airwake.cli import main

    clean, _ = flights
    with pytest.raises(WindEstimationError, match="--model-error 'bias'"):
        estimate_wind(clean, "table52", model_error="bias")
    out = tmp_path / "w.parquet"
    assert main(["wind", "estimate", str(clean), "--model-error", "states", "--em-passes",
                 "1", "--out", str(out), "--json"]) == 0
    capsys.readouterr()
    from airwake.record.flight_table import load_flight_table

    # table52 has no [calibration] offsets: the mode is recorded, there are no states
    meta = load_flight_table(out, required=()).metadata
    assert meta["model_error"] == "states" and meta["channel_bias"] is None


def test_zero_sigma_adds_no_state_and_the_bound_ignores_the_states(constant_wind_flight):
    from airwake.calibrate.residuals import FlightData
    from airwake.estimate.prefilter import prefilter
    from airwake.estimate.wind_prior import WindPrior
    from airwake.heli import load_model

    heli = load_model("table52")
    pre = prefilter(FlightData.from_flight(heli, constant_wind_flight), heli, 6.0, 15.0)
    prior = WindPrior.from_physics(0.6, 3.0)
    none = WindSmoother(heli, pre, prior, iterations=1)
    zero = WindSmoother(heli, pre, prior, iterations=1, channel_bias=(np.zeros(6), 30.0))
    some = WindSmoother(heli, pre, prior, iterations=1,
                        channel_bias=([0.1, 0, 0, 0, 0.05, 0], 30.0))
    assert zero.n_state == none.n_state and some.n_state == none.n_state + 2
    a, b = none.run(), zero.run()
    np.testing.assert_array_equal(a.mean, b.mean)
    assert np.isnan(b.bias).all()
    c = some.run()
    assert np.isfinite(c.bias[:, [0, 4]]).all() and np.isnan(c.bias[:, [1, 2, 3, 5]]).all()
    # the bound is for the channel error as given: the smoother's states do not enter it
    wind = np.tile(CONSTANT_WIND, (pre.data.t.size, 1))
    np.testing.assert_allclose(some.bound(wind, prior, none.noise_std),
                               none.bound(wind, prior, none.noise_std), rtol=1e-9)
    assert some.n_state == none.n_state + 2  # restored after the bound
    bad_inputs = (([0.1] * 5, 30.0), "sigma must be 6"), (([-0.1] + [0] * 5, 30.0),
                                                          "sigma must be 6"), \
        (([0.1] * 6, 0.0), "tau_s must be > 0")
    for bad, match in bad_inputs:
        with pytest.raises(ValueError, match=match):
            WindSmoother(heli, pre, prior, channel_bias=bad)


def test_the_ins_accelerometer_bias_becomes_a_state_on_each_accelerometer(flights):
    # a user who knows the INS's residual bias from its data sheet gives it; with states it
    # is estimated on each accelerometer channel (joined to the model's own offsets)
    clean, _ = flights
    est = estimate_wind(clean, "table52", em_passes=1, ins_velocity_std=0.0,
                        accel_bias_std=0.01, model_error="states",
                        calibration={"model_error_offset": [0.0, 0.02, 0.0, 0.0, 0.0, 0.0]})
    sigma = est.metadata["channel_bias"]["sigma"]
    assert sigma == pytest.approx([0.01, np.hypot(0.02, 0.01), 0.01, 0.0, 0.0, 0.0])
    assert est.metadata["offset_std"] is None  # estimated, so not considered as well
