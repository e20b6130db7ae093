"""Gravity (eq 5.2)."""

from __future__ import annotations

import math

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, kernel


@register_effect("gravity")
class Gravity(Effect):
    """Weight M_H g in body axes (eq 5.2's g terms), a field force the IMU does not sense:
    F = M_H g [-sin theta, cos theta sin phi, cos theta cos phi]."""

    PARAMETERS = (Parameter("g_m_s2", 9.798, "m/s^2", (9.7, 9.9), "Table 5.1 (g)", fixed=True),)
    REQUIRES = ("rigid_body",)
    LOAD_SENSED = False

    @kernel
    def environment(q, p, s, ds, load, scratch):
        q[Q.gravity_m_s2] = p.g_m_s2

    @kernel
    def forces(q, p, s, ds, load, scratch):
        st, ct = math.sin(q[Q.pitch_rad]), math.cos(q[Q.pitch_rad])
        sf, cf = math.sin(q[Q.roll_rad]), math.cos(q[Q.roll_rad])
        mg = q[Q.mass_kg] * p.g_m_s2
        load[0] += -st * mg
        load[1] += ct * sf * mg
        load[2] += ct * cf * mg
