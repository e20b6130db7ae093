"""Empennage: horizontal and vertical fins (eq 5.14)."""

from __future__ import annotations

import numpy as np

from airwake.heli.context import cross
from airwake.heli.effects.base import Effect, Parameter, register_effect


def _wake(ctx, name: str):
    return getattr(ctx, name, np.zeros(ctx.n))


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

    def forces(self, ctx, p) -> None:
        rho = ctx.air_density_kg_m3
        lh = np.asarray(p.h_fin_arm_m, dtype=float)
        lv = np.asarray(p.v_fin_arm_m, dtype=float)
        zh = np.zeros_like(lh)
        zv = np.zeros_like(lv)
        r_h = np.stack([-lh, zh, zh], -1)
        r_v = np.stack([-lv, zv, zv], -1)
        vz = ctx.air_velocity_at(r_h)[:, 2] + _wake(ctx, "rotor_wake_m_s")
        vy = ctx.air_velocity_at(r_v)[:, 1] + _wake(ctx, "tail_wash_m_s")
        f_h = np.zeros((ctx.n, 3))
        f_v = np.zeros((ctx.n, 3))
        f_h[:, 2] = 0.5 * rho * p.c_hf_m2 * vz * np.abs(vz)
        f_v[:, 1] = 0.5 * rho * p.c_vf_m2 * vy * np.abs(vy)
        ctx.add_load(self.name, f_h + f_v, cross(r_h, f_h) + cross(r_v, f_v))
