"""Cyclic trim that changes with the airspeed across the disc (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, kernel


@register_effect("advance_cyclic")
class AdvanceCyclic(Effect):
    """How much cyclic a rotor needs per unit of in-plane airspeed is set, in the model, by
    its quasi-steady equations: blow-back (flapping ~ 2 mu theta), the lateral flapping of
    the longitudinal inflow gradient (Pitt-Peters' wake skew), the flybar paddles' own
    blow-back (eta_2). A real head differs — a teetering hinge with delta-3 and elastomer
    dampers, paddles of another geometry, root cut-out and tip loss (Johnson, Helicopter
    Theory, §5.3-5.5; Padfield, Helicopter Flight Dynamics, §3.2.1) — and the difference
    shows as a cyclic trim error that grows linearly with the airspeed across the disc:
    the wind estimate then reads it as a steady wind and wind rotation.

    A blade cyclic-pitch increment linear in the in-plane advance ratio, in the main
    rotor's rotor frame (body y mirrored for a clockwise rotor, main_rotor's docstring):
        theta_c += k_cx mu_x + k_cy mu_y,   theta_s += k_sx mu_x + k_sy mu_y,
        mu = hub air velocity (eq 5.3 wind minus hub motion) / (Omega R).
    It acts on the blades after the flybar's mixer (it must follow `flybar` in the model),
    so the flapping, the hub moment and the thrust tilt all follow. Signature: roll and
    pitch residuals proportional to u and v, in steady legs as in manoeuvres. k = 0
    switches it off. Fitted on a still-air flight with forward, backward and sideward legs.
    """

    PARAMETERS = (
        Parameter("k_cx", 0.0, "rad", (-3.0, 3.0), "fitted",
                  doc="theta_c (rotor-frame cos psi) per unit mu_x (air from the nose: mu_x < 0)"),
        Parameter("k_cy", 0.0, "rad", (-3.0, 3.0), "fitted",
                  doc="theta_c per unit rotor-frame mu_y"),
        Parameter("k_sx", 0.0, "rad", (-3.0, 3.0), "fitted",
                  doc="theta_s (rotor-frame sin psi) per unit mu_x"),
        Parameter("k_sy", 0.0, "rad", (-3.0, 3.0), "fitted",
                  doc="theta_s per unit rotor-frame mu_y"),
    )
    REQUIRES = ("main_rotor",)
    AFTER = ("flybar",)

    @kernel
    def blade_pitch(q, p, s, ds, load, scratch):
        vt = q[Q.tip_speed_m_s]
        mx = q[Q.hub_air_velocity_rotor_m_s] / vt
        my = q[Q.hub_air_velocity_rotor_m_s + 1] / vt
        q[Q.theta_c] += p.k_cx * mx + p.k_cy * my
        q[Q.theta_s] += p.k_sx * mx + p.k_sy * my
