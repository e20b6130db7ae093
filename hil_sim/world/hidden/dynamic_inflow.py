"""Truth inflow dynamics: the three-state Pitt-Peters model.

Sources: Pitt, D. M. & Peters, D. A. (1981), "Theoretical prediction of dynamic-inflow
derivatives", Vertica 5(1): 21-34; Peters, D. A. & HaQuang, N. (1988), "Dynamic inflow
for practical applications", Journal of the American Helicopter Society 33(4): 64-68.
The inflow lambda(rbar, psi) = lambda_0 + rbar (lambda_c cos psi + lambda_s sin psi)
obeys, in the wind frame (0, A along the in-plane flow, B across) and rotor time
psi = Omega t,

    M dlambda/dpsi + V L^-1 lambda = F(lambda),   F = (C_T, m_A, m_B)
    M = diag(8 / (3 pi), 16 / (45 pi), 16 / (45 pi))           (apparent mass)
    L = [[1/2, -15 pi/64 X, 0], [15 pi/64 X, 4 cos chi / (1 + cos chi), 0],
         [0, 0, 4 / (1 + cos chi)]],   X = tan(chi/2)           (wake skew chi)
    V = diag(V_T, V_m, V_m),  V_T = sqrt(mu^2 + lambda_t^2),
        V_m = (mu^2 + lambda_t (lambda_t + lambda_0)) / V_T    (mass-flow parameters)

with lambda_t = lambda_0 + mu_z and tan chi = mu / lambda_t. The rotor's loads are
affine in the inflow, F(lambda) = F(lambda_qs) + J (lambda - lambda_qs) (J the load
Jacobian d(C_T, m_c, m_s)/d(lambda_0, lambda_c, lambda_s) the main rotor provides,
rotated to the wind frame), and the quasi-static inflow lambda_qs the model's inflow
stage produced (the host's static solve plus the hidden ground effects) satisfies
F(lambda_qs) = V L^-1 lambda_qs. Hence, linearised about lambda_qs,

    M dlambda/dpsi = (V L^-1 - J) (lambda_qs - lambda)

so the steady state is exactly lambda_qs, and the time constants include the loads'
inflow feedback (hover mean inflow: tau_0 = (8 / 3 pi) / (Omega (2 lambda_0 - J_00)),
38 ms for this rotor; 13 ms for the harmonics). `apparent_mass_scale` multiplies M.
States: lambda_0, lambda_c, lambda_s (rotor frame, as the main rotor's inflow
quantities).
"""

from __future__ import annotations

import math

import numpy as np
from airwake.heli.effects.base import Effect, Parameter, State
from airwake.heli.kernel import Q, kernel

M_MEAN = 8.0 / (3.0 * math.pi)
M_HARMONIC = 16.0 / (45.0 * math.pi)
SKEW_COUPLING = 15.0 * math.pi / 64.0
_FLOOR = 1e-4  # floor of V_T and V_m (zero thrust, vortex ring)


class PittPetersDynamicInflow(Effect):
    """Three-state Pitt-Peters inflow dynamics about the quasi-static inflow (inflow stage,
    last; module docstring)."""

    name = "hil_pitt_peters_inflow"
    PARAMETERS = (
        Parameter("apparent_mass_scale", 1.0, "-", (0.1, 10.0), "1 = Pitt & Peters' M"),
    )
    STATES = (
        State("lambda_0", "-", "mean inflow / (Omega R)"),
        State("lambda_c", "-", "inflow cos psi harmonic"),
        State("lambda_s", "-", "inflow sin psi harmonic"),
    )
    SCRATCH = 3  # the quasi-static inflow, from the inflow stage to state_rates

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        scratch[0] = q[Q.inflow_0]
        scratch[1] = q[Q.inflow_c]
        scratch[2] = q[Q.inflow_s]
        q[Q.inflow_0] = s[0]
        q[Q.inflow_c] = s[1]
        q[Q.inflow_s] = s[2]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        mu = q[Q.advance_ratio]
        lam_t = s[0] + q[Q.axial_flow_ratio]
        v_t = max(math.sqrt(mu * mu + lam_t * lam_t), _FLOOR)
        v_m = max((mu * mu + lam_t * (lam_t + s[0])) / v_t, _FLOOR)
        cos_chi = min(max(lam_t / v_t, 0.0), 1.0)
        x = min(max(mu / max(v_t + lam_t, 1e-9), 0.0), 1.0)  # tan(chi/2)
        # downstream azimuth: e_r(psi_d) along the in-plane air velocity (rotor frame)
        vx = q[Q.hub_air_velocity_rotor_m_s]
        vy = q[Q.hub_air_velocity_rotor_m_s + 1]
        vxy = math.hypot(vx, vy)
        cd, sd = (-vx / vxy, vy / vxy) if vxy > 1e-9 else (1.0, 0.0)
        # L^-1 of the wind-frame L: a 2x2 block (0, A) and the B diagonal
        a = 0.5
        b = SKEW_COUPLING * x
        c = 4.0 * cos_chi / (1.0 + cos_chi)
        det = a * c + b * b
        i00, i0a, ia0, iaa = c / det, b / det, -b / det, a / det
        ibb = (1.0 + cos_chi) / 4.0
        # J rotated to the wind frame: J_w = R J R^T, R = [[1,0,0],[0,cd,sd],[0,-sd,cd]]
        j = q[Q.rotor_load_jac:Q.rotor_load_jac + 9]
        r0a = j[1] * cd + j[2] * sd
        r0b = -j[1] * sd + j[2] * cd
        r1a = j[4] * cd + j[5] * sd
        r1b = -j[4] * sd + j[5] * cd
        r2a = j[7] * cd + j[8] * sd
        r2b = -j[7] * sd + j[8] * cd
        w00, w0a, w0b = j[0], r0a, r0b
        wa0 = cd * j[3] + sd * j[6]
        waa = cd * r1a + sd * r2a
        wab = cd * r1b + sd * r2b
        wb0 = -sd * j[3] + cd * j[6]
        wba = -sd * r1a + cd * r2a
        wbb = -sd * r1b + cd * r2b
        # the gap to the quasi-static inflow, wind frame
        e0 = scratch[0] - s[0]
        ec = scratch[1] - s[1]
        es = scratch[2] - s[2]
        ea = cd * ec + sd * es
        eb = -sd * ec + cd * es
        # (V L^-1 - J_w) e
        f0 = v_t * (i00 * e0 + i0a * ea) - (w00 * e0 + w0a * ea + w0b * eb)
        fa = v_m * (ia0 * e0 + iaa * ea) - (wa0 * e0 + waa * ea + wab * eb)
        fb = v_m * ibb * eb - (wb0 * e0 + wba * ea + wbb * eb)
        om = q[Q.rotor_speed_rad_s] / p.apparent_mass_scale
        d0 = om * f0 / M_MEAN
        da = om * fa / M_HARMONIC
        db = om * fb / M_HARMONIC
        ds[0] = d0
        ds[1] = cd * da - sd * db
        ds[2] = sd * da + cd * db

    def rest_state(self, u: np.ndarray, ctx) -> np.ndarray:
        """At the quasi-static inflow."""
        return np.array([float(ctx.inflow_0[0]), float(ctx.inflow_c[0]),
                         float(ctx.inflow_s[0])])

    def linear_values(self) -> dict:
        return {}
