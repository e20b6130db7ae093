"""Empennage: horizontal and vertical fins (eq 5.14)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, add_load, air_velocity_at, cross, kernel


@register_effect("empennage")
class Empennage(Effect):
    """Horizontal and vertical fins, eq 5.14:
        horizontal fin at (-l_H, 0, 0): F_z = rho/2 C_HF V_z|V_z|, V_z = air z-velocity there
            (eq 5.3 wind minus w + q l_H) + main-rotor wake v_d (downwash);
        vertical fin at (-l_V, 0, 0):   F_y = rho/2 C_VF V_y|V_y|, V_y = air y-velocity there
            (wind minus v - r l_V) + tail-rotor wash;
        M_e = sum r x F  (= [0, F_z l_H, -F_y l_V] as in eq 5.14).
    Deviation: signed drag along the relative flow (the reference squares a sum whose signs
    are inconsistent with eq 5.12); the vertical-fin arm l_V defaults to the tail arm l_T.
    """

    PARAMETERS = (
        Parameter("c_hf_m2", 7.598e-4, "m^2", (0.0, 0.1), "Table 5.1 (C_HF)"),
        Parameter("c_vf_m2", 2.2e-3, "m^2", (0.0, 0.1), "Table 5.1 (C_VF)"),
        Parameter("h_fin_arm_m", 0.57, "m", (0.0, 3.0), "Table 5.1 (l_H)"),
        Parameter("v_fin_arm_m", 0.79, "m", (0.0, 3.0), "Table 5.1 (l_T)"),
    )
    REQUIRES = ("rigid_body",)

    @kernel
    def forces(q, p, s, ds, load, scratch):
        rho = q[Q.air_density_kg_m3]
        lh, lv = p.h_fin_arm_m, p.v_fin_arm_m
        vz = air_velocity_at(q, -lh, 0.0, 0.0)[2] + q[Q.rotor_wake_m_s]
        vy = air_velocity_at(q, -lv, 0.0, 0.0)[1] + q[Q.tail_wash_m_s]
        fz = 0.5 * rho * p.c_hf_m2 * vz * abs(vz)  # horizontal fin
        fy = 0.5 * rho * p.c_vf_m2 * vy * abs(vy)  # vertical fin
        mhx, mhy, mhz = cross(-lh, 0.0, 0.0, 0.0, 0.0, fz)
        mvx, mvy, mvz = cross(-lv, 0.0, 0.0, 0.0, fy, 0.0)
        add_load(load, 0.0, fy, fz, mhx + mvx, mhy + mvy, mhz + mvz)
