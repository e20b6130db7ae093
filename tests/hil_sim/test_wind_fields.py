"""Wind fields: still air, uniform + turbulence, indoor fans; eq 5.3 local-wind fit;
config errors."""

import numpy as np
import pytest

from hil_sim.world.kinematics import euler_to_quat, quat_to_dcm
from hil_sim.world.wind import (
    DEFAULT_FIT,
    HeldLocalWind,
    LocalWindFit,
    WindField,
    build_wind_field,
)

SMALL_BOX = {"length_scale_m": 1.0, "grid_spacing_m": 0.25, "box_m": [64.0, 12.0, 12.0]}


class RigidRotation(WindField):
    """w = v0 + Omega x (p - c): the field eq 5.3 describes exactly."""

    kind = "test_rotation"

    def __init__(self, omega, centre, v0):
        self.omega, self.centre, self.v0 = map(np.asarray, (omega, centre, v0))

    def _velocity(self, t, pos, unsteady, turbulence):
        return self.v0 + np.cross(self.omega, pos - self.centre)


class LinearShear(WindField):
    kind = "test_shear"

    def __init__(self, gradient):
        self.g = np.asarray(gradient, dtype=float)

    def _velocity(self, t, pos, unsteady, turbulence):
        return pos @ self.g.T


def test_still_air_is_zero_everywhere():
    f = build_wind_field({"type": "still_air"}, rng=np.random.default_rng(0))
    assert np.all(f.velocity_ned(np.arange(5.0), np.random.default_rng(1).normal(size=(5, 3)))
                  == 0)
    assert np.all(f.local_wind(1.0, [0, 0, -2.0], [1, 0, 0, 0]) == 0)


def test_local_wind_fit_returns_omega_of_a_rigid_rotation_in_body_axes():
    # Eq 5.3 convention: for w = Omega x r the fit gives omega = Omega (the curl is 2 Omega).
    omega = np.array([0.3, -0.2, 0.5])
    field = RigidRotation(omega, centre=[1.0, -2.0, -3.0], v0=[2.0, 1.0, 0.0])
    hub = np.array([4.0, 1.0, -2.5])
    q = euler_to_quat(np.array([0.2, -0.1, 1.0]))
    lw = field.local_wind(0.0, hub, q)
    r = quat_to_dcm(q)
    v_hub = field.velocity_ned(0.0, hub)
    assert np.allclose(lw[:3], r.T @ v_hub, atol=1e-12)
    assert np.allclose(lw[3:], r.T @ omega, atol=1e-12)


def test_local_wind_of_a_shear_follows_the_documented_weighting():
    # w_z = G x: omega_y = -s_x G / (s_x + s_z) over the 1.3 x 1.3 x 0.6 m box.
    g = 0.8
    field = LinearShear([[0, 0, 0], [0, 0, 0], [g, 0, 0]])
    lw = field.local_wind(0.0, [0.0, 0.0, 0.0], [1, 0, 0, 0])
    r = DEFAULT_FIT.offsets_body_m
    sx, sz = np.mean(r[:, 0] ** 2), np.mean(r[:, 2] ** 2)
    assert lw[4] == pytest.approx(-sx * g / (sx + sz), rel=1e-12)
    # A flat (disc) volume gives exactly the in-plane gradient the rotor feels ...
    disc = LocalWindFit(volume_m=(1.3, 1.3, 1e-6))
    assert field.local_wind(0.0, [0, 0, 0], [1, 0, 0, 0], fit=disc)[4] == pytest.approx(-g)
    # ... and ignores a vertical shear of the in-plane wind, which the disc cannot feel.
    vertical = LinearShear([[0, 0, g], [0, 0, 0], [0, 0, 0]])
    assert vertical.local_wind(0.0, [0, 0, 0], [1, 0, 0, 0], fit=disc)[4] == pytest.approx(
        0.0, abs=1e-5)


def test_uniform_wind_mean_and_turbulence_intensity():
    cfg = {"type": "uniform", "velocity_ned_m_s": [5.0, 0.0, 0.0], "turbulence_intensity": 0.1,
           "turbulence": SMALL_BOX}
    f = build_wind_field(cfg, rng=np.random.default_rng(3))
    t = np.arange(0, 120.0, 0.05)
    samples = np.concatenate([f.velocity_ned(t, np.tile(p, (t.size, 1)))
                              for p in ([0, 0, -2], [0, 5, -4], [3, -4, -6])])
    assert samples.mean(axis=0) == pytest.approx([5.0, 0.0, 0.0], abs=0.1)
    ti = samples.std(axis=0) / 5.0
    assert ti == pytest.approx([0.1, 0.1, 0.1], rel=0.2)
    assert np.allclose(f.mean_velocity_ned(t[:3], np.zeros((3, 3))), [5.0, 0.0, 0.0])


def test_same_seed_same_field_different_seed_different():
    cfg = {"type": "uniform", "velocity_ned_m_s": [3.0, 1.0, 0.0],
           "turbulence_intensity": 0.2, "turbulence": SMALL_BOX}
    pts = np.random.default_rng(0).uniform(-5, 5, (50, 3))
    a = build_wind_field(cfg, rng=np.random.default_rng(9)).velocity_ned(1.5, pts)
    b = build_wind_field(cfg, rng=np.random.default_rng(9)).velocity_ned(1.5, pts)
    c = build_wind_field(cfg, rng=np.random.default_rng(10)).velocity_ned(1.5, pts)
    assert np.array_equal(a, b) and not np.allclose(a, c)


def test_config_errors_name_key_and_value():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match=r"wind\.type = 'tornado'"):
        build_wind_field({"type": "tornado"}, rng=rng)
    with pytest.raises(ValueError, match=r"wind: unknown key 'speed'"):
        build_wind_field({"type": "ship_airwake", "speed": 3}, rng=rng)
    with pytest.raises(ValueError, match=r"relative_wind_speed_m_s = -3.0"):
        build_wind_field({"type": "ship_airwake", "relative_wind_speed_m_s": -3}, rng=rng)
    with pytest.raises(ValueError, match=r"wind\.turbulence: unknown key 'L'"):
        build_wind_field({"type": "uniform", "turbulence": {"L": 2}}, rng=rng)
    with pytest.raises(ValueError, match=r"scenario\.wind\.fan_a_ned_m = 'here'"):
        build_wind_field({"type": "fans_indoor", "fan_a_ned_m": "here"}, rng=rng,
                         where="scenario.wind")


def test_held_local_wind_refreshes_on_its_grid_only():
    calls = []

    class Counting(RigidRotation):
        def _velocity(self, t, pos, unsteady, turbulence):
            calls.append(t[0])
            return super()._velocity(t, pos, unsteady, turbulence) * (1 + t[:, None])

    held = HeldLocalWind(Counting([0, 0, 0.1], [0, 0, 0], [1, 0, 0]), rate_hz=100.0)
    values = [held(t, np.zeros(3), [1, 0, 0, 0]) for t in np.arange(0, 0.05, 0.001)]
    assert len(calls) == 5
    assert np.allclose(values[0], values[9]) and not np.allclose(values[9], values[10])


@pytest.fixture(scope="module")
def fans():
    cfg = {"type": "fans_indoor", "turbulence": {"length_scale_m": 0.5, "grid_spacing_m": 0.15,
                                                 "box_m": [24.0, 6.0, 6.0]}}
    return build_wind_field(cfg, rng=np.random.default_rng(4))


def test_fan_jets_leave_at_the_source_speed_and_decay(fans):
    c = fans.config
    a, b = np.array(c.fan_a_ned_m), np.array(c.fan_b_ned_m)
    axis = (b - a) * np.array([1, 1, 0])
    axis /= np.linalg.norm(axis)
    # Fan A's jet alone: centreline U0 x0 / (x + x0), U0 = 7.24 m/s at the fan (§3.4).
    jet_a, _, _ = fans._jet((a + 0.5 * axis)[None, :], 0)
    assert jet_a[0] @ axis == pytest.approx(c.exit_speed_m_s * fans.x0 / (0.5 + fans.x0),
                                            rel=0.01)
    jet_a0, _, _ = fans._jet((a + 0.01 * axis)[None, :], 0)
    assert jet_a0[0] @ axis == pytest.approx(c.exit_speed_m_s, rel=0.01)
    near = fans.mean_velocity_ned(0.0, a + 1.0 * axis) @ axis
    far = fans.mean_velocity_ned(0.0, a + 3.0 * axis) @ axis
    assert far < 0.75 * near
    # Fan B blows the other way.
    assert fans.mean_velocity_ned(0.0, b - 0.5 * axis) @ axis < -5.0


def test_fan_jets_entrain_air_and_swirl(fans):
    c = fans.config
    a = np.array(c.fan_a_ned_m)
    axis = np.array([1.0, 0.0, 0.0])
    # Outside the jet the air is drawn inward (entrainment) ...
    off = a + 2.0 * axis + np.array([0.0, 1.5, 0.0])
    assert fans.mean_velocity_ned(0.0, off)[1] < 0.0
    # ... and the fan's swirl is a rotation about the jet axis: omega_x in eq 5.3.
    lw = fans.local_wind(0.0, a + 1.5 * axis, [1, 0, 0, 0], turbulence=False)
    assert abs(lw[3]) > 0.1 and abs(lw[3]) > 5 * abs(lw[5])


def test_fan_jet_turbulence_intensity_on_axis(fans):
    c = fans.config
    a = np.array(c.fan_a_ned_m)
    p = a + np.array([1.5, 0.0, 0.0])
    t = np.arange(0, 60.0, 0.02)
    v = fans.velocity_ned(t, np.tile(p, (t.size, 1)))
    mean = fans.mean_velocity_ned(0.0, p)
    ti = v[:, 0].std() / mean[0]
    assert ti == pytest.approx(c.turbulence_intensity, rel=0.3)


@pytest.mark.parametrize("cfg", [{"type": "still_air"},
                                 {"type": "uniform", "velocity_ned_m_s": [1.0, 2.0, 0.0],
                                  "turbulence": SMALL_BOX},
                                 {"type": "ship_airwake", "relative_wind_heading_deg": 15.0,
                                  "turbulence": SMALL_BOX}])
def test_describe_round_trips_through_build(cfg):
    # Metadata written from describe() must rebuild the same field.
    f = build_wind_field(cfg, rng=np.random.default_rng(1))
    again = build_wind_field(f.describe(), rng=np.random.default_rng(1))
    assert again.config == f.config and again.kind == f.kind
