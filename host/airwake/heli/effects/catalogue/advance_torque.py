"""Main-rotor torque that changes with the airspeed (catalogue effect)."""

from __future__ import annotations

import math

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, kernel

MIN_THRUST_COEFF = 1e-4  # the hover inflow's floor (a rotor at zero thrust has none)


@register_effect("advance_torque")
class AdvanceTorque(Effect):
    """The torque a rotor needs falls as the helicopter gathers airspeed: translational lift
    lowers the induced velocity, v_i / v_h = 1 / sqrt(...) of momentum theory, about 20 %
    at an airspeed equal to the hover induced velocity v_h, in every direction (Johnson,
    Helicopter Theory, §4.1; Padfield, Helicopter Flight Dynamics, §3.2.1). The model's
    rotor and inflow set how fast; a real airframe differs (its blade and root geometry,
    its governor and drive, the tail rotor's drive torque on the same shaft) and the
    difference is a couple about the shaft: a yaw residual that grows with the airspeed
    squared in forward, backward and sideward legs alike, with no side force (the tail
    rotor's thrust or the fin would bring one, and a roll moment with it). The wind
    estimate reads such a couple as a wind rotation about z and, through the tail's side
    force it then asks for, about x and y.

    A yaw couple on the fuselage (body z, about the CG):
        dM_z = -s k_q |Q| (mu_x^2 + mu_y^2) / lambda_h^2,    lambda_h^2 = C_T / 2,
    s the rotor sense (+1 counter-clockwise from above: its torque reaction yaws the nose
    right), Q the model's aerodynamic rotor torque, mu the in-plane advance ratio at the
    hub (eq 5.3 wind minus hub motion, over Omega R), lambda_h the hover inflow of momentum
    theory. k_q > 0: the airframe's torque falls faster with airspeed than the model's, by
    the fraction k_q of the torque at an airspeed of v_h. k_q = 0 switches it off. Fitted
    on a still-air flight with forward, backward and sideward legs.
    Valid at the legs' airspeeds (up to ~1 v_h, 3.5 m/s on a 600-class machine): momentum
    theory's drop of the induced velocity levels off beyond (0.21 of it at v_h, 0.51 at
    2 v_h, 0.67 at 3 v_h) while mu^2 keeps growing; and |Q| holds the profile torque too,
    so at a thrust far below hover (C_T at its floor) the couple is overstated.
    """

    PARAMETERS = (
        Parameter("k_q", 0.0, "-", (-2.0, 2.0), "fitted",
                  doc="torque fraction lost beyond the model's at an airspeed of v_h"),
    )
    REQUIRES = ("main_rotor",)
    AFTER = ("main_rotor",)

    @kernel
    def forces(q, p, s, ds, load, scratch):
        vt = q[Q.tip_speed_m_s]
        mx = q[Q.hub_air_velocity_rotor_m_s] / vt
        my = q[Q.hub_air_velocity_rotor_m_s + 1] / vt
        lam2 = 0.5 * max(q[Q.thrust_coeff], MIN_THRUST_COEFF)
        torque = math.fabs(q[Q.rotor_torque_nm])
        load[5] += -q[Q.rotor_sense] * p.k_q * torque * (mx * mx + my * my) / lam2
