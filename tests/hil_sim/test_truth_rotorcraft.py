"""The blade-element truth against physics and published data, never against the host's
model (docs/truth-world.md "Validation"): the airframe file names its sources, the section
and tip-loss formulas behave, hover against momentum theory, figure of merit, the power
bucket, blow-back against the closed-form flapping of an articulated rotor, ground effect
against Cheeseman & Bennett, the flybar-coupled rotor-fuselage mode against the
stabiliser-bar theory, vibration lines from the blade loads, and determinism."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.optimize
import scipy.signal
from hypothesis import given, settings
from hypothesis import strategies as st

from hil_sim.world.rotorcraft import dynamics as D
from hil_sim.world.rotorcraft.airfoil import SECTION, load_table, section_coefficients
from hil_sim.world.rotorcraft.airframe import (
    DEFAULT_AIRFRAME,
    SCHEMA,
    AirframeError,
    load_airframe,
)
from hil_sim.world.rotorcraft.blade_element import prandtl_tip_loss, section_load
from hil_sim.world.rotorcraft.inflow import disc_sources, ground_upwash
from hil_sim.world.rotorcraft.model import BladeElementHelicopter

RHO = 1.204
G = 9.80


@pytest.fixture(scope="module")
def heli():
    return BladeElementHelicopter(load_airframe(), air_density_kg_m3=RHO, gravity_m_s2=G)


@pytest.fixture(scope="module")
def hover(heli):
    return heli.trim()


def rotor_average(heli, trim, revs=4):
    """Mean aux outputs and the states over whole revolutions at a trim (body held)."""
    x = trim.x.copy()
    per = heli.revolution_steps(x[D.OMEGA])
    dt = 2 * math.pi / x[D.OMEGA] / per
    n = revs * per
    ox = np.empty((n, D.N_STATES))
    oa = np.empty((n, D.N_AUX))
    w = heli.uniform_wind()
    g = heli.no_ground()
    heli.integrate(x, 0.0, n, trim.delta, trim.delta, heli.env(0, 0), w, w, g, g, ox, oa, 0,
                   D.SPEED_HELD, dt=dt)
    return oa.mean(0), ox


# -- the airframe file ------------------------------------------------------------------


def test_every_airframe_parameter_has_a_value_and_a_source():
    af = load_airframe()
    for part, names in SCHEMA.items():
        for name in names:
            key = f"{part}.{name}"
            assert af.source(key).strip(), key
            assert af[key] is not None


def test_an_airframe_entry_without_a_source_is_refused_naming_it(tmp_path):
    text = DEFAULT_AIRFRAME.read_text().replace(
        'chord_m = { value = 0.052, source = "Align 600D carbon main blade: chord 52 mm" }',
        "chord_m = { value = 0.052 }")
    bad = tmp_path / "af.toml"
    bad.write_text(text)
    with pytest.raises(AirframeError, match="main_rotor.chord_m"):
        load_airframe(bad)


def test_airframe_overrides_are_checked_by_name_and_value():
    assert load_airframe(overrides={"main_rotor.chord_m": 0.06})["main_rotor.chord_m"] == 0.06
    with pytest.raises(AirframeError, match="main_rotor.cord_m"):
        load_airframe(overrides={"main_rotor.cord_m": 0.06})
    with pytest.raises(AirframeError, match="must be > 0"):
        load_airframe(overrides={"main_rotor.radius_m": -1.0})


# -- section aerodynamics ---------------------------------------------------------------


def test_naca0012_table_is_the_published_one_and_symmetric():
    a, cl, cd = load_table()
    assert cl[a == 10.0][0] == pytest.approx(0.9811) and cd[a == 90.0][0] == pytest.approx(1.8)
    for deg in (3.0, 11.0, 45.0, 150.0, 179.0):
        c_pos = section_coefficients(math.radians(deg), SECTION)
        c_neg = section_coefficients(math.radians(-deg), SECTION)
        assert c_pos[0] == pytest.approx(-c_neg[0], abs=1e-12)
        assert c_pos[1] == pytest.approx(c_neg[1], abs=1e-12)
    # the 12 % section stalls between 10 and 12 deg at this Reynolds number
    assert section_coefficients(math.radians(12.0), SECTION)[0] < 0.6


unit = st.floats(-30.0, 30.0)


@settings(max_examples=200, deadline=None)
@given(ux=unit, uy=unit, uz=unit, theta=st.floats(-0.5, 0.5), psi=st.floats(0.0, 6.28))
def test_section_load_is_lift_across_and_drag_along_the_relative_wind(ux, uy, uz, theta, psi):
    # a blade moving along e_t in the x-y plane, lift normal up (-z)
    et = np.array([math.sin(psi), -math.cos(psi), 0.0])
    eu = np.array([0.0, 0.0, -1.0])
    fx, fy, fz, alpha, ut, up = section_load(ux, uy, uz, *et, *eu, theta, 0.05, 0.1, RHO, 1.0,
                                             SECTION)
    f = np.array([fx, fy, fz])
    w = -ut * et + up * eu  # the in-plane relative wind
    v = math.hypot(ut, up)
    cl, cd = section_coefficients(alpha, SECTION)
    q = 0.5 * RHO * v * v * 0.05 * 0.1
    assert np.linalg.norm(f) == pytest.approx(q * math.hypot(cl, cd), rel=1e-9, abs=1e-12)
    if v > 1e-6:
        assert np.dot(f, w / v) == pytest.approx(q * cd, rel=1e-9, abs=1e-9)  # drag along
        assert f @ np.cross(et, eu) == pytest.approx(0.0, abs=1e-9)  # nothing radial


def test_prandtl_tip_loss_vanishes_at_the_tip_and_is_one_inboard():
    phi = 0.08
    values = [prandtl_tip_loss(2.0, r, phi) for r in (0.3, 0.6, 0.8, 0.9, 0.97, 0.9999)]
    assert values[0] == pytest.approx(1.0, abs=1e-6)
    assert all(b < a for a, b in zip(values[1:], values[2:], strict=False))
    assert values[-1] < 0.1


# -- hover against theory ----------------------------------------------------------------


def test_hover_induced_velocity_is_momentum_theory_with_tip_loss(heli, hover):
    aux, _ = rotor_average(heli, hover)
    thrust = aux[D.AUX_THRUST]
    area = math.pi * heli.rotor_radius_m**2
    vtip = heli.nominal_rotor_speed_rad_s * heli.rotor_radius_m
    c_t = thrust / (RHO * area * vtip**2)
    # Prandtl's tip loss as an effective radius B = 1 - sqrt(2 C_T) / N (Johnson 1980, eq 4.9)
    b = 1.0 - math.sqrt(2 * c_t) / 2.0
    v_momentum = math.sqrt(thrust / (2 * RHO * area * b**2))
    assert aux[D.AUX_NU0] == pytest.approx(v_momentum, rel=0.10)
    # the rotor carries the weight plus the fuselage/stabiliser/paddle download: more
    # than the weight, not absurdly more
    weight = heli.mass_kg * G
    assert weight < thrust < 1.3 * weight


def test_hover_figure_of_merit_is_blade_element_momentum_theory(heli, hover):
    """FM = C_T^1.5 / sqrt(2) / (kappa C_T^1.5 / sqrt(2) + sigma C_d0 / 8) (Johnson 1980
    §2.6), kappa = 1.15 for a sqrt(r) inflow with tip loss, C_d0 the section's drag at
    the blades' mean angle of attack (6 C_T / (sigma a) with a = 2 pi): within 10 %, and
    in the band of small low-Reynolds rotors (0.4-0.75)."""
    aux, _ = rotor_average(heli, hover)
    thrust, power = aux[D.AUX_THRUST], aux[D.AUX_POWER]
    area = math.pi * heli.rotor_radius_m**2
    ideal = thrust * math.sqrt(thrust / (2 * RHO * area))
    fm = ideal / power
    vtip = heli.nominal_rotor_speed_rad_s * heli.rotor_radius_m
    c_t = thrust / (RHO * area * vtip**2)
    sigma = 2 * heli.airframe["main_rotor.chord_m"] / (math.pi * heli.rotor_radius_m)
    cd0 = section_coefficients(6 * c_t / (sigma * 2 * math.pi), SECTION)[1]
    induced = c_t**1.5 / math.sqrt(2)
    assert fm == pytest.approx(induced / (1.15 * induced + sigma * cd0 / 8), rel=0.10)
    assert 0.4 <= fm <= 0.75


def test_hover_trim_leans_against_the_tail_rotor_and_holds_the_governor_speed(heli, hover):
    # a clockwise rotor's tail rotor pushes the tail left: the disc tilts right to balance
    assert math.degrees(hover.body12[6]) > 0.5
    assert hover.x[D.OMEGA] == pytest.approx(heli.nominal_rotor_speed_rad_s, rel=1e-9)
    assert 0.0 < math.degrees(hover.delta[0]) < 10.0


def test_power_against_speed_has_a_bucket(heli):
    power = {}
    for v in (0.0, 8.0, 13.0):
        aux, _ = rotor_average(heli, heli.trim(vel_ned_m_s=(v, 0.0, 0.0)))
        power[v] = aux[D.AUX_POWER]
    assert power[8.0] < 0.85 * power[0.0]  # induced power falls with speed
    assert power[13.0] > power[8.0]  # parasite and profile power rise again


def test_blowback_grows_with_advance_ratio_as_closed_form_flapping_says():
    # the main rotor alone (flybar mixing off): longitudinal tip-path tilt back, a1,
    # against a1 = 2 mu (4/3 theta_0 - lambda) / (1 - mu^2/2) (Johnson 1980, eq 5.43)
    af = load_airframe(overrides={"main_rotor.hiller_ratio": 1e-6, "main_rotor.bell_ratio": 1.0})
    h = BladeElementHelicopter(af, air_density_kg_m3=RHO, gravity_m_s2=G)
    delta = np.radians([4.3, 0.0, 0.0, 4.3])

    def tilt_back(u):
        x = h.initial_state([0, 0, -3], [0, 0, 0], [u, 0, 0], delta)
        _, xs = h.captive_average(x, delta, (0, 0, 0), h.no_ground(), 0.6)
        per = h.revolution_steps(xs[D.OMEGA])
        dt = 2 * math.pi / xs[D.OMEGA] / per
        ox = np.empty((2 * per, D.N_STATES))
        oa = np.empty((2 * per, D.N_AUX))
        w = h.uniform_wind()
        g = h.no_ground()
        h.integrate(xs, 0, 2 * per, delta, delta, h.env(0, 0), w, w, g, g, ox, oa, 0,
                    D.SPEED_HELD, dt=dt)
        psi, beta = ox[:, D.PSI], ox[:, D.BETA]
        coef = np.linalg.lstsq(np.column_stack([np.ones_like(psi), np.cos(psi), np.sin(psi)]),
                               beta, rcond=None)[0]
        lam = oa[:, D.AUX_NU0].mean() / (xs[D.OMEGA] * h.rotor_radius_m)
        return -coef[1], u / (xs[D.OMEGA] * h.rotor_radius_m), lam  # front up = back tilt

    a0, _, _ = tilt_back(0.0)
    a3, mu3, lam3 = tilt_back(3.0)
    a6, mu6, lam6 = tilt_back(6.0)
    d3, d6 = a3 - a0, a6 - a0
    assert d3 > 0 and d6 > 0  # forward speed blows the disc back
    assert d6 / d3 == pytest.approx(2.0, rel=0.25)  # proportional to mu
    theory = 2 * mu6 * (4 / 3 * 0.075 - lam6) / (1 - mu6**2 / 2)
    assert d6 == pytest.approx(theory, rel=0.5)


def test_ground_images_reproduce_cheeseman_and_bennett_far_from_the_ground():
    radius = 0.675
    src, area = disc_sources(radius)
    upwash = []
    for z in (0.5 * radius, radius, 2 * radius, 4 * radius):
        sources = np.column_stack([src, np.full(len(src), -z)])
        upwash.append(ground_upwash(np.array([[0.0, 0.0, -z]]), sources,
                                    np.full(len(src), z), area)[0])
        if z >= 2 * radius:  # the point-source limit (R / 4z)^2
            assert upwash[-1] == pytest.approx((radius / (4 * z)) ** 2, rel=0.05)
    assert all(b < a for a, b in zip(upwash, upwash[1:], strict=False))
    # near the ground the disc-spread images give less than the point source
    assert 0.5 * (1 / 2) ** 2 < upwash[0] <= (1 / 2) ** 2


def test_flybar_rotor_fuselage_mode_matches_the_stabiliser_bar_theory(heli, hover):
    """Pitch response to a longitudinal cyclic step from hover, free flight: fit Mettler's
    coupled rotor-fuselage model  q' = M_a a,  tau_f a' = -a - tau_f q + B u  (Mettler,
    Tischler & Kanade 2002) to the revolution-averaged pitch rate; its time constant must
    be the stabiliser bar's 16 / (gamma_f Omega) (the flybar's Lock number from the airframe
    file) within a factor of two, and the mode lightly damped as identified on flybarred
    small helicopters."""
    x = hover.x.copy()
    n = int(0.6 / heli.dt)
    ox = np.empty((n, D.N_STATES))
    oa = np.empty((n, D.N_AUX))
    step = math.radians(0.5)
    d1 = hover.delta.copy()
    d1[2] += step
    w = heli.uniform_wind()
    g = heli.no_ground()
    heli.integrate(x, 0.0, n, d1, d1, heli.env(0, 0), w, w, g, g, ox, oa, 0, D.FREE)
    t = np.arange(n) * heli.dt
    k = heli.revolution_steps()
    q = np.convolve(ox[:, D.RATES + 1] - hover.x[D.RATES + 1], np.ones(k) / k, mode="valid")
    tq = t[: q.size] + 0.5 * k * heli.dt

    def simulate(par):
        m_a, tau, b = par
        sys = scipy.signal.StateSpace([[0.0, m_a], [-1.0, -1.0 / tau]], [[0.0], [b / tau]],
                                      [[1.0, 0.0]], [[0.0]])
        return scipy.signal.lsim(sys, np.full(tq.size, step), tq)[1]

    fit = scipy.optimize.least_squares(lambda p: simulate(p) - q, [80.0, 0.15, -1.0],
                                       bounds=([1.0, 0.01, -50.0], [5000.0, 2.0, 50.0]))
    m_a, tau, _ = fit.x
    f = heli.airframe.part("flybar")
    ri, rt = f["paddle_inner_m"], f["tip_radius_m"]
    inertia = 2 * f["paddle_mass_kg"] * ((ri + rt) / 2) ** 2 + f["rod_mass_kg"] * rt**2 / 3
    lock = RHO * 2 * math.pi * f["paddle_chord_m"] * (rt**4 - ri**4) / inertia
    tau_theory = 16.0 / (lock * heli.nominal_rotor_speed_rad_s)
    assert tau == pytest.approx(tau_theory, rel=1.0)
    wn = math.sqrt(m_a / tau)
    zeta = 1.0 / (2.0 * tau * wn)
    assert 8.0 < wn < 40.0 and zeta < 0.5
    assert np.sqrt(np.mean(fit.fun**2)) < 0.2 * np.max(np.abs(q))


# -- flights -------------------------------------------------------------------------------


def blade_scenario(name, **heli):
    from hil_sim.world.scenario import load_scenario

    sc = load_scenario(name)
    return dataclasses.replace(sc, helicopter=dataclasses.replace(
        sc.helicopter, model="blade_element", **heli))


@pytest.fixture(scope="module")
def hover_flight():
    from hil_sim.world.run import run_scenario

    return run_scenario(blade_scenario("still_air_calibration"), duration_s=3.0, seed=11)


def test_vibration_lines_emerge_from_the_blade_loads(hover_flight):
    """The VN-200 shows the 1/rev of the stated blade imbalance and the 2/rev of the
    two-bladed rotor, from the blade loads through the isolator (no vibration model: the
    data-sheet noise floor between the lines stays far below them)."""
    vn = hover_flight.samples["vn200"]
    fs = 1.0 / np.median(np.diff(vn.t_s))
    omega = hover_flight.truth.rotor_speed_rad_s.mean() / (2 * math.pi)
    two_rev = []
    for signal in (vn.accel_body_m_s2, vn.rates_body_rad_s):
        for axis in range(3):
            x = signal[:, axis] - signal[:, axis].mean()
            f, pxx = scipy.signal.welch(x, fs=fs, nperseg=256)
            floor = np.median(pxx[(f > 10) & (f < 25)])
            if signal is vn.accel_body_m_s2:
                assert pxx[np.abs(f - omega) < 2.0].max() > 100 * floor, f"axis {axis}"
            two_rev.append(pxx[np.abs(f - 2 * omega) < 2.0].max() / floor)
    assert max(two_rev) > 30, f"no 2/rev line at {2 * omega:.1f} Hz: {np.round(two_rev, 1)}"


def test_blade_element_flight_is_deterministic_by_seed(hover_flight):
    from hil_sim.world.run import run_scenario

    again = run_scenario(blade_scenario("still_air_calibration"), duration_s=3.0, seed=11)
    a = hover_flight.flight_table().df
    b = again.flight_table().df
    num = a.select_dtypes("number").columns
    np.testing.assert_array_equal(a[num].to_numpy(), b[num].to_numpy())
    assert {"truth_main_rotor_thrust_n", "truth_main_rotor_power_w", "truth_inflow_m_s",
            "truth_rotor_speed_rad_s"} <= set(a.columns)


@pytest.mark.parametrize(("name", "pilot"), [
    ("fans_indoor", "crossover"), ("ship_airwake_b15", "crossover"),
    ("hidden_lever_arm", "crossover"), ("ship_airwake_b0", "full_state")])
def test_shipped_scenarios_fly_on_the_blade_element_truth(name, pilot):
    from hil_sim.world.run import run_scenario

    r = run_scenario(blade_scenario(name, pilot=pilot), duration_s=2.0)
    assert np.all(np.isfinite(r.body_states))
    assert np.max(np.abs(np.degrees(r.body_states[:, 6:8]))) < 30.0


def test_hidden_dynamics_effects_are_refused_on_the_blade_element_truth():
    from hil_sim.world.run import SimulationError, run_scenario

    with pytest.raises(SimulationError, match="ground_effect.*physics of its own"):
        run_scenario(blade_scenario("hidden_ground_effect"), duration_s=1.0)
