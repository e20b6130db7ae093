"""Fuselage drag error (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, add_load, air_velocity_at, cross, kernel


@register_effect("fuselage_drag_error")
class FuselageDragError(Effect):
    """A correction to the eq 5.13 fuselage drag: extra drag areas dC (m^2, either sign)
    acting at a centre of pressure r_cp = (x_cp, 0, z_cp) from the CG (the reference puts
    the drag at the CG, so it has no moment):
        dF = rho/6 [dC_X V_x|V_x|, dC_Y V_y|V_y|, dC_Z V_z|V_z|],   dM = r_cp x dF
    V = air velocity relative to the fuselage plus the main-rotor downwash (as eq 5.13).
    Signature: ax, ay (az) residuals proportional to airspeed squared along that axis,
    pitch/yaw residuals proportional to the same through the centre-of-pressure offset.
    dC = 0 switches it off."""

    PARAMETERS = (
        Parameter("dcx_m2", 0.0, "m^2", (-0.5, 0.5), "fitted"),
        Parameter("dcy_m2", 0.0, "m^2", (-0.5, 0.5), "fitted"),
        Parameter("dcz_m2", 0.0, "m^2", (-0.5, 0.5), "fitted"),
        Parameter("x_cp_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="centre of pressure ahead of CG"),
        Parameter("z_cp_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="centre of pressure below CG"),
    )
    REQUIRES = ("rigid_body",)

    @kernel
    def forces(q, p, s, ds, load, scratch):
        vx, vy, vz = air_velocity_at(q, 0.0, 0.0, 0.0)
        vz += q[Q.rotor_wake_m_s]  # zero without a main rotor
        k = q[Q.air_density_kg_m3] / 6.0
        fx = k * p.dcx_m2 * vx * abs(vx)
        fy = k * p.dcy_m2 * vy * abs(vy)
        fz = k * p.dcz_m2 * vz * abs(vz)
        mx, my, mz = cross(p.x_cp_m, 0.0, p.z_cp_m, fx, fy, fz)
        add_load(load, fx, fy, fz, mx, my, mz)
