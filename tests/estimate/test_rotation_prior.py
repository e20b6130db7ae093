"""The rotation's turbulence std from the mean flow's (`WindPrior.rotation_sigma`) and the
smoother's EM that uses it for w_x, w_y (`airwake.estimate.smoother`, learn item
"rotation_from_mean_flow")."""

import numpy as np
import pytest
from airwake.calibrate import load_flight
from airwake.calibrate.residuals import FlightData
from airwake.estimate.prefilter import prefilter
from airwake.estimate.smoother import TIED_ROTATION, WindSmoother
from airwake.estimate.wind_prior import WindPrior
from airwake.heli import load_model
from hypothesis import given
from hypothesis import strategies as st


def _frozen_field_difference(sigma, scale, sep, n, rng):
    """std of u(x + sep) - u(x) for a frozen 1-D field with correlation exp(-r / scale),
    sampled exactly as an Ornstein-Uhlenbeck process in x (Gillespie 1996)."""
    rho = np.exp(-sep / scale)
    u0 = rng.normal(0.0, sigma, n)
    u1 = rho * u0 + np.sqrt(1.0 - rho**2) * sigma * rng.normal(size=n)
    return float(np.std(u1 - u0))


@pytest.mark.parametrize("radius,airspeed", [(0.673, 3.0), (0.3, 1.0), (1.2, 6.0)])
def test_the_rotation_std_is_a_frozen_fields_difference_across_the_radius(radius, airspeed):
    """Sampled, not re-derived: the velocity difference across one rotor radius of a field
    with the mean flow's integral scale (tau U), over the radius."""
    prior = WindPrior.from_physics(radius, airspeed, sigma=(0.3, 0.2, 0.25, 0.5, 0.5, 0.5))
    scale = prior.tau_s[0] * airspeed
    sv = float(np.sqrt(np.mean(prior.sigma[:3] ** 2)))
    diff = _frozen_field_difference(sv, scale, radius, 400_000, np.random.default_rng(3))
    np.testing.assert_allclose(prior.rotation_sigma(), diff / radius, rtol=0.01)


@given(st.floats(0.05, 3.0), st.floats(0.1, 3.0), st.floats(0.0, 5.0))
def test_the_rotation_std_scales_with_the_mean_flow_and_falls_with_the_scale(sv, radius, u):
    prior = WindPrior.from_physics(radius, u)
    one = prior.rotation_sigma([sv] * 3)
    assert one.shape == (3,) and np.all(one > 0)
    np.testing.assert_allclose(prior.rotation_sigma([2 * sv] * 3), 2 * one, rtol=1e-12)
    # larger eddies (a longer correlation time at the same airspeed): a smaller gradient
    wide = prior.copy()
    wide.tau_s = wide.tau_s * 4.0
    assert np.all(wide.rotation_sigma([sv] * 3) < one)
    # the rotation a gradient can hold: never above sqrt(2) sigma_v / R (uncorrelated ends)
    assert np.all(one <= np.sqrt(2.0) * sv / radius + 1e-12)


def test_a_prior_without_its_rotor_is_refused():
    prior = WindPrior(sigma=[0.5] * 6, tau_s=[1.0] * 6, mean_walk=[0.05] * 6,
                      mean_std0=[1.0] * 6)
    with pytest.raises(ValueError, match="rotor radius"):
        prior.rotation_sigma()


def _smoother(flight, learn):
    model = load_model("table52")
    pre = prefilter(FlightData.from_flight(model, load_flight(flight)), model, 6.0, 15.0)
    return WindSmoother(model, pre, WindPrior.from_physics(0.673, 3.0), iterations=2,
                        learn=learn)


def test_em_sets_the_horizontal_rotations_sigma_from_the_mean_flows(varying_wind_flight):
    tied = _smoother(varying_wind_flight, ("sigma", "noise", "rotation_from_mean_flow")).run()
    free = _smoother(varying_wind_flight, ("sigma", "noise")).run()
    idx = list(TIED_ROTATION)
    want = tied.prior.rotation_sigma()[[i - 3 for i in idx]]
    np.testing.assert_allclose(tied.prior.sigma[idx], want, rtol=1e-12)
    # w_z and the mean flow keep their own EM update: the first pass is the same
    np.testing.assert_allclose(tied.prior.sigma[[0, 1, 2, 5]], free.prior.sigma[[0, 1, 2, 5]],
                               rtol=1e-9)
    assert not np.allclose(free.prior.sigma[idx], want, rtol=0.05)


def test_the_cli_learns_the_rotation_on_its_own_when_asked(tiny_wind_file, tmp_path, capsys):
    import json

    from airwake.cli import main
    from airwake.record.flight_table import read_flight_table

    learned = {}
    for choice in ("from-mean-flow", "learned"):
        out = tmp_path / f"{choice}.parquet"
        assert main(["wind", "estimate", str(tiny_wind_file), "--em-passes", "2",
                     "--rotation-sigma", choice, "--out", str(out), "--json"]) == 0
        json.loads(capsys.readouterr().out)
        meta = read_flight_table(out)[1]
        learned[choice] = ("rotation_from_mean_flow" in meta["learn"], meta["prior"]["sigma"])
    assert learned["from-mean-flow"][0] and not learned["learned"][0]
    assert learned["from-mean-flow"][1][3:5] != learned["learned"][1][3:5]
    out = tmp_path / "apf.parquet"
    assert main(["wind", "estimate", str(tiny_wind_file), "--method", "apf",
                 "--rotation-sigma", "learned", "--out", str(out)]) == 2
    assert "is for --method smoother" in capsys.readouterr().err and not out.exists()
