"""Bell-Hiller stabiliser bar (flybar), eq 5.15 re-derived."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, State, register_effect
from airwake.heli.kernel import Q, kernel


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

    @kernel
    def blade_pitch(q, p, s, ds, load, scratch):
        q[Q.theta_c] = p.c1 * q[Q.swash_c] + p.c2 * s[1]
        q[Q.theta_s] = p.c1 * q[Q.swash_s] - p.c2 * s[0]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        ac, as_, dac, das = s[0], s[1], s[2], s[3]
        v0x = q[Q.hub_air_velocity_rotor_m_s]
        v0y = q[Q.hub_air_velocity_rotor_m_s + 1]
        v0z = q[Q.hub_air_velocity_rotor_m_s + 2]
        wx, wy = q[Q.rel_rotation_rotor_rad_s], q[Q.rel_rotation_rotor_rad_s + 1]
        bx, by = q[Q.body_rates_rotor_rad_s], q[Q.body_rates_rotor_rad_s + 1]
        om, vtip = q[Q.rotor_speed_rad_s], q[Q.tip_speed_m_s]
        k = p.lock_number / 8.0
        up0 = -v0z / vtip - q[Q.inflow_0]
        rhs_c = 2.0 * bx / om + k * (
            q[Q.swash_c] - wy / om - q[Q.inflow_c] + 2.0 * p.eta2 * up0 * (-v0y / vtip)
        )
        rhs_s = -2.0 * by / om + k * (
            q[Q.swash_s] - wx / om - q[Q.inflow_s] + 2.0 * p.eta2 * up0 * (-v0x / vtip)
        )
        om2 = om * om
        ds[0] = dac
        ds[1] = das
        ds[2] = om2 * (rhs_c - k * (dac / om + as_)) - 2.0 * om * das
        ds[3] = om2 * (rhs_s - k * (das / om - ac)) + 2.0 * om * dac
