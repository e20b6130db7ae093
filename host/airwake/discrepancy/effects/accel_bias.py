"""Accelerometer bias (catalogue effect)."""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.effects._util import vec3
from airwake.heli.effects.base import Effect, Parameter, register_effect


@register_effect("accel_bias")
class AccelBias(Effect):
    """Constant accelerometer offsets b (body axes): a_meas = a + b (temperature drift
    and turn-on bias of a MEMS IMU, ~0.05-0.3 m/s^2). Signature: a constant residual in
    ax, ay, az that no flight regime explains."""

    PARAMETERS = (
        Parameter("bx_m_s2", 0.0, "m/s^2", (-3.0, 3.0), "fitted"),
        Parameter("by_m_s2", 0.0, "m/s^2", (-3.0, 3.0), "fitted"),
        Parameter("bz_m_s2", 0.0, "m/s^2", (-3.0, 3.0), "fitted"),
    )

    def measurement(self, ctx, p) -> None:
        meas = np.array(ctx.meas, dtype=float)
        meas[:, 0:3] += vec3(p.bx_m_s2, p.by_m_s2, p.bz_m_s2)
        ctx.meas = meas
