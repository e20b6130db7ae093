"""Truth rotor speed: an electric drive (battery, ESC, brushless motor, gear) and a PI
governor with a throttle ceiling and anti-windup.

Motor (the brushless DC machine's steady equations, e.g. Hanselman 2006, "Brushless
Permanent Magnet Motor Design", 2nd ed.; SI units, so K_t = K_e = 60 / (2 pi Kv)):

    w_m = N Omega                               (motor speed through the gear ratio N)
    I   = max((V_b d - K_e w_m) / R, 0)         (ESC duty d; no regenerative braking)
    Q_shaft = N K_t I                            (at the rotor shaft, lossless gear)
    I_R dOmega/dt = Q_shaft - Q_rotor            (Q_rotor: the main rotor's aero torque)

R lumps the battery's internal, the ESC's and the winding's resistance, so the battery
sag under load is in the torque-speed line. Governor (PI on the head speed, parallel
form, with back-calculation anti-windup and its tracking time constant T_t: Astrom &
Hagglund 2006, "Advanced PID Control", ISA, on integrator windup):

    e = Omega_set - Omega,  d_raw = K_p e + I_g,  d = clip(d_raw, 0, d_max)
    dI_g/dt = (K_p / T_i) e + (d - d_raw) / T_t

Within the throttle range the integral removes any steady droop; a collective change
droops the rotor while the governor catches up (time scale ~ I_R / (N K_t V_b K_p / R)).
At the ceiling d_max the speed settles on the motor's torque-speed line:

    Omega_sat = (V_b d_max - R Q_rotor / (N K_t)) / (N K_e)

and the back-calculation keeps I_g near d_max, so the governor takes over again without
a wound-up overshoot. Not modelled: gear and ESC losses, the tail rotor's share of the
shaft torque (small in hover), the battery's state-of-charge drift over a flight.
States: Omega (rad/s), I_g (throttle).
"""

from __future__ import annotations

import math

import numpy as np
from airwake.heli.effects.base import Effect, Parameter, State
from airwake.heli.kernel import Q, kernel, kernel_function

RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)


@kernel_function
def back_emf_constant(kv_rpm_per_v):
    """K_e (V s/rad) = K_t (N m/A) of a motor with the speed constant Kv (rpm/V)."""
    return 60.0 / (2.0 * math.pi * kv_rpm_per_v)


class ElectricDriveGovernor(Effect):
    """Rotor speed from the electric drive and its PI governor (rotor_speed stage; module
    docstring). Overrides the rotor speed the main rotor would use."""

    name = "hil_electric_drive"
    PARAMETERS = (
        Parameter("rotor_inertia_kg_m2", 0.055, "kg m^2", (0.005, 1.0), "rotor + drivetrain"),
        Parameter("battery_voltage_v", 22.2, "V", (5.0, 60.0), "6S LiPo"),
        Parameter("motor_kv_rpm_per_v", 1100.0, "rpm/V", (100.0, 5000.0), "motor Kv"),
        Parameter("circuit_resistance_ohm", 0.08, "ohm", (0.005, 1.0), "battery+ESC+winding"),
        Parameter("gear_ratio", 11.0, "-", (1.0, 30.0), "motor / rotor speed"),
        Parameter("governor_kp_per_rad_s", 0.004, "1/(rad/s)", (1e-4, 0.1), "K_p"),
        Parameter("governor_ti_s", 1.0, "s", (0.05, 20.0), "T_i"),
        Parameter("antiwindup_time_s", 0.3, "s", (0.01, 10.0), "T_t (back-calculation)"),
        Parameter("max_throttle", 0.95, "-", (0.3, 1.0), "governor's throttle ceiling"),
        Parameter("speed_setpoint_rad_s", 163.3, "rad/s", (50.0, 400.0), "Omega_set"),
    )
    STATES = (
        State("omega_rad_s", "rad/s", "main-rotor speed"),
        State("throttle_integral", "-", "governor's integral term I_g"),
    )

    @kernel
    def rotor_speed(q, p, s, ds, load, scratch):
        q[Q.rotor_speed_rad_s] = s[0]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        err = p.speed_setpoint_rad_s - s[0]
        raw = p.governor_kp_per_rad_s * err + s[1]
        duty = min(max(raw, 0.0), p.max_throttle)
        k_e = back_emf_constant(p.motor_kv_rpm_per_v)
        current = max((p.battery_voltage_v * duty - k_e * p.gear_ratio * s[0])
                      / p.circuit_resistance_ohm, 0.0)
        shaft = p.gear_ratio * k_e * current
        ds[0] = (shaft - q[Q.rotor_torque_nm]) / p.rotor_inertia_kg_m2
        ds[1] = (p.governor_kp_per_rad_s / p.governor_ti_s * err
                 + (duty - raw) / p.antiwindup_time_s)

    def _motor(self):
        v = self.parameters()
        k_e = 60.0 / (2.0 * math.pi * v["motor_kv_rpm_per_v"])
        return v, k_e

    def throttle_for(self, omega_rad_s: float, rotor_torque_nm: float) -> float:
        """Duty that holds `rotor_torque_nm` at `omega_rad_s` (steady, no saturation)."""
        v, k_e = self._motor()
        current = rotor_torque_nm / (v["gear_ratio"] * k_e)
        return (k_e * v["gear_ratio"] * omega_rad_s
                + v["circuit_resistance_ohm"] * current) / v["battery_voltage_v"]

    def saturated_speed(self, rotor_torque_nm: float) -> float:
        """Omega_sat: steady speed at the throttle ceiling for a rotor torque (module
        docstring; the rotor torque itself depends on the speed: iterate outside)."""
        v, k_e = self._motor()
        n, r = v["gear_ratio"], v["circuit_resistance_ohm"]
        return (v["battery_voltage_v"] * v["max_throttle"] - r * rotor_torque_nm / (n * k_e)
                ) / (n * k_e)

    def rest_state(self, u: np.ndarray, ctx) -> np.ndarray:
        """At the set point with the integral holding the hover throttle."""
        om = self.parameters()["speed_setpoint_rad_s"]
        return np.array([om, self.throttle_for(om, float(ctx.rotor_torque_nm[0]))])

    def linear_values(self) -> dict:
        return {}
