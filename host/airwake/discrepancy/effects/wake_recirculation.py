"""Rotor-wake recirculation near the ground at low airspeed (catalogue effect)."""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.effects._util import finite_height, rotor_radius, smooth_fade
from airwake.heli.effects.base import Effect, Parameter, register_effect


@register_effect("wake_recirculation")
class WakeRecirculation(Effect):
    """Ground-vortex recirculation: close to the ground at low forward speed the wall jet
    of the rotor wake meets the oncoming air, rolls up into a vortex under the leading
    edge of the disk and is re-ingested. The rotor flies in its own downwash: the mean
    inflow rises (thrust loss at fixed pitch) and more at the upstream edge:

        d lambda_0 = A |lambda_0| H(z/R) G(V / V_p)
        d lambda(rbar, psi) = g d lambda_0 rbar (e_r(psi) . u_up)   (upstream-edge gradient)
        H = 1 below full_height_ratio R, 0 above zero_height_ratio R (cubic between)
        G(x) = x^2 exp(1 - x^2): no vortex in hover (the wall jet spreads evenly), a peak
               when the airspeed V equals the wall-jet speed ~ hover induced velocity,
               blown away at higher speed,
    V the in-plane air speed at the hub, u_up the unit in-plane vector toward the oncoming
    air (rotor frame). Distinct from ground effect: a thrust *loss* (az residual > 0),
    zero in hover, peaked in airspeed; the gradient tilts the disk (pitch/roll residuals).
    """

    PARAMETERS = (
        Parameter("inflow_increase", 0.3, "-", (0.0, 3.0), "fitted",
                  doc="A: peak relative rise of the mean inflow (0 = off)"),
        Parameter("peak_airspeed_m_s", 3.0, "m/s", (0.3, 15.0), "fitted",
                  doc="V_p: airspeed of the strongest recirculation"),
        Parameter("full_height_ratio", 1.0, "-", (0.1, 4.0), "fitted",
                  doc="z/R below which the recirculation is fully developed"),
        Parameter("zero_height_ratio", 2.5, "-", (0.2, 8.0), "fitted",
                  doc="z/R above which there is none"),
        Parameter("gradient_fraction", 0.5, "-", (-1.0, 3.0), "fitted",
                  doc="g: upstream-edge share of the inflow rise"),
    )
    REQUIRES = ("main_rotor", "pitt_peters_inflow")

    def inflow(self, ctx, p) -> None:
        radius = rotor_radius(ctx)
        zr = finite_height(ctx) / radius
        top = np.maximum(p.zero_height_ratio, np.asarray(p.full_height_ratio) + 0.05)
        h = smooth_fade(zr, p.full_height_ratio, top)
        v_air = np.asarray(ctx.hub_air_velocity_m_s, float)
        speed = np.hypot(v_air[:, 0], v_air[:, 1])
        x2 = (speed / p.peak_airspeed_m_s) ** 2
        g = x2 * np.exp(1.0 - x2)
        lam0 = np.asarray(ctx.inflow_0, float)
        d0 = p.inflow_increase * np.abs(lam0) * h * g
        # rotor frame (y mirrored for a clockwise rotor): u_up = -v_air_in_plane / |v|
        sense = np.asarray(ctx.rotor_sense, float)
        moving = speed > 1e-9
        safe = np.where(moving, speed, 1.0)
        up_x = np.where(moving, -v_air[:, 0] / safe, 0.0)
        up_y = np.where(moving, -sense * v_air[:, 1] / safe, 0.0)
        # e_r(psi) = (-cos psi, sin psi): e_r . u_up = -up_x cos psi + up_y sin psi
        grad = p.gradient_fraction * d0
        ctx.inflow_0 = lam0 + d0
        ctx.inflow_c = np.asarray(ctx.inflow_c, float) - grad * up_x
        ctx.inflow_s = np.asarray(ctx.inflow_s, float) + grad * up_y
