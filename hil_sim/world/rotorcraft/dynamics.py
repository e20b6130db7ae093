"""The truth helicopter's equations of motion (Kane's method) and its own RK4 integrator.

State x (N_STATES,):

    0:3   position of the body origin (the aircraft's CG with the rotor at rest), NED, m
    3:6   velocity of the origin, body axes (u, v, w), m/s
    6:10  attitude quaternion body -> NED [w, x, y, z]
    10:13 body rates (p, q, r), rad/s
    13    main-rotor azimuth psi of blade 0 (unwrapped), rad;   14  rotor speed Omega, rad/s
    15,16 teeter angle beta and rate;   17,18 flybar teeter angle beta_f and rate
    19:22 main-rotor inflow nu_0, nu_x, nu_y (m/s);   22  tail-rotor inflow nu_t (m/s)
    23    governor integral;   24:28 servo arm angles (3 swash, tail);  28:32 their rates
    32    tail gyro's heading-hold integral (rad of tail pitch)

Multibody dynamics (Kane & Levinson, *Dynamics: Theory and Applications*, 1985, ch. 6):
generalised speeds z = (u, v, w, p, q, r, Omega, beta', beta_f'). Every mass point P
(blade and paddle elements, the flybar rod, the rigid remainder at its centre of mass)
moves with v_P = v + w x r_P + r_P' (r_P' from the rotor's turning and teetering), so its
partial velocities V_k = d v_P / d z_k are e_k (k < 3), e_k x r_P (k = 3..5), dp/dpsi,
dp/dbeta, dp/dbeta_f. Kane's equations

    sum_P m_P V_k . V_l  z_l'  =  sum_P (F_P - m_P a0_P) . V_k  + Q_k,   k = 0..8

(a0_P: the point's acceleration at zero z', F_P: its aerodynamic and gravity forces, Q_k:
hub spring and damper, motor torque, the rigid remainder's rotational inertia and the
spinning shaft's and tail rotor's polar inertia) give the mass matrix and right-hand
side; a Cholesky solve gives z'. The hub loads, the rotor torque and its reaction on the
fuselage, the teeter and flybar equations with all their gyroscopic and hub-motion
terms, and the vibration of a two-bladed rotor (its inertia is not axisymmetric, its
loads pulse twice a revolution, blade 0 is heavier) all come out of these sums; no
closed-form rotor expression is used.

Air at each element: the wind field sampled where the element is (a body-fixed grid
around the aircraft, refreshed from the field, `flight.py`), plus the induced flows of
`inflow.py`. Integration: classical RK4 at fixed step (`integrate`); inputs linear over
the call, the wind grid linear in time between its two snapshots.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from hil_sim.world.rotorcraft.airfoil import SECTION
from hil_sim.world.rotorcraft.blade_element import (
    prandtl_tip_loss,
    section_load,
    teeter_point,
    teeter_velocity_terms,
)
from hil_sim.world.rotorcraft.drive import DRV_SHAFT_INERTIA, drive
from hil_sim.world.rotorcraft.flybar import FB_DAMPING, FB_PHASE_LEAD
from hil_sim.world.rotorcraft.fuselage import (
    FUS_L_REF,
    FUS_REF_X,
    FUS_S_REF,
    fuselage_coefficients,
    surface_load,
)
from hil_sim.world.rotorcraft.inflow import (
    momentum_inflow_rate,
    pitt_peters_rates,
    radial_shape,
    wake_skew,
    wake_velocity,
)
from hil_sim.world.rotorcraft.main_rotor import (
    MR_AREA,
    MR_BELL,
    MR_CHORD,
    MR_DAMPING,
    MR_HILLER,
    MR_HUB_X,
    MR_N_BLADES,
    MR_PADDLE_GAIN,
    MR_PHASE,
    MR_RADIUS,
    MR_SENSE,
    MR_SPRING,
    swash_feathering,
)
from hil_sim.world.rotorcraft.servos import (
    SRV_RATE,
    SRV_TAIL_RATE,
    SRV_TAIL_WN,
    SRV_TAIL_ZETA,
    SRV_WN,
    SRV_ZETA,
    servo_acceleration,
    servo_commands,
    swash_and_tail,
    tail_gyro,
)
from hil_sim.world.rotorcraft.tail_rotor import (
    TR_AREA,
    TR_CHORD,
    TR_GEAR,
    TR_HUB_X,
    TR_INERTIA,
    TR_N_BLADES,
    TR_RADIUS,
    TR_SENSE,
    tail_point,
)

POS, VEL, QUAT, RATES, PSI, OMEGA, BETA, BETA_DOT, FLY, FLY_DOT, NU0, NUX, NUY, NUT, GOV, \
    SERVO, SERVO_RATE, GYRO = 0, 3, 6, 10, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 28, 32
N_STATES = 33
N_SPEEDS = 9

# rigid remainder: [mass, cg x, y, z, Jxx, Jyy, Jzz, Jxz]
BODY_MASS, BODY_CG, BODY_J = 0, 1, 4
# environment scalars: [t0 of snapshot 0, t1 of snapshot 1, grid lo (3), 1 / step (3),
# air density, gravity]
ENV_T0, ENV_T1, ENV_LO, ENV_INV, ENV_RHO, ENV_G = 0, 1, 2, 5, 8, 9
N_ENV = 10
# aux outputs per step
AUX_SPECIFIC_FORCE, AUX_ANG_ACC, AUX_THRUST, AUX_POWER, AUX_NU0, AUX_TAIL_THRUST, \
    AUX_CURRENT, AUX_DUTY, AUX_PITCH, AUX_TAIL_PITCH, AUX_TORQUE, AUX_OMEGA_DOT, \
    AUX_TAIL_COMMAND = 0, 3, 6, 7, 8, 9, 10, 11, 12, 15, 16, 17, 18
N_AUX = 19
# Prandtl's factor is 1 to 1e-3 inboard of half the radius at rotor inflow angles (f > 6)
TIP_LOSS_FROM = 0.5
# captive modes: free flight, body held, body held at a fixed rotor speed
FREE, BODY_HELD, SPEED_HELD = 0, 1, 2


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def quat_dcm(q):
    """Body -> NED rotation matrix of a unit quaternion [w, x, y, z]."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    r = np.empty((3, 3))
    r[0, 0] = 1 - 2 * (y * y + z * z)
    r[0, 1] = 2 * (x * y - w * z)
    r[0, 2] = 2 * (x * z + w * y)
    r[1, 0] = 2 * (x * y + w * z)
    r[1, 1] = 1 - 2 * (x * x + z * z)
    r[1, 2] = 2 * (y * z - w * x)
    r[2, 0] = 2 * (x * z - w * y)
    r[2, 1] = 2 * (y * z + w * x)
    r[2, 2] = 1 - 2 * (x * x + y * y)
    return r


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _grid_wind(px, py, pz, env, wg, rot):
    """Wind at a body point, trilinear in the body-fixed grid snapshot wg (already blended
    in time), returned in body axes."""
    nx, ny, nz = wg.shape[0], wg.shape[1], wg.shape[2]
    gx = (px - env[ENV_LO]) * env[ENV_INV]
    gy = (py - env[ENV_LO + 1]) * env[ENV_INV + 1]
    gz = (pz - env[ENV_LO + 2]) * env[ENV_INV + 2]
    i = min(max(int(math.floor(gx)), 0), nx - 2)
    j = min(max(int(math.floor(gy)), 0), ny - 2)
    k = min(max(int(math.floor(gz)), 0), nz - 2)
    fx = min(max(gx - i, 0.0), 1.0)
    fy = min(max(gy - j, 0.0), 1.0)
    fz = min(max(gz - k, 0.0), 1.0)
    out0 = 0.0
    out1 = 0.0
    out2 = 0.0
    for a in range(2):
        wa = fx if a else 1.0 - fx
        for b in range(2):
            wb = wa * (fy if b else 1.0 - fy)
            for c in range(2):
                wc = wb * (fz if c else 1.0 - fz)
                out0 += wc * wg[i + a, j + b, k + c, 0]
                out1 += wc * wg[i + a, j + b, k + c, 1]
                out2 += wc * wg[i + a, j + b, k + c, 2]
    # NED -> body: R^T w
    return (rot[0, 0] * out0 + rot[1, 0] * out1 + rot[2, 0] * out2,
            rot[0, 1] * out0 + rot[1, 1] * out1 + rot[2, 1] * out2,
            rot[0, 2] * out0 + rot[1, 2] * out1 + rot[2, 2] * out2)


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _grid_upwash(px, py, env, g0, g1, f):
    """Ground/deck upwash per unit nu_0 at a body point (bilinear on the grid's x, y)."""
    nx, ny = g0.shape[0], g0.shape[1]
    gx = (px - env[ENV_LO]) * env[ENV_INV]
    gy = (py - env[ENV_LO + 1]) * env[ENV_INV + 1]
    i = min(max(int(math.floor(gx)), 0), nx - 2)
    j = min(max(int(math.floor(gy)), 0), ny - 2)
    fx = min(max(gx - i, 0.0), 1.0)
    fy = min(max(gy - j, 0.0), 1.0)
    v = 0.0
    for a in range(2):
        for b in range(2):
            w = (fx if a else 1.0 - fx) * (fy if b else 1.0 - fy)
            v += w * ((1.0 - f) * g0[i + a, j + b] + f * g1[i + a, j + b])
    return v


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _add_mass(mm, rhs, m, r, vpsi, vb, ib, force, a0):
    """Add one mass point's terms to Kane's mass matrix (upper triangle) and right-hand side.

    r: position (body); vpsi: dp/dpsi (partial velocity for Omega); vb: the partial velocity
    of teeter speed ib (7 or 8; -1 for none); force: applied force on it; a0: its
    acceleration at zero generalised accelerations. The partial velocities are e_i
    (i < 3), e_k x r (k = 3..5), vpsi and vb; their dot products are written out:
    e_i . (e_k x r) = (e_k x r)_i, (e_k x r) . (e_l x r) = |r|^2 delta_kl - r_k r_l,
    (e_k x r) . a = (r x a)_k."""
    rx, ry, rz = r[0], r[1], r[2]
    gx = force[0] - m * a0[0]
    gy = force[1] - m * a0[1]
    gz = force[2] - m * a0[2]
    rhs[0] += gx
    rhs[1] += gy
    rhs[2] += gz
    rhs[3] += ry * gz - rz * gy
    rhs[4] += rz * gx - rx * gz
    rhs[5] += rx * gy - ry * gx
    rhs[6] += vpsi[0] * gx + vpsi[1] * gy + vpsi[2] * gz
    mm[0, 0] += m
    mm[1, 1] += m
    mm[2, 2] += m
    # e_i . (e_k x r): e_x x r = (0, -rz, ry), e_y x r = (rz, 0, -rx), e_z x r = (-ry, rx, 0)
    mm[0, 4] += m * rz
    mm[0, 5] -= m * ry
    mm[1, 3] -= m * rz
    mm[1, 5] += m * rx
    mm[2, 3] += m * ry
    mm[2, 4] -= m * rx
    r2 = rx * rx + ry * ry + rz * rz
    mm[3, 3] += m * (r2 - rx * rx)
    mm[3, 4] -= m * rx * ry
    mm[3, 5] -= m * rx * rz
    mm[4, 4] += m * (r2 - ry * ry)
    mm[4, 5] -= m * ry * rz
    mm[5, 5] += m * (r2 - rz * rz)
    px, py, pz = vpsi[0], vpsi[1], vpsi[2]
    mm[0, 6] += m * px
    mm[1, 6] += m * py
    mm[2, 6] += m * pz
    mm[3, 6] += m * (ry * pz - rz * py)
    mm[4, 6] += m * (rz * px - rx * pz)
    mm[5, 6] += m * (rx * py - ry * px)
    mm[6, 6] += m * (px * px + py * py + pz * pz)
    if ib >= 0:
        bx, by, bz = vb[0], vb[1], vb[2]
        rhs[ib] += bx * gx + by * gy + bz * gz
        mm[0, ib] += m * bx
        mm[1, ib] += m * by
        mm[2, ib] += m * bz
        mm[3, ib] += m * (ry * bz - rz * by)
        mm[4, ib] += m * (rz * bx - rx * bz)
        mm[5, ib] += m * (rx * by - ry * bx)
        mm[6, ib] += m * (px * bx + py * by + pz * bz)
        mm[ib, ib] += m * (bx * bx + by * by + bz * bz)


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _add_force(rhs, r, vpsi, force):
    """A force without mass (aerodynamic point load) at body point r moving with dp/dpsi."""
    rhs[0] += force[0]
    rhs[1] += force[1]
    rhs[2] += force[2]
    # (e_k x r) . F = (r x F)_k
    rhs[3] += r[1] * force[2] - r[2] * force[1]
    rhs[4] += r[2] * force[0] - r[0] * force[2]
    rhs[5] += r[0] * force[1] - r[1] * force[0]
    rhs[6] += vpsi[0] * force[0] + vpsi[1] * force[1] + vpsi[2] * force[2]


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _point_a0(w, v, r, rdot, rdd, a):
    """a0 = w x v + w x (w x r) + 2 w x rdot + rdd (body axes), written into a."""
    c1 = _cross(w[0], w[1], w[2], v[0], v[1], v[2])
    wr = _cross(w[0], w[1], w[2], r[0], r[1], r[2])
    c2 = _cross(w[0], w[1], w[2], wr[0], wr[1], wr[2])
    c3 = _cross(w[0], w[1], w[2], rdot[0], rdot[1], rdot[2])
    for i in range(3):
        a[i] = c1[i] + c2[i] + 2.0 * c3[i] + rdd[i]


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _solve_spd(mm, rhs):
    """Cholesky solve of the symmetric positive-definite system (upper triangle filled)."""
    n = rhs.size
    a = np.zeros((n, n))
    for i in range(n):
        for j in range(i, n):
            a[i, j] = mm[i, j]
            a[j, i] = mm[i, j]
    low = np.zeros((n, n))
    for i in range(n):
        for j in range(i + 1):
            s = a[i, j]
            for k in range(j):
                s -= low[i, k] * low[j, k]
            if i == j:
                low[i, i] = math.sqrt(max(s, 1e-18))
            else:
                low[i, j] = s / low[j, j]
    y = np.empty(n)
    for i in range(n):
        s = rhs[i]
        for k in range(i):
            s -= low[i, k] * y[k]
        y[i] = s / low[i, i]
    out = np.empty(n)
    for i in range(n - 1, -1, -1):
        s = y[i]
        for k in range(i + 1, n):
            s -= low[k, i] * out[k]
        out[i] = s / low[i, i]
    return out


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _teeter_element(sign, r, cpsi, spsi, cbeta, sbeta, s, omega, rate, hub, r_e, vpsi, vb,
                    rdot, rdd):
    """Kinematics of a teetering blade's (or paddle's) point: blade `sign` (+1 at psi, -1 at
    psi + pi with the opposite teeter) at radius r, the shaft at (cpsi, spsi), the teeter
    at (cbeta, sbeta) and its rate. Fills its body position r_e, partial velocities vpsi
    (Omega) and vb (teeter rate), its velocity relative to the body rdot and the
    velocity-dependent part of its acceleration rdd; returns (p, e_t, e_u)."""
    cp, sp, sb = sign * cpsi, sign * spsi, sign * sbeta
    p, p_psi, p_beta, e_t, e_u = teeter_point(cp, sp, cbeta, sb, s, r)
    for i in range(3):
        r_e[i] = hub[i] + p[i]
        vpsi[i] = p_psi[i]
        vb[i] = sign * p_beta[i]
        rdot[i] = omega * p_psi[i] + rate * vb[i]
    dd = teeter_velocity_terms(cp, sp, cbeta, sb, s, r, omega, sign * rate)
    for i in range(3):
        rdd[i] = dd[i]
    return p, e_t, e_u


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def _air_relative(r_e, rdot, down, v, w, env, wg, rot):
    """Air velocity relative to a point at r_e moving with rdot relative to the body, with
    `down` m/s of induced flow added along +z (body axes)."""
    wr = _cross(w[0], w[1], w[2], r_e[0], r_e[1], r_e[2])
    air = _grid_wind(r_e[0], r_e[1], r_e[2], env, wg, rot)
    return (air[0] - (v[0] + wr[0] + rdot[0]), air[1] - (v[1] + wr[1] + rdot[1]),
            air[2] + down - (v[2] + wr[2] + rdot[2]))


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def rates(t, x, delta, body, mr, mre, fb, fbe, tr, tre, fus, fus_tab, emp, drv, srv, env,
          w0, w1, g0, g1, xdot, aux, captive, wg):
    """dx/dt (written into xdot) and the auxiliary outputs (aux) at state x, radio
    command delta (4,). `captive`: hold the body (rotor, drive, servos and inflow run; the
    body accelerations the loads would cause are still returned in aux) — trim and
    linearisation use it; SPEED_HELD also holds the rotor speed, reporting its
    acceleration in aux."""
    table = SECTION
    rho = env[ENV_RHO]
    f_t = 0.0
    if env[ENV_T1] > env[ENV_T0]:
        f_t = min(max((t - env[ENV_T0]) / (env[ENV_T1] - env[ENV_T0]), 0.0), 1.0)
    v = x[VEL:VEL + 3]
    q = x[QUAT:QUAT + 4]
    w = x[RATES:RATES + 3]
    psi = x[PSI]
    omega = x[OMEGA]
    beta = x[BETA]
    beta_d = x[BETA_DOT]
    fly = x[FLY]
    fly_d = x[FLY_DOT]
    nu0, nux, nuy, nut = x[NU0], x[NUX], x[NUY], x[NUT]
    rot = quat_dcm(q)
    # the wind grid at t: linear between the two snapshots (into the scratch wg)
    flat0 = w0.reshape(-1)
    flat1 = w1.reshape(-1)
    flat = wg.reshape(-1)
    for i in range(flat.size):
        flat[i] = flat0[i] + f_t * (flat1[i] - flat0[i])
    grav = env[ENV_G]
    gb = (rot[2, 0] * grav, rot[2, 1] * grav, rot[2, 2] * grav)  # R^T (0, 0, g)

    # -- servos -> swashplate and tail pitch -----------------------------------------
    cmd = np.empty(4)
    tail_cmd, dgyro = tail_gyro(delta[3], w[2], x[GYRO], srv)
    servo_commands(delta, tail_cmd, srv, cmd)
    h0, slat, slon, tail_pitch = swash_and_tail(x[SERVO:SERVO + 4], srv)

    mm = np.zeros((N_SPEEDS, N_SPEEDS))
    rhs = np.zeros(N_SPEEDS)
    zero3 = np.zeros(3)

    # -- rigid remainder -------------------------------------------------------------
    mb = body[BODY_MASS]
    rb = body[BODY_CG:BODY_CG + 3]
    a0 = np.empty(3)
    _point_a0(w, v, rb, zero3, zero3, a0)
    fgrav = np.array([mb * gb[0], mb * gb[1], mb * gb[2]])
    _add_mass(mm, rhs, mb, rb, zero3, zero3, -1, fgrav, a0)
    jxx, jyy, jzz, jxz = body[BODY_J], body[BODY_J + 1], body[BODY_J + 2], body[BODY_J + 3]
    mm[3, 3] += jxx
    mm[4, 4] += jyy
    mm[5, 5] += jzz
    mm[3, 5] -= jxz
    hx = jxx * w[0] - jxz * w[2]
    hy = jyy * w[1]
    hz = jzz * w[2] - jxz * w[0]
    c = _cross(w[0], w[1], w[2], hx, hy, hz)
    rhs[3] -= c[0]
    rhs[4] -= c[1]
    rhs[5] -= c[2]

    # -- spinning shaft (hub, grips, gears, motor) and tail rotor: polar inertia -------
    s = mr[MR_SENSE]
    i_s = drv[DRV_SHAFT_INERTIA]
    mm[5, 5] += i_s
    mm[5, 6] += i_s * s
    mm[6, 6] += i_s
    hs = i_s * (w[2] + s * omega)
    rhs[3] -= w[1] * hs  # -(w x (0, 0, hs))
    rhs[4] += w[0] * hs
    s_t = tr[TR_SENSE]
    gear_t = tr[TR_GEAR]
    i_t = tr[TR_INERTIA]
    mm[4, 4] += i_t
    mm[4, 6] += i_t * s_t * gear_t
    mm[6, 6] += i_t * gear_t * gear_t
    ht = i_t * (w[1] + s_t * gear_t * omega)
    rhs[3] += w[2] * ht  # -(w x (0, ht, 0))
    rhs[5] -= w[0] * ht

    # -- drive -----------------------------------------------------------------------
    torque, current, duty, dgov = drive(omega, x[GOV], drv)
    rhs[6] += torque

    # -- main rotor ------------------------------------------------------------------
    radius = mr[MR_RADIUS]
    hub = mr[MR_HUB_X:MR_HUB_X + 3]
    area = mr[MR_AREA]
    vtip = max(omega * radius, 1.0)
    coef = 1.0 / (rho * area * vtip * vtip)
    # air at the hub relative to the hub (for the inflow and the wake)
    ah = _grid_wind(hub[0], hub[1], hub[2], env, wg, rot)
    wh = _cross(w[0], w[1], w[2], hub[0], hub[1], hub[2])
    vhx = ah[0] - (v[0] + wh[0])
    vhy = ah[1] - (v[1] + wh[1])
    vhz = ah[2] - (v[2] + wh[2])
    chi, sx, sy = wake_skew(vhx, vhy, vhz, nu0)
    thrust = 0.0
    mom_x = 0.0
    mom_y = 0.0
    q_gen = 0.0  # generalised aerodynamic force on Omega (= -torque)
    bell = mr[MR_BELL]
    hiller = mr[MR_HILLER]
    phase = mr[MR_PHASE]
    chord = mr[MR_CHORD]
    n_blades = mr[MR_N_BLADES]
    r_e = np.empty(3)
    rdot = np.empty(3)
    rdd = np.empty(3)
    vb_part = np.empty(3)
    vpsi = np.empty(3)
    force = np.empty(3)
    cyclic = bell * swash_feathering(psi, s, phase, slat, slon) + hiller * fly
    cpsi, spsi = math.cos(psi), math.sin(psi)
    cbeta, sbeta = math.cos(beta), math.sin(beta)
    for e in range(mre.shape[0]):
        sign = mre[e, 0]
        r = mre[e, 1]
        p, e_t, e_u = _teeter_element(sign, r, cpsi, spsi, cbeta, sbeta, s, omega, beta_d, hub,
                                      r_e, vpsi, vb_part, rdot, rdd)
        ge = _grid_upwash(r_e[0], r_e[1], env, g0, g1, f_t)
        nu = nu0 * (radial_shape(r / radius) - ge) + nux * p[0] / radius + nuy * p[1] / radius
        ux, uy, uz = _air_relative(r_e, rdot, nu, v, w, env, wg, rot)
        # blade pitch: collective + Bell + Hiller (+ twist, track on blade 1)
        theta = h0 + mre[e, 4] + sign * cyclic
        ut = -(ux * e_t[0] + uy * e_t[1] + uz * e_t[2])
        up = ux * e_u[0] + uy * e_u[1] + uz * e_u[2]
        tip = 1.0
        if r > TIP_LOSS_FROM * radius:
            tip = prandtl_tip_loss(n_blades, r / radius, math.atan2(-up, abs(ut) + 1e-9))
        fx, fy, fz, _, _, _ = section_load(ux, uy, uz, e_t[0], e_t[1], e_t[2], e_u[0],
                                           e_u[1], e_u[2], theta, chord, mre[e, 2], rho,
                                           tip, table)
        m = mre[e, 3]
        force[0] = fx + m * gb[0]
        force[1] = fy + m * gb[1]
        force[2] = fz + m * gb[2]
        _point_a0(w, v, r_e, rdot, rdd, a0)
        _add_mass(mm, rhs, m, r_e, vpsi, vb_part, 7, force, a0)
        thrust -= fz
        mom_x -= fz * p[0]
        mom_y -= fz * p[1]
        q_gen += fx * vpsi[0] + fy * vpsi[1] + fz * vpsi[2]
    # hub spring and damper on the teeter
    rhs[7] += -mr[MR_SPRING] * beta - mr[MR_DAMPING] * beta_d

    # -- flybar ------------------------------------------------------------------------
    paddle_gain = mr[MR_PADDLE_GAIN]
    lead = fb[FB_PHASE_LEAD]
    cfp, sfp = math.cos(psi + lead), math.sin(psi + lead)
    cfb, sfb = math.cos(fly), math.sin(fly)
    feather_f = paddle_gain * swash_feathering(psi + lead, s, phase, slat, slon)
    for e in range(fbe.shape[0]):
        sign = fbe[e, 0]
        r = fbe[e, 1]
        p, e_t, e_u = _teeter_element(sign, r, cfp, sfp, cfb, sfb, s, omega, fly_d, hub, r_e,
                                      vpsi, vb_part, rdot, rdd)
        m = fbe[e, 3]
        force[0] = m * gb[0]
        force[1] = m * gb[1]
        force[2] = m * gb[2]
        if fbe[e, 5] > 0.0:
            ge = _grid_upwash(r_e[0], r_e[1], env, g0, g1, f_t)
            nu = (nu0 * (radial_shape(r / radius) - ge) + nux * p[0] / radius
                  + nuy * p[1] / radius)
            ux, uy, uz = _air_relative(r_e, rdot, nu, v, w, env, wg, rot)
            theta = sign * feather_f
            fx, fy, fz, _, _, _ = section_load(ux, uy, uz, e_t[0], e_t[1], e_t[2], e_u[0],
                                               e_u[1], e_u[2], theta, fbe[e, 4], fbe[e, 2],
                                               rho, 1.0, table)
            force[0] += fx
            force[1] += fy
            force[2] += fz
            q_gen += fx * vpsi[0] + fy * vpsi[1] + fz * vpsi[2]
        _point_a0(w, v, r_e, rdot, rdd, a0)
        _add_mass(mm, rhs, m, r_e, vpsi, vb_part, 8, force, a0)
    rhs[8] += -fb[FB_DAMPING] * fly_d

    # -- tail rotor ------------------------------------------------------------------------
    thub = tr[TR_HUB_X:TR_HUB_X + 3]
    t_radius = tr[TR_RADIUS]
    t_omega = gear_t * omega
    t_vtip = max(t_omega * t_radius, 1.0)
    cphi, sphi = math.cos(gear_t * psi), math.sin(gear_t * psi)
    t_thrust = 0.0
    # air at the tail hub (wind + main-rotor wake) relative to the hub
    at = _grid_wind(thub[0], thub[1], thub[2], env, wg, rot)
    wake_t = wake_velocity(thub[0] - hub[0], thub[1] - hub[1], thub[2] - hub[2], radius,
                           nu0, chi, sx, sy)
    wt = _cross(w[0], w[1], w[2], thub[0], thub[1], thub[2])
    tvx = at[0] - (v[0] + wt[0])
    tvy = at[1] - (v[1] + wt[1])
    tvz = at[2] + wake_t - (v[2] + wt[2])
    for e in range(tre.shape[0]):
        sign = tre[e, 0]
        r = tre[e, 1]
        p, p_phi, e_t = tail_point(sign * cphi, sign * sphi, s_t, r)
        for i in range(3):
            r_e[i] = thub[i] + p[i]
            vpsi[i] = gear_t * p_phi[i]
        wr = _cross(w[0], w[1], w[2], r_e[0], r_e[1], r_e[2])
        air = _grid_wind(r_e[0], r_e[1], r_e[2], env, wg, rot)
        ux = air[0] - (v[0] + wr[0] + omega * vpsi[0])
        uy = air[1] + nut - (v[1] + wr[1] + omega * vpsi[1])
        uz = air[2] + wake_t - (v[2] + wr[2] + omega * vpsi[2])
        ut = -(ux * e_t[0] + uz * e_t[2])
        up = -uy
        tip = 1.0
        if r > TIP_LOSS_FROM * t_radius:
            tip = prandtl_tip_loss(tr[TR_N_BLADES], r / t_radius,
                                   math.atan2(-up, abs(ut) + 1e-9))
        fx, fy, fz, _, _, _ = section_load(ux, uy, uz, e_t[0], e_t[1], e_t[2], 0.0, -1.0, 0.0,
                                           tail_pitch, tr[TR_CHORD], tre[e, 2], rho, tip,
                                           table)
        force[0] = fx
        force[1] = fy
        force[2] = fz
        _add_force(rhs, r_e, vpsi, force)
        t_thrust -= fy

    # -- fuselage and empennage --------------------------------------------------------------
    rf = fus[FUS_REF_X:FUS_REF_X + 3]
    air = _grid_wind(rf[0], rf[1], rf[2], env, wg, rot)
    wake_f = wake_velocity(rf[0] - hub[0], rf[1] - hub[1], rf[2] - hub[2], radius, nu0, chi,
                           sx, sy)
    wr = _cross(w[0], w[1], w[2], rf[0], rf[1], rf[2])
    bx = v[0] + wr[0] - air[0]
    by = v[1] + wr[1] - air[1]
    bz = v[2] + wr[2] - air[2] - wake_f
    speed2 = bx * bx + by * by + bz * bz
    if speed2 > 1e-6:
        speed = math.sqrt(speed2)
        cf = fuselage_coefficients(bx / speed, by / speed, bz / speed, fus_tab)
        qs = 0.5 * rho * speed2 * fus[FUS_S_REF]
        for i in range(3):
            force[i] = qs * cf[i]
            vpsi[i] = 0.0
        _add_force(rhs, rf, vpsi, force)
        ql = qs * fus[FUS_L_REF]
        rhs[3] += ql * cf[3]
        rhs[4] += ql * cf[4]
        rhs[5] += ql * cf[5]
    for e in range(emp.shape[0]):
        for i in range(3):
            r_e[i] = emp[e, i]
            vpsi[i] = 0.0
        air = _grid_wind(r_e[0], r_e[1], r_e[2], env, wg, rot)
        wake_e = wake_velocity(r_e[0] - hub[0], r_e[1] - hub[1], r_e[2] - hub[2], radius, nu0,
                               chi, sx, sy)
        wr = _cross(w[0], w[1], w[2], r_e[0], r_e[1], r_e[2])
        fx, fy, fz = surface_load(air[0] - (v[0] + wr[0]), air[1] - (v[1] + wr[1]),
                                  air[2] + wake_e - (v[2] + wr[2]), emp[e], rho, table)
        force[0] = fx
        force[1] = fy
        force[2] = fz
        _add_force(rhs, r_e, vpsi, force)

    # -- solve ----------------------------------------------------------------------------
    zd = _solve_spd(mm, rhs)
    zr = zd[6:9]
    if captive:
        # body held: the rotor, drive and servos run against a fixed shaft
        sub = np.zeros((3, 3))
        for i in range(3):
            for j in range(i, 3):
                sub[i, j] = mm[6 + i, 6 + j]
        zr = _solve_spd(sub, rhs[6:9])
    # -- state derivative ---------------------------------------------------------------------
    for i in range(N_STATES):
        xdot[i] = 0.0
    if not captive:
        for i in range(3):
            xdot[POS + i] = rot[i, 0] * v[0] + rot[i, 1] * v[1] + rot[i, 2] * v[2]
            xdot[VEL + i] = zd[i]
            xdot[RATES + i] = zd[3 + i]
        xdot[QUAT] = 0.5 * (-q[1] * w[0] - q[2] * w[1] - q[3] * w[2])
        xdot[QUAT + 1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1])
        xdot[QUAT + 2] = 0.5 * (q[0] * w[1] - q[1] * w[2] + q[3] * w[0])
        xdot[QUAT + 3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0])
        xdot[OMEGA] = zd[6]
        xdot[BETA_DOT] = zd[7]
        xdot[FLY_DOT] = zd[8]
    else:
        xdot[OMEGA] = zr[0] if captive == BODY_HELD else 0.0
        xdot[BETA_DOT] = zr[1]
        xdot[FLY_DOT] = zr[2]
    xdot[PSI] = omega
    xdot[BETA] = beta_d
    xdot[FLY] = fly_d
    d0, dx_, dy_ = pitt_peters_rates(nu0, nux, nuy, thrust * coef, mom_x * coef / radius,
                                     mom_y * coef / radius, vhx, vhy, vhz, omega, radius)
    xdot[NU0] = d0
    xdot[NUX] = dx_
    xdot[NUY] = dy_
    c_tt = t_thrust / (rho * tr[TR_AREA] * t_vtip * t_vtip)
    xdot[NUT] = momentum_inflow_rate(nut, c_tt, math.sqrt(tvx * tvx + tvz * tvz), tvy,
                                     t_omega, t_radius)
    xdot[GOV] = dgov
    xdot[GYRO] = dgyro
    for i in range(4):
        wn = srv[SRV_WN] if i < 3 else srv[SRV_TAIL_WN]
        zeta = srv[SRV_ZETA] if i < 3 else srv[SRV_TAIL_ZETA]
        rate = srv[SRV_RATE] if i < 3 else srv[SRV_TAIL_RATE]
        xdot[SERVO + i] = x[SERVO_RATE + i]
        xdot[SERVO_RATE + i] = servo_acceleration(x[SERVO + i], x[SERVO_RATE + i], cmd[i], wn,
                                                  zeta, rate)
    # -- auxiliary outputs ----------------------------------------------------------------------
    cv = _cross(w[0], w[1], w[2], v[0], v[1], v[2])
    for i in range(3):
        aux[AUX_SPECIFIC_FORCE + i] = zd[i] + cv[i] - gb[i]
        aux[AUX_ANG_ACC + i] = zd[3 + i]
    aux[AUX_THRUST] = thrust
    aux[AUX_POWER] = -q_gen * omega
    aux[AUX_TORQUE] = -q_gen
    aux[AUX_NU0] = nu0
    aux[AUX_TAIL_THRUST] = t_thrust
    aux[AUX_CURRENT] = current
    aux[AUX_DUTY] = duty
    aux[AUX_PITCH] = h0
    aux[AUX_PITCH + 1] = slat
    aux[AUX_PITCH + 2] = slon
    aux[AUX_TAIL_PITCH] = tail_pitch
    aux[AUX_OMEGA_DOT] = zr[0]
    aux[AUX_TAIL_COMMAND] = tail_cmd


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def integrate(x, t0, dt, n, delta0, delta1, body, mr, mre, fb, fbe, tr, tre, fus, fus_tab,
              emp, drv, srv, env, w0, w1, g0, g1, out_x, out_aux, out_start, captive):
    """n classical RK4 steps of dt from (t0, x) (x updated in place); the command is
    linear from delta0 at t0 to delta1 at t0 + n dt. Writes the state at the start of
    each step and its aux outputs into out_x / out_aux rows out_start.. (skipped when
    out_start < 0). Returns the final time."""
    s = N_STATES
    k1 = np.empty(s)
    k2 = np.empty(s)
    k3 = np.empty(s)
    k4 = np.empty(s)
    xs = np.empty(s)
    aux = np.empty(N_AUX)
    scratch = np.empty(N_AUX)
    wg = np.empty_like(w0)
    d = np.empty(4)
    span = n * dt
    t = t0
    for step in range(n):
        f0 = (t - t0) / span if span > 0 else 0.0
        for i in range(4):
            d[i] = delta0[i] + f0 * (delta1[i] - delta0[i])
        rates(t, x, d, body, mr, mre, fb, fbe, tr, tre, fus, fus_tab, emp, drv, srv, env, w0,
              w1, g0, g1, k1, aux, captive, wg)
        if out_start >= 0:
            out_x[out_start + step, :] = x
            out_aux[out_start + step, :] = aux
        fm = (t + 0.5 * dt - t0) / span if span > 0 else 0.0
        for i in range(4):
            d[i] = delta0[i] + fm * (delta1[i] - delta0[i])
        for i in range(s):
            xs[i] = x[i] + 0.5 * dt * k1[i]
        rates(t + 0.5 * dt, xs, d, body, mr, mre, fb, fbe, tr, tre, fus, fus_tab, emp, drv,
              srv, env, w0, w1, g0, g1, k2, scratch, captive, wg)
        for i in range(s):
            xs[i] = x[i] + 0.5 * dt * k2[i]
        rates(t + 0.5 * dt, xs, d, body, mr, mre, fb, fbe, tr, tre, fus, fus_tab, emp, drv,
              srv, env, w0, w1, g0, g1, k3, scratch, captive, wg)
        f1 = (t + dt - t0) / span if span > 0 else 0.0
        for i in range(4):
            d[i] = delta0[i] + f1 * (delta1[i] - delta0[i])
        for i in range(s):
            xs[i] = x[i] + dt * k3[i]
        rates(t + dt, xs, d, body, mr, mre, fb, fbe, tr, tre, fus, fus_tab, emp, drv, srv, env,
              w0, w1, g0, g1, k4, scratch, captive, wg)
        for i in range(s):
            x[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        nq = math.sqrt(x[QUAT] ** 2 + x[QUAT + 1] ** 2 + x[QUAT + 2] ** 2 + x[QUAT + 3] ** 2)
        for i in range(4):
            x[QUAT + i] /= nq
        t = t0 + (step + 1) * dt
    return t
