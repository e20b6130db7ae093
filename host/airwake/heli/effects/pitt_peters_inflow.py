"""Pitt-Peters static inflow (reference [86], eq 5.5's lambda_0, lambda_c, lambda_s)."""

from __future__ import annotations

import math

import numpy as np

from airwake.heli.effects.base import Effect, register_effect
from airwake.heli.kernel import Q, kernel, solve3

_K15 = 15.0 * np.pi / 64.0
_ITERATIONS = 5
_EPS = 1e-4  # floor of V_T (keeps zero thrust at zero inflow well defined)


@register_effect("pitt_peters_inflow")
class PittPetersInflow(Effect):
    """Static Pitt-Peters inflow lambda = lambda_0 + rbar (lambda_c cos psi + lambda_s sin psi).

    With lambda_t = lambda_0 + mu_z (mu_z: air flowing down through the disk relative to the
    hub, / Omega R), V_T = sqrt(mu^2 + lambda_t^2), mass-flow V = (mu^2 + lambda_t(lambda_t +
    lambda_0))/V_T, wake skew chi = atan(mu/lambda_t), X = tan(chi/2), and the loads in
    coefficient form (C_T; m_A, m_B: first harmonics of the lift moment along / across
    the in-plane flow, m_A toward the downstream edge):
        lambda_0 = (C_T/2 - 15 pi/64 X m_A) / V_T
        lambda_A = (15 pi/64 X C_T + 4 cos chi/(1 + cos chi) m_A) / V
        lambda_B = 4/(1 + cos chi) m_B / V
    (Peters & HaQuang's L matrix written sign-free: inflow is higher where the lift is
    higher; in hover lambda_0 = C_T/(2 lambda_0) and lambda_s = m_s/lambda_0). The loads are
    affine in the inflow (main_rotor.rotor_loading), so each iteration solves a 3x3 linear
    system with the lambda_0 V_T product linearised (Newton); 5 iterations converge to
    machine precision near hover. Writes ctx.inflow_0/c/s; later inflow-stage effects
    (ground effect, wake recirculation) may modify them.
    """

    REQUIRES = ("main_rotor",)
    ITERATIONS = _ITERATIONS
    EPS = _EPS

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        bt, bm_c, bm_s = q[Q.rotor_load_base], q[Q.rotor_load_base + 1], q[Q.rotor_load_base + 2]
        j = q[Q.rotor_load_jac:Q.rotor_load_jac + 9]  # d[C_T, m_c, m_s]/d[l0, lc, ls]
        mu = q[Q.advance_ratio]
        muz = q[Q.axial_flow_ratio]
        v0x = q[Q.hub_air_velocity_rotor_m_s]
        v0y = q[Q.hub_air_velocity_rotor_m_s + 1]
        vxy = math.hypot(v0x, v0y)
        # downstream azimuth: e_r(psi_d) parallel to the in-plane air velocity
        if vxy > 1e-9:
            cd, sd = -v0x / vxy, v0y / vxy
        else:
            cd, sd = 1.0, 0.0
        # initial guess: hover momentum theory with the affine thrust
        j00 = j[0]
        lam0 = np.sign(bt) * (j00 + math.sqrt(j00 * j00 + 8.0 * abs(bt))) / 4.0
        # e_a = (0, cd, sd) picks m_A / lambda_A, e_b = (0, -sd, cd)
        ja0, ja1, ja2 = cd * j[3] + sd * j[6], cd * j[4] + sd * j[7], cd * j[5] + sd * j[8]
        jb0, jb1, jb2 = -sd * j[3] + cd * j[6], -sd * j[4] + cd * j[7], -sd * j[5] + cd * j[8]
        ba = cd * bm_c + sd * bm_s
        bb = -sd * bm_c + cd * bm_s
        jt0, jt1, jt2 = j[0], j[1], j[2]
        s0, s1, s2 = lam0, 0.0, 0.0
        for _ in range(_ITERATIONS):
            lt = lam0 + muz
            # V_T floored at half the hover inflow of the current thrust: keeps the
            # iteration defined in the vortex-ring state (lambda_t ~ 0), where momentum
            # theory has no solution; inactive in hover, climb and forward flight.
            ct = bt + (jt0 * s0 + jt1 * s1 + jt2 * s2)
            v_free = math.sqrt(mu * mu + lt * lt + _EPS**2)
            vmin = 0.5 * math.sqrt(0.5 * abs(ct))
            free = v_free >= vmin
            vt = v_free if free else vmin
            inv_vt = 1.0 / vt
            vmf = np.maximum((mu * mu + lt * (lt + lam0)) * inv_vt, _EPS)
            x = np.minimum(np.maximum(mu / np.maximum(vt + lt, 1e-9), 0.0), 1.0)
            cchi = np.minimum(np.maximum(lt * inv_vt, 0.0), 1.0)
            g2 = 4.0 / (1.0 + cchi)
            g1 = cchi * g2
            kx = _K15 * x
            # lambda_0 V_T(lambda_0) linearised about the current lambda_0
            dvt = lt * inv_vt if free else 0.0
            a0 = np.maximum(vt + lam0 * dvt, 0.5 * vt)
            b0 = lam0 * lam0 * dvt
            p0, p1, p2 = s0, s1, s2
            s0, s1, s2 = solve3(
                -0.5 * jt0 + kx * ja0 + a0, -0.5 * jt1 + kx * ja1, -0.5 * jt2 + kx * ja2,
                -(kx * jt0 + g1 * ja0), vmf * cd - (kx * jt1 + g1 * ja1),
                vmf * sd - (kx * jt2 + g1 * ja2),
                -g2 * jb0, vmf * -sd - g2 * jb1, vmf * cd - g2 * jb2,
                b0 + 0.5 * bt - kx * ba, kx * bt + g1 * ba, g2 * bb,
            )
            lam0 = s0
            if max(abs(s0 - p0), abs(s1 - p1), abs(s2 - p2)) <= 1e-13 * (
                    abs(s0) + abs(s1) + abs(s2)):
                break  # converged: more iterations change the inflow by < 1e-13
        q[Q.inflow_0] = s0
        q[Q.inflow_c] = s1
        q[Q.inflow_s] = s2
