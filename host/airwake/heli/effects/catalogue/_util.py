"""Compiled helpers the catalogue effects' kernels share (one row at a time)."""

from __future__ import annotations

import math

from airwake.heli.kernel import Q, kernel_function

FAR_M = 1e9  # height used where the height above ground is unknown (+inf)


@kernel_function
def smooth_fade(x, x0, x1):
    """1 for x <= x0, 0 for x >= x1, cubic (C1) in between (x1 > x0 + 0.05 enforced)."""
    top = max(x1, x0 + 0.05)
    s = min(max((x - x0) / (top - x0), 0.0), 1.0)
    return 1.0 - s * s * (3.0 - 2.0 * s)


@kernel_function
def rotor_radius(q):
    """Main-rotor radius R of this row: tip speed / rotor speed."""
    om = q[Q.rotor_speed_rad_s]
    return q[Q.tip_speed_m_s] / om if om != 0.0 else 0.0


@kernel_function
def height(q):
    """Hub height above ground; unknown (+inf, NaN) -> FAR_M."""
    z = q[Q.height_agl_m]
    return z if math.isfinite(z) else FAR_M
