"""Bell-Hiller stabiliser bar (flybar), eq 5.15 re-derived."""

from __future__ import annotations

import numpy as np

from airwake.heli.effects.base import Effect, Parameter, State, register_effect


@register_effect("flybar")
class Flybar(Effect):
    """Bell-Hiller flybar: a teetering paddle bar whose cyclic flapping a_c, a_s (rotor frame,
    relative to the shaft) is mixed with the swashplate into the main-blade cyclic pitch.

    Paddle pitch = swashplate cyclic (sw_c, sw_s). Rotating-frame flap equation of the bar
    (no spring, Lock number gamma_f, ' = d/dpsi):
        a'' + a = 2(p cos psi - q sin psi)/Omega
                  + gamma_f/8 [theta_f(psi) + d(psi) - a' + 2 eta_2 U_P0 mu_t(psi)]
    d: rotor-frame body-rate, wind-rotation and inflow harmonics as in main_rotor's U_P,
    U_P0 = -mu_z - lambda_0 the mean normal flow, mu_t(psi) the in-plane advance (the
    reference's B_lambda term; eta_2 scales the paddles' share). In multi-blade coordinates:
        a_c'' = Omega^2 [RHS_c - gamma_f/8 (a_c'/Omega + a_s)] - 2 Omega a_s'
        a_s'' = Omega^2 [RHS_s - gamma_f/8 (a_s'/Omega - a_c)] + 2 Omega a_c'
    Blade cyclic pitch (mixer): theta_c = c1 sw_c + c2 a_s, theta_s = c1 sw_s - c2 a_c.
    Steady state: a_s = sw_c + q/Omega + 16 p/(gamma_f Omega) -> cyclic gain c1 + c2 and a
    rate feedback c2 16/(gamma_f Omega) that damps the body (the bar is a rate gyro); the
    regressive mode decays with gamma_f Omega/16 ~ 8 1/s (slow).
    Deviation: the printed eq 5.15 is dimensionally inconsistent (its B_omega omits the 1/8
    and gives ~1.5 rad of blade pitch per rad/s of roll rate); this is the same structure
    re-derived; O(mu^2) terms are dropped (mu < 0.05 for this vehicle).
    """

    PARAMETERS = (
        Parameter("lock_number", 0.8002, "-", (0.05, 5.0), "Table 5.1 (gamma_f)"),
        Parameter("eta2", 4.3714, "-", (0.0, 20.0), "Table 5.1 (eta_2)", fixed=True),
        Parameter("c1", 0.733, "-", (0.0, 2.0), "Table 5.1 (c_1, swashplate share)", fixed=True),
        Parameter("c2", 0.663, "-", (0.0, 2.0), "Table 5.1 (c_2, flybar share)", fixed=True),
    )
    STATES = (
        State("a_c_rad", "rad", "flybar flapping, rotor frame cos psi"),
        State("a_s_rad", "rad", "flybar flapping, rotor frame sin psi"),
        State("a_c_dot_rad_s", "rad/s", ""),
        State("a_s_dot_rad_s", "rad/s", ""),
    )
    REQUIRES = ("main_rotor",)

    def blade_pitch(self, ctx, p) -> None:
        st = ctx.state(self.name)
        ctx.theta_c = p.c1 * ctx.swash_c + p.c2 * st[:, 1]
        ctx.theta_s = p.c1 * ctx.swash_s - p.c2 * st[:, 0]

    def state_rates(self, ctx, p) -> None:
        st = ctx.state(self.name)
        ac, as_, dac, das = st[:, 0], st[:, 1], st[:, 2], st[:, 3]
        rf = ctx._cache["rotor_frame"]
        v0, w, body, om, vtip = rf["v0"], rf["w"], rf["body"], rf["om"], rf["vtip"]
        k = p.lock_number / 8.0
        up0 = -v0[:, 2] / vtip - ctx.inflow_0
        rhs_c = 2.0 * body[:, 0] / om + k * (
            ctx.swash_c - w[:, 1] / om - ctx.inflow_c + 2.0 * p.eta2 * up0 * (-v0[:, 1] / vtip)
        )
        rhs_s = -2.0 * body[:, 1] / om + k * (
            ctx.swash_s - w[:, 0] / om - ctx.inflow_s + 2.0 * p.eta2 * up0 * (-v0[:, 0] / vtip)
        )
        om2 = om * om
        ddac = om2 * (rhs_c - k * (dac / om + as_)) - 2.0 * om * das
        ddas = om2 * (rhs_s - k * (das / om - ac)) + 2.0 * om * dac
        ctx.set_rates(self.name, np.column_stack([dac, das, ddac, ddas]))
