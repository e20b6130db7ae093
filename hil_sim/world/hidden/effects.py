"""The model-side hidden effects (truth only; see the package docstring).

Each is an `airwake.heli.Effect` (same pipeline contract as the host's effects: stage
methods on a batched context, own parameters and states) but is not registered in the
host's effect registry. Their formulas are written here from the literature, not taken
from any host effect. Quantities read from the context (documented in
`airwake.heli.context`): height_agl_m, hub_air_velocity_m_s, rotor_sense,
advance_ratio, inflow_0/c/s, rotor_speed_rad_s, rotor_torque_nm, delta_*_rad.
"""

from __future__ import annotations

import numpy as np
from airwake.heli.effects.base import Effect, Parameter, State

from hil_sim.world.hidden.config import HiddenConfig

_INFLOW_FLOOR = 1e-3  # |lambda_0| floor in mu/lambda_0 (no division by zero at zero thrust)


def smoothstep_down(x, x0, x1):
    """1 for x <= x0, 0 for x >= x1, C1-smooth cubic in between (arrays)."""
    s = np.clip((np.asarray(x, dtype=float) - x0) / (x1 - x0), 0.0, 1.0)
    return 1.0 - s * s * (3.0 - 2.0 * s)


class GroundEffect(Effect):
    """Cheeseman-Bennett ground/deck effect on the mean induced inflow (inflow stage).

    The rotor's image in the ground reduces the induced velocity at the disk
    (Cheeseman & Bennett 1955, source model of the wake):
        v_IGE / v_OGE = 1 - (R / 4z)^2       (i.e. T_IGE/T_OGE = 1/(1 - (R/4z)^2) at equal power)
    with their forward-flight correction: the wake is swept back, the factor shrinks as
        (R/4z)^2 / (1 + (mu / lambda_0)^2).
    Applied as lambda_0 <- lambda_0 (1 - k), k = strength (R/4z_e)^2 / (1 + (mu/lambda_0)^2)
    * taper(z/R), z = hub height above ground/deck (ctx.height_agl_m), z_e = max(z,
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

    def inflow(self, ctx, p) -> None:
        radius = p.rotor_radius_m
        z = np.asarray(ctx.height_agl_m, dtype=float)
        z_eff = np.maximum(np.where(np.isfinite(z), z, 1e9), p.min_height_ratio * radius)
        image = (radius / (4.0 * z_eff)) ** 2
        lam0 = np.abs(ctx.inflow_0) + _INFLOW_FLOOR
        forward = 1.0 / (1.0 + (ctx.advance_ratio / lam0) ** 2)
        taper = smoothstep_down(z / radius, p.fade_start_ratio, p.fade_end_ratio)
        k = p.strength * image * forward * taper
        ctx.inflow_0 = ctx.inflow_0 * (1.0 - k)
        ctx.hil_ground_effect_factor = k


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

    def inflow(self, ctx, p) -> None:
        z = np.asarray(ctx.height_agl_m, dtype=float)
        height = smoothstep_down(np.where(np.isfinite(z), z, 1e9) / p.rotor_radius_m,
                                 p.full_height_ratio, p.zero_height_ratio)
        v_air = np.asarray(ctx.hub_air_velocity_m_s, dtype=float)
        speed = np.hypot(v_air[:, 0], v_air[:, 1])
        x2 = (speed / p.peak_airspeed_m_s) ** 2
        airspeed = x2 * np.exp(1.0 - x2)
        d0 = p.inflow_increase * np.abs(ctx.inflow_0) * height * airspeed
        # Downstream azimuth in the rotor frame (body y mirrored for a clockwise rotor):
        # e_r(psi_d) = (-cos psi_d, sin psi_d) along the in-plane air velocity.
        sense = np.asarray(ctx.rotor_sense, dtype=float)
        safe = np.where(speed > 1e-9, speed, 1.0)
        cos_d = np.where(speed > 1e-9, -v_air[:, 0] / safe, 1.0)
        sin_d = np.where(speed > 1e-9, sense * v_air[:, 1] / safe, 0.0)
        d_up = p.gradient_fraction * d0
        ctx.inflow_0 = ctx.inflow_0 + d0
        ctx.inflow_c = ctx.inflow_c - d_up * cos_d
        ctx.inflow_s = ctx.inflow_s - d_up * sin_d
        ctx.hil_recirculation_inflow = d0


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

    def inflow(self, ctx, p) -> None:
        ctx.hil_inflow_quasi_static = ctx.inflow_0
        ctx.inflow_0 = ctx.state(self.name)[:, 0].copy()

    def state_rates(self, ctx, p) -> None:
        lam = ctx.state(self.name)[:, 0]
        ctx.set_rates(self.name, ((ctx.hil_inflow_quasi_static - lam) / p.tau_s)[:, None])


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

    def inputs(self, ctx, p) -> None:
        ctx.hil_servo_command = np.column_stack(
            [ctx.delta_col_rad, ctx.delta_lat_rad, ctx.delta_lon_rad, ctx.delta_ped_rad])
        st = ctx.state(self.name)
        ctx.delta_col_rad = st[:, 0]
        ctx.delta_lat_rad = st[:, 1]
        ctx.delta_lon_rad = st[:, 2]
        ctx.delta_ped_rad = st[:, 3]

    def state_rates(self, ctx, p) -> None:
        st = ctx.state(self.name)
        swash = np.asarray(p.tau_swash_s, dtype=float)
        tail = np.asarray(p.tau_tail_s, dtype=float)
        tau = np.stack(np.broadcast_arrays(swash, swash, swash, tail), -1)
        ctx.set_rates(self.name, (ctx.hil_servo_command - st) / tau)


class RotorGovernor(Effect):
    """Rotor speed from a finite-gain governor and the drivetrain inertia (rotor_speed stage).

        I_R dOmega/dt = Q_engine - Q_rotor,   Q_engine = max(0, Q_ff + K (Omega_set - Omega))
    Q_rotor = ctx.rotor_torque_nm (the rotor's aerodynamic torque). A proportional governor
    leaves a steady droop (Q_rotor - Q_ff)/K: more collective, more torque, lower speed,
    with the time constant I_R / K. Overrides whatever rotor speed the main rotor chose
    (measured or nominal). The body's yaw reaction stays the main rotor's hub torque.
    """

    name = "hil_rotor_governor"
    PARAMETERS = (
        Parameter("rotor_inertia_kg_m2", 0.05, "kg m^2", (0.005, 1.0), "rotor + drivetrain"),
        Parameter("governor_gain_nm_s", 0.15, "N m s/rad", (0.005, 10.0), "K"),
        Parameter("speed_setpoint_rad_s", 163.3, "rad/s", (50.0, 400.0), "Omega_set"),
        Parameter("feedforward_torque_nm", 2.25, "N m", (0.0, 50.0), "Q_ff (trimmed)"),
    )
    STATES = (State("omega_rad_s", "rad/s", "main-rotor speed"),)

    def rotor_speed(self, ctx, p) -> None:
        ctx.rotor_speed_rad_s = ctx.state(self.name)[:, 0].copy()

    def state_rates(self, ctx, p) -> None:
        omega = ctx.state(self.name)[:, 0]
        engine = np.maximum(
            p.feedforward_torque_nm + p.governor_gain_nm_s * (p.speed_setpoint_rad_s - omega), 0.0)
        ctx.set_rates(self.name,
                      ((engine - ctx.rotor_torque_nm) / p.rotor_inertia_kg_m2)[:, None])


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
