"""Hover trim, stability, units sanity and mirror symmetry of the reference models."""

import numpy as np
import pytest
from airwake.heli import load_spec
from airwake.heli.integrate import simulate
from airwake.heli.trim import linearize, trim_hover

MODELS = {name: load_spec(name) for name in ("table51", "table52")}


@pytest.mark.parametrize("name", sorted(MODELS))
def test_hover_trim_exists_and_balances_weight(name):
    m = MODELS[name]
    tr = trim_hover(m)
    assert tr.residual < 1e-9
    ctx = m.evaluate(tr.x, tr.u)
    weight = m["rigid_body"].parameters()["mass_kg"] * m["gravity"].parameters()["g_m_s2"]
    g = m["gravity"].parameters()["g_m_s2"]
    # at trim the sensed (aerodynamic) forces carry the weight exactly ...
    assert np.linalg.norm(ctx.meas[0, :3]) == pytest.approx(g, rel=1e-8)
    # ... and the main-rotor thrust provides most of it (the rest: tilted tail thrust, fins)
    assert ctx.thrust_n[0] == pytest.approx(weight, rel=0.12)


def test_table51_hover_matches_the_reference_anchors():
    m = MODELS["table51"]
    tr = trim_hover(m)
    ctx = m.evaluate(tr.x, tr.u)
    assert ctx.thrust_n[0] == pytest.approx(48.7, rel=0.01)
    assert ctx.thrust_coeff[0] == pytest.approx(0.0023, rel=0.03)
    assert 5.0 < np.degrees(tr.u[0]) < 6.0  # collective
    mr = m["main_rotor"].parameters()
    rho = m["atmosphere"].parameters()["air_density_kg_m3"]
    lock = rho * mr["chord_m"] * mr["lift_slope_per_rad"] * mr["radius_m"] ** 4
    lock /= mr["flap_inertia_kg_m2"]
    assert lock == pytest.approx(4.49, abs=0.01)
    assert lock == pytest.approx(mr["lock_number"], rel=0.01)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_hover_rotor_modes_are_stable_and_body_modes_diverge_slowly(name):
    # Helicopters are not statically stable in hover (the phugoid-like pair); the rotor,
    # lag and flybar modes must be damped and any body divergence slow (> 0.7 s to double).
    m = MODELS[name]
    tr = trim_hover(m)
    a, _ = linearize(m, tr.x, tr.u)
    keep = [i for i in range(m.n_states) if i not in (0, 1, 2, 8)]  # position, yaw: neutral
    ev = np.linalg.eigvals(a[np.ix_(keep, keep)])
    fast = ev[np.abs(ev) > 20.0]
    assert np.all(fast.real < -1.0)
    assert np.max(ev.real) < np.log(2) / 0.7


@pytest.mark.parametrize("name", sorted(MODELS))
def test_short_integration_stays_near_trim_after_a_small_kick(name):
    m = MODELS[name]
    tr = trim_hover(m)
    x0 = tr.x.copy()
    x0[9] += 0.02  # roll-rate kick, rad/s
    traj = simulate(m, x0[None], 1.0, 1 / 500, lambda t, x: tr.u[None], sample_every=50)
    dev = np.abs(traj.x[-1, 0] - tr.x)
    assert dev[6] < 0.05 and dev[7] < 0.05  # attitude within 3 deg
    assert np.all(np.abs(traj.x[:, 0, 9:12]) < 0.2)


def _mirror_state(m, x):
    y = x.copy()
    for s in ("pos_e_m", "vel_v_m_s", "roll_rad", "yaw_rad", "p_rad_s", "r_rad_s"):
        y[..., m.state_index(s)] *= -1
    return y


def test_mirrored_lateral_and_pedal_inputs_give_a_mirrored_response():
    # y -> -y maps a counter-clockwise rotor onto a clockwise one; with the rotor sense
    # flipped the whole model (tail rotor, I_xz, flapping, flybar) must be mirror-equivariant.
    rng = np.random.default_rng(3)
    ccw = MODELS["table51"].with_parameters({"main_rotor.rotation": 1.0})
    cw = MODELS["table51"].with_parameters({"main_rotor.rotation": -1.0})
    n = 64
    x = np.zeros((n, ccw.n_states))
    x[:, 3:6] = rng.normal(0, 2, (n, 3))
    x[:, 6:8] = rng.normal(0, 0.2, (n, 2))
    x[:, 8] = rng.normal(0, 1, n)
    x[:, 9:12] = rng.normal(0, 0.5, (n, 3))
    x[:, 12:] = rng.normal(0, 0.01, (n, ccw.n_states - 12))
    u = np.column_stack([rng.uniform(0.05, 0.12, n), rng.normal(0, 0.03, (n, 3))])
    w = rng.normal(0, 1, (n, 6))
    ctx_a = ccw.evaluate(x, u, w)
    um = u * [1, -1, 1, -1]
    wm = w * [1, -1, 1, -1, 1, -1]
    ctx_b = cw.evaluate(_mirror_state(cw, x), um, wm)
    np.testing.assert_allclose(ctx_b.xdot, _mirror_state(cw, ctx_a.xdot), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(ctx_b.meas, ctx_a.meas * [1, -1, 1, -1, 1, -1], rtol=1e-9, atol=1e-9)


def test_positive_lateral_cyclic_rolls_right_and_positive_pedal_yaws_right():
    for sense in (-1.0, 1.0):
        m = MODELS["table51"].with_parameters({"main_rotor.rotation": sense})
        tr = trim_hover(m)
        a, b = linearize(m, tr.x, tr.u)
        # steady rotor response: roll/yaw acceleration per input, rotor states settled
        ti = trim_hover(m)
        ctx0 = m.evaluate(ti.x, ti.u)
        x_ss = ti.x.copy()
        for k, sign in ((1, "p"), (3, "r")):
            du = np.zeros(4)
            du[k] = 0.01
            # settle the hidden states for the perturbed input
            hid = list(range(12, m.n_states))
            dh = -np.linalg.solve(a[np.ix_(hid, hid)], b[hid] @ du)
            x1 = x_ss.copy()
            x1[hid] += dh
            z = m.measure(x1, ti.u + du) - ctx0.meas
            idx = 3 if sign == "p" else 5
            assert z[0, idx] > 0, (sense, sign)
