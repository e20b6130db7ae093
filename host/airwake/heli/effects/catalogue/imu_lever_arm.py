"""IMU lever arm: the inertial sensor is not at the centre of gravity (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, cross, kernel


@register_effect("imu_lever_arm")
class ImuLeverArm(Effect):
    """The IMU sits at r = (x, y, z) from the CG (body axes). A rigid body's point r feels

        a_IMU = a_CG + omega_dot x r + omega x (omega x r)

    (Euler and centripetal terms); gyros are unaffected. An INS also reports the IMU
    point's velocity v_IMU = v_CG + omega x r, so the aerodynamic effects get
    v_CG = v_meas - omega x r (environment stage). Signature: ax, ay, az residuals
    proportional to the angular accelerations (and rates squared) with the lever
    r as the coefficients, none in the angular channels. r = 0 switches it off.
    """

    PARAMETERS = (
        Parameter("x_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="IMU ahead of the CG"),
        Parameter("y_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="IMU right of the CG"),
        Parameter("z_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="IMU below the CG"),
    )
    REQUIRES = ("rigid_body",)

    @kernel
    def environment(q, p, s, ds, load, scratch):
        wx, wy, wz = q[Q.omega_b_rad_s], q[Q.omega_b_rad_s + 1], q[Q.omega_b_rad_s + 2]
        cx, cy, cz = cross(wx, wy, wz, p.x_m, p.y_m, p.z_m)
        q[Q.vel_b_m_s] -= cx
        q[Q.vel_b_m_s + 1] -= cy
        q[Q.vel_b_m_s + 2] -= cz

    @kernel
    def measurement(q, p, s, ds, load, scratch):
        wx, wy, wz = q[Q.omega_b_rad_s], q[Q.omega_b_rad_s + 1], q[Q.omega_b_rad_s + 2]
        ex, ey, ez = cross(q[Q.meas + 3], q[Q.meas + 4], q[Q.meas + 5], p.x_m, p.y_m, p.z_m)
        vx, vy, vz = cross(wx, wy, wz, p.x_m, p.y_m, p.z_m)
        cx, cy, cz = cross(wx, wy, wz, vx, vy, vz)
        q[Q.meas] += ex + cx
        q[Q.meas + 1] += ey + cy
        q[Q.meas + 2] += ez + cz
