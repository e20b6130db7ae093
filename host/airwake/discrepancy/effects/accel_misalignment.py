"""Accelerometer misalignment (catalogue effect)."""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.effects._util import cross, vec3
from airwake.heli.effects.base import Effect, Parameter, register_effect


@register_effect("accel_misalignment")
class AccelMisalignment(Effect):
    """The accelerometer triad is rotated by the small angles e = (e_x, e_y, e_z) from the
    body axes (mounting error): a_meas = R(e)^T a, R(e) the rotation by e (Rodrigues).
    To first order a_meas = a - e x a: with hover's large specific force (0, 0, -g) a
    pitch misalignment e_y puts -g e_y into ax and a roll misalignment +g e_x into ay;
    these move with thrust (collective), unlike a bias."""

    PARAMETERS = (
        Parameter("ex_rad", 0.0, "rad", (-0.3, 0.3), "fitted", doc="about body x"),
        Parameter("ey_rad", 0.0, "rad", (-0.3, 0.3), "fitted", doc="about body y"),
        Parameter("ez_rad", 0.0, "rad", (-0.3, 0.3), "fitted", doc="about body z"),
    )

    def measurement(self, ctx, p) -> None:
        e = vec3(p.ex_rad, p.ey_rad, p.ez_rad)
        meas = np.array(ctx.meas, dtype=float)
        a = meas[:, 0:3]
        angle = np.linalg.norm(e, axis=-1, keepdims=True)
        safe = np.where(angle > 0, angle, 1.0)
        k = e / safe  # unit axis (any where angle = 0)
        # R(e)^T a = a cos t - (k x a) sin t + k (k . a)(1 - cos t)
        c, s = np.cos(angle), np.sin(angle)
        meas[:, 0:3] = a * c - cross(k, a) * s + k * np.sum(k * a, -1, keepdims=True) * (1 - c)
        ctx.meas = meas
