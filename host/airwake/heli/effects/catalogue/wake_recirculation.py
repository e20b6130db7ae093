"""Rotor-wake recirculation near the ground at low airspeed (catalogue effect)."""

from __future__ import annotations

import math

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.effects.catalogue._util import height, rotor_radius, smooth_fade
from airwake.heli.kernel import Q, kernel


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
    air, e_r(psi) = (-cos psi, sin psi) the blade's radial direction (rotor frame). Distinct
    from ground effect: a thrust *loss* (az residual > 0), zero in hover, peaked in
    airspeed; the gradient tilts the disk (pitch/roll residuals). A = 0 switches it off.
    """

    PARAMETERS = (
        Parameter("inflow_increase", 0.3, "-", (0.0, 3.0), "fitted",
                  doc="A: peak relative rise of the mean inflow (0 = off)"),
        Parameter("peak_airspeed_m_s", 3.0, "m/s", (0.3, 15.0), "fitted",
                  doc="V_p: airspeed of the strongest recirculation"),
        Parameter("full_height_ratio", 1.0, "-", (0.1, 4.0), "fitted",
                  doc="z/R below which the recirculation is fully developed"),
        Parameter("zero_height_ratio", 2.5, "-", (0.2, 8.0), "fitted",
                  doc="z/R above which there is none (at least full + 0.05)"),
        Parameter("gradient_fraction", 0.5, "-", (-1.0, 3.0), "fitted",
                  doc="g: upstream-edge share of the inflow rise"),
    )
    REQUIRES = ("main_rotor", "pitt_peters_inflow")

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        radius = rotor_radius(q)
        if radius <= 0.0:
            return
        h = smooth_fade(height(q) / radius, p.full_height_ratio, p.zero_height_ratio)
        vx, vy = q[Q.hub_air_velocity_m_s], q[Q.hub_air_velocity_m_s + 1]
        speed = math.hypot(vx, vy)
        x2 = (speed / p.peak_airspeed_m_s) ** 2
        d0 = p.inflow_increase * abs(q[Q.inflow_0]) * h * x2 * math.exp(1.0 - x2)
        q[Q.inflow_0] += d0
        if speed > 1e-9:
            # rotor frame (y mirrored for a clockwise rotor): u_up = -v_in-plane / |v|;
            # e_r . u_up = -up_x cos psi + up_y sin psi
            up_x = -vx / speed
            up_y = -q[Q.rotor_sense] * vy / speed
            grad = p.gradient_fraction * d0
            q[Q.inflow_c] -= grad * up_x
            q[Q.inflow_s] += grad * up_y
