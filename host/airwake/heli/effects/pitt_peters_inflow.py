"""Pitt-Peters static inflow (reference [86], eq 5.5's lambda_0, lambda_c, lambda_s)."""

from __future__ import annotations

import numpy as np

from airwake.heli.effects.base import Effect, register_effect

_K15 = 15.0 * np.pi / 64.0


def solve3(m: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Solve a batch of 3x3 systems m (N,3,3) y = r (N,3) by Cramer's rule (np.linalg.solve
    costs ~1 ms per batch of 2000 on small systems)."""
    a, b, c = m[:, 0, 0], m[:, 0, 1], m[:, 0, 2]
    d, e, f = m[:, 1, 0], m[:, 1, 1], m[:, 1, 2]
    g, h, i = m[:, 2, 0], m[:, 2, 1], m[:, 2, 2]
    co0 = e * i - f * h
    co1 = f * g - d * i
    co2 = d * h - e * g
    det = a * co0 + b * co1 + c * co2
    r0, r1, r2 = r[:, 0], r[:, 1], r[:, 2]
    y0 = r0 * co0 + b * (f * r2 - r1 * i) + c * (r1 * h - e * r2)
    y1 = a * (r1 * i - f * r2) + r0 * co1 + c * (d * r2 - r1 * g)
    y2 = a * (e * r2 - r1 * h) + b * (r1 * g - d * r2) + r0 * co2
    return np.stack([y0, y1, y2], -1) / det[:, None]


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
    ITERATIONS = 5
    EPS = 1e-4  # floor of V_T (keeps zero thrust at zero inflow well defined)

    def inflow(self, ctx, p) -> None:
        base = ctx.rotor_load_base  # (N,3): C_T, m_c, m_s at zero inflow
        jac = ctx.rotor_load_jac  # (N,3,3) d[C_T, m_c, m_s]/d[l0, lc, ls]
        mu = ctx.advance_ratio
        muz = ctx.axial_flow_ratio
        v0 = ctx._cache["rotor_frame"]["v0"]
        vxy = np.hypot(v0[:, 0], v0[:, 1])
        safe = vxy > 1e-9
        # downstream azimuth: e_r(psi_d) parallel to the in-plane air velocity
        cd = np.where(safe, -v0[:, 0] / np.where(safe, vxy, 1.0), 1.0)
        sd = np.where(safe, v0[:, 1] / np.where(safe, vxy, 1.0), 0.0)
        n = ctx.n
        # initial guess: hover momentum theory with the affine thrust
        bt, j00 = base[:, 0], jac[:, 0, 0]
        lam0 = np.sign(bt) * (j00 + np.sqrt(j00 * j00 + 8.0 * np.abs(bt))) / 4.0
        e_a = np.stack([np.zeros(n), cd, sd], -1)  # picks m_A / lambda_A
        e_b = np.stack([np.zeros(n), -sd, cd], -1)
        ja = np.einsum("ni,nij->nj", e_a, jac)
        jb = np.einsum("ni,nij->nj", e_b, jac)
        ba = np.einsum("ni,ni->n", e_a, base)
        bb = np.einsum("ni,ni->n", e_b, base)
        jt = jac[:, 0, :]
        m = np.empty((n, 3, 3))
        rhs = np.empty((n, 3))
        sol = np.stack([lam0, np.zeros(n), np.zeros(n)], -1)
        for _ in range(self.ITERATIONS):
            lt = lam0 + muz
            # V_T floored at half the hover inflow of the current thrust: keeps the
            # iteration defined in the vortex-ring state (lambda_t ~ 0), where momentum
            # theory has no solution; inactive in hover, climb and forward flight.
            ct = bt + np.einsum("ni,ni->n", jt, sol)
            v_free = np.sqrt(mu * mu + lt * lt + self.EPS**2)
            vmin = 0.5 * np.sqrt(0.5 * np.abs(ct))
            free = v_free >= vmin
            vt = np.where(free, v_free, vmin)
            vmf = np.maximum((mu * mu + lt * (lt + lam0)) / vt, self.EPS)
            x = np.clip(mu / np.maximum(vt + lt, 1e-9), 0.0, 1.0)
            cchi = np.clip(lt / vt, 0.0, 1.0)
            g1 = 4.0 * cchi / (1.0 + cchi)
            g2 = 4.0 / (1.0 + cchi)
            kx = _K15 * x
            # lambda_0 V_T(lambda_0) linearised about the current lambda_0
            dvt = np.where(free, lt / vt, 0.0)
            a0 = np.maximum(vt + lam0 * dvt, 0.5 * vt)
            b0 = lam0 * lam0 * dvt
            m[:, 0, :] = -0.5 * jt + kx[:, None] * ja
            m[:, 0, 0] += a0
            rhs[:, 0] = b0 + 0.5 * bt - kx * ba
            m[:, 1, :] = vmf[:, None] * e_a - (kx[:, None] * jt + g1[:, None] * ja)
            rhs[:, 1] = kx * bt + g1 * ba
            m[:, 2, :] = vmf[:, None] * e_b - g2[:, None] * jb
            rhs[:, 2] = g2 * bb
            sol = solve3(m, rhs)
            lam0 = sol[:, 0]
        ctx.inflow_0 = sol[:, 0]
        ctx.inflow_c = sol[:, 1]
        ctx.inflow_s = sol[:, 2]
