"""Ground / deck effect on the main rotor's induced inflow (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.effects.catalogue._util import height, rotor_radius, smooth_fade
from airwake.heli.kernel import Q, kernel

_LAMBDA_FLOOR = 1e-3  # |lambda_0| floor in the forward-flight correction


@register_effect("ground_effect")
class GroundEffect(Effect):
    """Ground (or deck) effect: the rotor's mirror image below the ground plane induces an
    upwash at the disk that cancels part of the induced inflow (Cheeseman & Bennett 1955,
    a point-source wake and its image):
        lambda_0 <- lambda_0 (1 - k_GE)
        k_GE = strength (R / 4 z_e)^2 / (1 + (mu / lambda_0)^2) F(z/R)
    z_e = max(z, min_height_ratio R) (the image formula diverges at z = R/4 and is not used
    below ~R/2), z the hub height above ground/deck (`height_agl_m`), mu/lambda_0 the
    wake skew (the forward-flight correction: a swept-back wake sees less of its image).
    F fades the image model out between fade_start_ratio R and fade_end_ratio R: measured
    in-ground benefit is negligible above about one rotor diameter (z = 2R), where the
    (R/4z)^2 tail (~1.6 %) is below the formula's own accuracy. Applied after the inflow
    solve, at fixed blade pitch: thrust rises, the az residual is negative and grows as
    (R/4z)^2 near the ground. strength = 0 switches it off.
    """

    PARAMETERS = (
        Parameter("strength", 1.0, "-", (0.0, 4.0), "Cheeseman-Bennett (1 = the formula)",
                  doc="0 switches the effect off"),
        Parameter("min_height_ratio", 0.5, "-", (0.3, 2.0), "floor of z/R (formula limit)",
                  fixed=True),
        Parameter("fade_start_ratio", 2.0, "-", (0.5, 6.0), "one rotor diameter",
                  doc="z/R where the image model starts to fade out"),
        Parameter("fade_end_ratio", 3.0, "-", (0.6, 10.0), "fitted",
                  doc="z/R above which the effect is zero (at least fade start + 0.05)"),
    )
    REQUIRES = ("main_rotor", "pitt_peters_inflow")

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        radius = rotor_radius(q)
        if radius <= 0.0:
            return
        z = height(q)
        z_e = max(z, p.min_height_ratio * radius)
        image = (radius / (4.0 * z_e)) ** 2
        lam0 = abs(q[Q.inflow_0]) + _LAMBDA_FLOOR
        skew = 1.0 / (1.0 + (q[Q.advance_ratio] / lam0) ** 2)
        fade = smooth_fade(z / radius, p.fade_start_ratio, p.fade_end_ratio)
        q[Q.inflow_0] *= 1.0 - p.strength * image * skew * fade
