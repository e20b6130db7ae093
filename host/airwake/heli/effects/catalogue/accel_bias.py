"""Accelerometer bias (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, kernel


@register_effect("accel_bias")
class AccelBias(Effect):
    """Constant accelerometer offsets b (body axes): a_meas = a + b (temperature drift
    and turn-on bias of a MEMS IMU, ~0.05-0.3 m/s^2). Signature: a constant residual in
    ax, ay, az that no flight regime explains. b = 0 switches it off."""

    PARAMETERS = (
        Parameter("bx_m_s2", 0.0, "m/s^2", (-3.0, 3.0), "fitted"),
        Parameter("by_m_s2", 0.0, "m/s^2", (-3.0, 3.0), "fitted"),
        Parameter("bz_m_s2", 0.0, "m/s^2", (-3.0, 3.0), "fitted"),
    )

    @kernel
    def measurement(q, p, s, ds, load, scratch):
        q[Q.meas] += p.bx_m_s2
        q[Q.meas + 1] += p.by_m_s2
        q[Q.meas + 2] += p.bz_m_s2
