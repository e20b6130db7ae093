"""The model-side hidden effects in pipeline order, built from a scenario's settings.

Each is an `airwake.heli.Effect` written as compiled kernel stages (`airwake.heli.kernel`:
one row, numba), so the truth model stays one fused compiled function, but none is
registered in the host's effect registry. Context quantities read (`airwake.heli.layout`):
height_agl_m, advance_ratio, axial_flow_ratio, hub_air_velocity_rotor_m_s,
rotor_load_base/jac, inflow_0/c/s, rotor_torque_nm, rotor_speed_rad_s, delta_*_rad;
written: inflow_0/c/s, delta_*_rad, rotor_speed_rad_s.

Every one also says where it rests (`rest_state(u, ctx)`: its states in steady flight
with inputs u, ctx the host model's evaluation there) and which parameter values make it
smooth for a linear design (`linear_values()`: the servo's deadband off).
"""

from __future__ import annotations

import math

from airwake.heli.effects.base import Effect

from hil_sim.world.hidden.config import HiddenConfig
from hil_sim.world.hidden.dynamic_inflow import PittPetersDynamicInflow
from hil_sim.world.hidden.electric_drive import ElectricDriveGovernor
from hil_sim.world.hidden.ground_effect import GroundEffect
from hil_sim.world.hidden.ground_vortex import GroundVortexRecirculation
from hil_sim.world.hidden.servo import SecondOrderServo

HIDDEN_EFFECT_CLASSES = (SecondOrderServo, ElectricDriveGovernor, GroundEffect,
                         GroundVortexRecirculation, PittPetersDynamicInflow)
HEIGHT_EFFECTS = (GroundEffect.name, GroundVortexRecirculation.name)


def build_hidden_effects(hidden: HiddenConfig, *, rotor_radius_m: float,
                         nominal_speed_rad_s: float) -> list[Effect]:
    """Effect instances for the model-side hidden effects that are on, in pipeline order
    (appended after the host effects: the servos transform the inputs, the drive sets
    the rotor speed, the ground effects modify the host's quasi-static inflow, and the
    Pitt-Peters dynamics come last, so they lag the total quasi-static inflow)."""
    out: list[Effect] = []
    on = hidden.enabled()
    if "servo_lag" in on:
        c = on["servo_lag"]
        two_pi = 2.0 * math.pi
        out.append(SecondOrderServo(
            natural_frequency_rad_s=two_pi * c.natural_frequency_hz,
            damping_ratio=c.damping_ratio, rate_limit_rad_s=c.rate_limit_rad_s,
            tail_natural_frequency_rad_s=two_pi * c.tail_natural_frequency_hz,
            tail_damping_ratio=c.tail_damping_ratio,
            tail_rate_limit_rad_s=c.tail_rate_limit_rad_s, deadband_rad=c.deadband_rad))
    if "rotor_droop" in on:
        c = on["rotor_droop"]
        out.append(ElectricDriveGovernor(
            rotor_inertia_kg_m2=c.rotor_inertia_kg_m2, battery_voltage_v=c.battery_voltage_v,
            motor_kv_rpm_per_v=c.motor_kv_rpm_per_v,
            circuit_resistance_ohm=c.circuit_resistance_ohm, gear_ratio=c.gear_ratio,
            governor_kp_per_rad_s=c.governor_kp_per_rad_s, governor_ti_s=c.governor_ti_s,
            antiwindup_time_s=c.antiwindup_time_s, max_throttle=c.max_throttle,
            speed_setpoint_rad_s=(nominal_speed_rad_s if c.speed_setpoint_rad_s is None
                                  else c.speed_setpoint_rad_s)))
    if "ground_effect" in on:
        c = on["ground_effect"]
        out.append(GroundEffect(power_ratio_intercept=c.power_ratio_intercept,
                                power_ratio_slope=c.power_ratio_slope,
                                min_height_ratio=c.min_height_ratio,
                                rotor_radius_m=rotor_radius_m))
    if "wake_recirculation" in on:
        c = on["wake_recirculation"]
        out.append(GroundVortexRecirculation(
            circulation_ratio=c.circulation_ratio, position_ratio=c.position_ratio,
            sweep_ratio=c.sweep_ratio, core_height_ratio=c.core_height_ratio,
            core_radius_ratio=c.core_radius_ratio, decay_height_ratio=c.decay_height_ratio,
            rotor_radius_m=rotor_radius_m))
    if "dynamic_inflow" in on:
        out.append(PittPetersDynamicInflow(
            apparent_mass_scale=on["dynamic_inflow"].apparent_mass_scale))
    return out
