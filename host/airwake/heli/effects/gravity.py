"""Gravity (eq 5.2)."""

from __future__ import annotations

import numpy as np

from airwake.heli.effects.base import Effect, Parameter, register_effect


@register_effect("gravity")
class Gravity(Effect):
    """Weight M_H g in body axes (eq 5.2's g terms), a field force the IMU does not sense:
    F = M_H g [-sin theta, cos theta sin phi, cos theta cos phi]."""

    PARAMETERS = (Parameter("g_m_s2", 9.798, "m/s^2", (9.7, 9.9), "Table 5.1 (g)", fixed=True),)
    REQUIRES = ("rigid_body",)

    def environment(self, ctx, p) -> None:
        ctx.gravity_m_s2 = p.g_m_s2

    def forces(self, ctx, p) -> None:
        st, ct = np.sin(ctx.pitch_rad), np.cos(ctx.pitch_rad)
        sf, cf = np.sin(ctx.roll_rad), np.cos(ctx.roll_rad)
        mg = ctx.mass_kg * p.g_m_s2
        f = np.column_stack([-st, ct * sf, ct * cf]) * np.reshape(mg, (-1, 1))
        ctx.add_load(self.name, f, 0.0, sensed=False)
