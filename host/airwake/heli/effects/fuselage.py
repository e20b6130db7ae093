"""Fuselage drag (eq 5.13)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, air_velocity_at, kernel


@register_effect("fuselage")
class Fuselage(Effect):
    """Fuselage drag of an equivalent tri-axial ellipsoid, eq 5.13, at the CG:
        F_f = rho/6 [C_X V_x|V_x|, C_Y V_y|V_y|, C_Z V_z|V_z|],  no moment,
    V = eq 5.3 wind at the CG minus the body velocity, plus the main-rotor wake
    v_d = lambda_0 Omega R + sqrt(T/(2 rho A_d)) blowing down (+z).
    Deviation: the reference squares (u + v_x) and so loses the drag's sign; here the
    drag acts along the relative air velocity, and v_d is in m/s (lambda_0 scaled by
    Omega R). C_X, C_Y, C_Z are areas (m^2) in this form; the reference's units are garbled.
    """

    PARAMETERS = (
        Parameter("cx_m2", 6.26e-2, "m^2", (0.0, 1.0), "Table 5.1 (C_X)"),
        Parameter("cy_m2", 0.1036, "m^2", (0.0, 1.0), "Table 5.1 (C_Y)"),
        Parameter("cz_m2", 2.43e-2, "m^2", (0.0, 1.0), "Table 5.1 (C_Z)"),
    )
    REQUIRES = ("rigid_body",)

    @kernel
    def forces(q, p, s, ds, load, scratch):
        vx, vy, vz = air_velocity_at(q, 0.0, 0.0, 0.0)
        vz += q[Q.rotor_wake_m_s]  # zero without a main rotor
        k = q[Q.air_density_kg_m3] / 6.0
        load[0] += k * p.cx_m2 * vx * abs(vx)
        load[1] += k * p.cy_m2 * vy * abs(vy)
        load[2] += k * p.cz_m2 * vz * abs(vz)
