"""Rotor-speed droop: the rotor does not turn at the constant nominal speed (catalogue)."""

from __future__ import annotations

import math

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, kernel


@register_effect("rotor_droop")
class RotorDroop(Effect):
    """Rotor speed from the tachometer instead of the constant nominal speed Omega*.

    The baseline model (reference Table 5.1) flies at a constant Omega*. A real governor has
    finite gain: more collective, more rotor torque, lower speed (droop), recovering with
    the drivetrain's time constant. Where the flight table has the measured rotor speed,
        Omega = Omega* + gain (Omega_meas - Omega*)
    (gain 1: believe the tachometer; the fit tells how much of the measured variation the
    data support). Everything downstream (blade loads ~ Omega^2, tail rotor at N_T Omega,
    flapping dynamics) sees Omega. Rows without a measurement keep Omega*. Signature: az
    and yaw residuals proportional to (Omega_meas - Omega*), i.e. correlated with the
    collective through the governor.
    """

    PARAMETERS = (
        Parameter("tachometer_gain", 1.0, "-", (0.0, 1.5), "fitted",
                  doc="share of the measured speed deviation used (0 = constant Omega*)"),
    )
    REQUIRES = ("main_rotor",)

    @kernel
    def rotor_speed(q, p, s, ds, load, scratch):
        meas = q[Q.rotor_speed_meas_rad_s]
        if math.isfinite(meas) and meas > 0.0:
            om = q[Q.rotor_speed_rad_s]
            q[Q.rotor_speed_rad_s] = om + p.tachometer_gain * (meas - om)
