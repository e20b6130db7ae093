"""IMU lever arm: the inertial sensor is not at the centre of gravity (catalogue effect)."""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.effects._util import cross, vec3
from airwake.heli.effects.base import Effect, Parameter, register_effect


@register_effect("imu_lever_arm")
class ImuLeverArm(Effect):
    """The IMU sits at r = (x, y, z) from the CG (body axes). A rigid body's point r feels

        a_IMU = a_CG + omega_dot x r + omega x (omega x r)

    (Euler and centripetal terms); gyros are unaffected. An INS also reports the IMU
    point's velocity v_IMU = v_CG + omega x r, so the aerodynamic effects get
    v_CG = v_meas - omega x r (environment stage). Signature: ax, ay, az residuals
    proportional to the angular accelerations (and rates squared) with the lever
    r as the coefficients, none in the angular channels.
    """

    PARAMETERS = (
        Parameter("x_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="IMU ahead of the CG"),
        Parameter("y_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="IMU right of the CG"),
        Parameter("z_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="IMU below the CG"),
    )
    REQUIRES = ("rigid_body",)

    def environment(self, ctx, p) -> None:
        r = vec3(p.x_m, p.y_m, p.z_m)
        omega = np.asarray(ctx.omega_b_rad_s, float)
        ctx.vel_b_m_s = np.asarray(ctx.vel_b_m_s, float) - cross(omega, r)

    def measurement(self, ctx, p) -> None:
        r = vec3(p.x_m, p.y_m, p.z_m)
        omega = np.asarray(ctx.omega_b_rad_s, float)
        meas = np.array(ctx.meas, dtype=float)
        omega_dot = meas[:, 3:6]
        meas[:, 0:3] += cross(omega_dot, r) + cross(omega, cross(omega, r))
        ctx.meas = meas
