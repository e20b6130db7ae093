"""Accelerometer misalignment (catalogue effect)."""

from __future__ import annotations

import math

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, cross, kernel


@register_effect("accel_misalignment")
class AccelMisalignment(Effect):
    """The accelerometer triad is rotated by the small angles e = (e_x, e_y, e_z) from the
    body axes (mounting error): a_meas = R(e)^T a, R(e) the rotation by the vector e
    (Rodrigues: R^T a = a cos t - (k x a) sin t + k (k.a)(1 - cos t), t = |e|, k = e/t).
    To first order a_meas = a - e x a: with hover's specific force (0, 0, -g) a pitch
    misalignment e_y puts g e_y into ax and a roll misalignment -g e_x into ay; these move
    with thrust (collective), unlike a bias. e = 0 switches it off."""

    PARAMETERS = (
        Parameter("ex_rad", 0.0, "rad", (-0.3, 0.3), "fitted", doc="about body x"),
        Parameter("ey_rad", 0.0, "rad", (-0.3, 0.3), "fitted", doc="about body y"),
        Parameter("ez_rad", 0.0, "rad", (-0.3, 0.3), "fitted", doc="about body z"),
    )

    @kernel
    def measurement(q, p, s, ds, load, scratch):
        t = math.sqrt(p.ex_rad**2 + p.ey_rad**2 + p.ez_rad**2)
        if t == 0.0:
            return
        kx, ky, kz = p.ex_rad / t, p.ey_rad / t, p.ez_rad / t
        ax, ay, az = q[Q.meas], q[Q.meas + 1], q[Q.meas + 2]
        c, sn = math.cos(t), math.sin(t)
        cx, cy, cz = cross(kx, ky, kz, ax, ay, az)
        dot = (kx * ax + ky * ay + kz * az) * (1.0 - c)
        q[Q.meas] = ax * c - cx * sn + kx * dot
        q[Q.meas + 1] = ay * c - cy * sn + ky * dot
        q[Q.meas + 2] = az * c - cz * sn + kz * dot
