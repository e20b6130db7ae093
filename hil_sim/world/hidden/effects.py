"""The model-side hidden effects (truth only; see the package docstring).

Each is an `airwake.heli.Effect` written as compiled kernel stages (`airwake.heli.kernel`:
one row, numba), so the truth model stays one fused compiled function, but is not
registered in the host's effect registry. Their formulas are written here from the
literature, not taken from any host effect. Context quantities read (`airwake.heli.layout`):
height_agl_m, hub_air_velocity_rotor_m_s, advance_ratio, inflow_0/c/s, rotor_torque_nm,
delta_*_rad; written: inflow_0/c/s, delta_*_rad, rotor_speed_rad_s.
"""

from __future__ import annotations

import math

from airwake.heli.effects.base import Effect, Parameter, State
from airwake.heli.kernel import Q, kernel, kernel_function

from hil_sim.world.hidden.config import HiddenConfig

_INFLOW_FLOOR = 1e-3  # |lambda_0| floor in mu/lambda_0 (no division by zero at zero thrust)


@kernel_function
def smoothstep_down(x, x0, x1):
    """1 for x <= x0, 0 for x >= x1, C1-smooth cubic in between (x may be +inf)."""
    s = min(max((x - x0) / (x1 - x0), 0.0), 1.0)
    return 1.0 - s * s * (3.0 - 2.0 * s)


class GroundEffect(Effect):
    """Cheeseman-Bennett ground/deck effect on the mean induced inflow (inflow stage).

    The rotor's image in the ground reduces the induced velocity at the disk
    (Cheeseman & Bennett 1955, source model of the wake):
        v_IGE / v_OGE = 1 - (R / 4z)^2       (i.e. T_IGE/T_OGE = 1/(1 - (R/4z)^2) at equal power)
    with their forward-flight correction: the wake is swept back, the factor shrinks as
        (R/4z)^2 / (1 + (mu / lambda_0)^2).
    Applied as lambda_0 <- lambda_0 (1 - k), k = strength (R/4z_e)^2 / (1 + (mu/lambda_0)^2)
    * taper(z/R), z = hub height above ground/deck (height_agl_m), z_e = max(z,
    min_height_ratio R) (the formula diverges at z = R/4 and is not meant below ~R/2);
    the taper (1 below fade_start_ratio R, 0 above fade_end_ratio R, cubic between) makes
    the effect exactly zero high up, where C-B's 1-2 % tail is below its own accuracy.
    """

    name = "hil_ground_effect"
    PARAMETERS = (
        Parameter("strength", 1.0, "-", (0.0, 3.0), "Cheeseman-Bennett (1 = the formula)"),
        Parameter("rotor_radius_m", 0.6645, "m", (0.2, 1.5), "truth main rotor R", fixed=True),
        Parameter("min_height_ratio", 0.5, "-", (0.3, 2.0), "floor of z/R", fixed=True),
        Parameter("fade_start_ratio", 2.0, "-", (0.5, 10.0), "taper start z/R", fixed=True),
        Parameter("fade_end_ratio", 3.0, "-", (0.6, 20.0), "taper end z/R", fixed=True),
    )

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        radius = p.rotor_radius_m
        z = q[Q.height_agl_m]
        z_eff = max(z, p.min_height_ratio * radius)
        image = (radius / (4.0 * z_eff)) ** 2
        lam0 = abs(q[Q.inflow_0]) + _INFLOW_FLOOR
        forward = 1.0 / (1.0 + (q[Q.advance_ratio] / lam0) ** 2)
        taper = smoothstep_down(z / radius, p.fade_start_ratio, p.fade_end_ratio)
        q[Q.inflow_0] = q[Q.inflow_0] * (1.0 - p.strength * image * forward * taper)


class WakeRecirculation(Effect):
    """Ground-vortex wake recirculation at low height and low airspeed (inflow stage).

    In ground effect at low forward speed the wake spreading forward along the ground
    rolls up into a ground vortex under the front of the disk and is re-ingested: the
    rotor's mean inflow rises (a thrust loss at fixed pitch, the "power bump" of the
    transition) and more at the upstream edge (a longitudinal inflow gradient, which a
    flapping rotor turns into a disk tilt and a rolling/pitching moment). Model:
        d lambda_0  = A |lambda_0| F(z/R) G(V / V_peak)
        d lambda_up = g d lambda_0      (added at the upstream edge, linear across the disk)
        F = 1 for z/R <= full_height_ratio, 0 for z/R >= zero_height_ratio, cubic between;
        G(x) = x^2 exp(1 - x^2): 0 in hover, 1 at V = V_peak, vanishing at high speed,
    V the in-plane air speed at the hub. Distinct from ground effect by sign (loss, not
    gain), by its airspeed dependence (a peak at V_peak, zero in hover, where ground
    effect is strongest) and by the moment from the gradient.
    """

    name = "hil_wake_recirculation"
    PARAMETERS = (
        Parameter("inflow_increase", 0.25, "-", (0.0, 2.0), "A: peak relative inflow rise"),
        Parameter("peak_airspeed_m_s", 3.0, "m/s", (0.1, 20.0), "V_peak ~ hover induced velocity"),
        Parameter("full_height_ratio", 1.0, "-", (0.1, 10.0), "z/R with full effect", fixed=True),
        Parameter("zero_height_ratio", 2.5, "-", (0.2, 20.0), "z/R with none", fixed=True),
        Parameter("gradient_fraction", 0.5, "-", (0.0, 3.0), "g: upstream-edge share"),
        Parameter("rotor_radius_m", 0.6645, "m", (0.2, 1.5), "truth main rotor R", fixed=True),
    )

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        height = smoothstep_down(q[Q.height_agl_m] / p.rotor_radius_m, p.full_height_ratio,
                                 p.zero_height_ratio)
        # hub air velocity in the rotor frame; e_r(psi_d) = (-cos psi_d, sin psi_d) points
        # downstream, as in the Pitt-Peters solve
        vx = q[Q.hub_air_velocity_rotor_m_s]
        vy = q[Q.hub_air_velocity_rotor_m_s + 1]
        speed = math.sqrt(vx * vx + vy * vy)
        x2 = (speed / p.peak_airspeed_m_s) ** 2
        d0 = p.inflow_increase * abs(q[Q.inflow_0]) * height * x2 * math.exp(1.0 - x2)
        if speed > 1e-9 and d0 != 0.0:
            d_up = p.gradient_fraction * d0
            q[Q.inflow_c] = q[Q.inflow_c] + d_up * vx / speed  # -d_up * cos(psi_d)
            q[Q.inflow_s] = q[Q.inflow_s] - d_up * vy / speed  # -d_up * sin(psi_d)
        q[Q.inflow_0] = q[Q.inflow_0] + d0


class DynamicInflow(Effect):
    """First-order dynamics of the mean inflow (inflow stage, own state).

    The air mass through the disk cannot change its momentum instantly (Pitt-Peters'
    apparent mass): tau d lambda_0/dt = lambda_0,qs - lambda_0, with lambda_0,qs the
    quasi-static inflow the earlier inflow-stage effects produced. A collective step
    first meets the old, lower inflow: thrust overshoots, then settles (and lags on the
    way down). The cyclic harmonics stay quasi-static.
    """

    name = "hil_dynamic_inflow"
    PARAMETERS = (Parameter("tau_s", 0.08, "s", (0.005, 1.0), "inflow time constant"),)
    STATES = (State("lambda_0", "-", "lagged mean inflow (normalised by Omega R)"),)
    SCRATCH = 1  # the quasi-static inflow, from the inflow stage to state_rates

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        scratch[0] = q[Q.inflow_0]
        q[Q.inflow_0] = s[0]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        ds[0] = (scratch[0] - s[0]) / p.tau_s


class ServoLag(Effect):
    """First-order servo lag between the commanded and the actual blade pitch (inputs stage).

    d theta_j/dt = (delta_j - theta_j) / tau_j for j = col, lat, lon (swashplate servos,
    tau_swash) and ped (tail servo, tau_tail); the rest of the model sees theta. The
    recorded pilot inputs (RC PWM) are the commands delta, before the lag. A pure delay
    in front of the lag is applied by the simulation loop to the command itself.
    """

    name = "hil_servo_lag"
    PARAMETERS = (
        Parameter("tau_swash_s", 0.06, "s", (0.002, 0.5), "swashplate servo time constant"),
        Parameter("tau_tail_s", 0.04, "s", (0.002, 0.5), "tail servo time constant"),
    )
    STATES = (
        State("col_rad", "rad", "actual collective pitch"),
        State("lat_rad", "rad", "actual lateral cyclic"),
        State("lon_rad", "rad", "actual longitudinal cyclic"),
        State("ped_rad", "rad", "actual tail pitch"),
    )
    SCRATCH = 4  # the commands, from the inputs stage to state_rates

    @kernel
    def inputs(q, p, s, ds, load, scratch):
        scratch[0] = q[Q.delta_col_rad]
        scratch[1] = q[Q.delta_lat_rad]
        scratch[2] = q[Q.delta_lon_rad]
        scratch[3] = q[Q.delta_ped_rad]
        q[Q.delta_col_rad] = s[0]
        q[Q.delta_lat_rad] = s[1]
        q[Q.delta_lon_rad] = s[2]
        q[Q.delta_ped_rad] = s[3]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        for j in range(3):
            ds[j] = (scratch[j] - s[j]) / p.tau_swash_s
        ds[3] = (scratch[3] - s[3]) / p.tau_tail_s


class RotorGovernor(Effect):
    """Rotor speed from a finite-gain governor and the drivetrain inertia (rotor_speed stage).

        I_R dOmega/dt = Q_engine - Q_rotor,   Q_engine = max(0, Q_ff + K (Omega_set - Omega))
    Q_rotor = rotor_torque_nm (the rotor's aerodynamic torque). A proportional governor
    leaves a steady droop (Q_rotor - Q_ff)/K: more collective, more torque, lower speed,
    with the time constant I_R / K. Overrides whatever rotor speed the main rotor chose
    (measured or nominal). The body's yaw reaction stays the main rotor's hub torque.
    """

    name = "hil_rotor_governor"
    PARAMETERS = (
        Parameter("rotor_inertia_kg_m2", 0.06, "kg m^2", (0.005, 1.0), "rotor + drivetrain"),
        Parameter("governor_gain_nm_s", 0.05, "N m s/rad", (0.005, 10.0), "K"),
        Parameter("speed_setpoint_rad_s", 163.3, "rad/s", (50.0, 400.0), "Omega_set"),
        Parameter("feedforward_torque_nm", 2.25, "N m", (0.0, 50.0), "Q_ff (trimmed)"),
    )
    STATES = (State("omega_rad_s", "rad/s", "main-rotor speed"),)

    @kernel
    def rotor_speed(q, p, s, ds, load, scratch):
        q[Q.rotor_speed_rad_s] = s[0]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        engine = max(p.feedforward_torque_nm
                     + p.governor_gain_nm_s * (p.speed_setpoint_rad_s - s[0]), 0.0)
        ds[0] = (engine - q[Q.rotor_torque_nm]) / p.rotor_inertia_kg_m2


def build_hidden_effects(hidden: HiddenConfig, *, rotor_radius_m: float,
                         nominal_speed_rad_s: float, hover_torque_nm: float | None = None
                         ) -> list[Effect]:
    """Effect instances for the model-side hidden effects that are on, in pipeline order
    (appended after the host effects: inflow modifiers after Pitt-Peters, the inflow lag
    last so it lags the total quasi-static inflow). `hover_torque_nm` trims the governor's
    feed-forward when the scenario does not set it."""
    out: list[Effect] = []
    on = hidden.enabled()
    if "servo_lag" in on:
        c = on["servo_lag"]
        out.append(ServoLag(tau_swash_s=c.tau_swash_s, tau_tail_s=c.tau_tail_s))
    if "rotor_droop" in on:
        c = on["rotor_droop"]
        q_ff = c.feedforward_torque_nm
        if q_ff is None:
            q_ff = 2.25 if hover_torque_nm is None else hover_torque_nm
        out.append(RotorGovernor(
            rotor_inertia_kg_m2=c.rotor_inertia_kg_m2, governor_gain_nm_s=c.governor_gain_nm_s,
            speed_setpoint_rad_s=(nominal_speed_rad_s if c.speed_setpoint_rad_s is None
                                  else c.speed_setpoint_rad_s),
            feedforward_torque_nm=q_ff))
    if "ground_effect" in on:
        c = on["ground_effect"]
        out.append(GroundEffect(strength=c.strength, rotor_radius_m=rotor_radius_m,
                                min_height_ratio=c.min_height_ratio,
                                fade_start_ratio=c.fade_start_ratio,
                                fade_end_ratio=c.fade_end_ratio))
    if "wake_recirculation" in on:
        c = on["wake_recirculation"]
        out.append(WakeRecirculation(
            inflow_increase=c.inflow_increase, peak_airspeed_m_s=c.peak_airspeed_m_s,
            full_height_ratio=c.full_height_ratio, zero_height_ratio=c.zero_height_ratio,
            gradient_fraction=c.gradient_fraction, rotor_radius_m=rotor_radius_m))
    if "dynamic_inflow" in on:
        out.append(DynamicInflow(tau_s=on["dynamic_inflow"].tau_s))
    return out
