"""Fuselage drag error (catalogue effect)."""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.effects._util import cross, vec3
from airwake.heli.effects.base import Effect, Parameter, register_effect


@register_effect("fuselage_drag_error")
class FuselageDragError(Effect):
    """A correction to the eq 5.13 fuselage drag: extra drag areas dC (m^2, either sign)
    acting at a centre of pressure r_cp = (x_cp, 0, z_cp) from the CG (the reference puts
    the drag at the CG, so it has no moment):
        dF = rho/6 [dC_X V_x|V_x|, dC_Y V_y|V_y|, dC_Z V_z|V_z|],   dM = r_cp x dF
    V = air velocity relative to the fuselage plus the main-rotor downwash (as eq 5.13).
    Signature: ax, ay (az) residuals proportional to airspeed squared along that axis,
    pitch/yaw residuals proportional to the same through the centre-of-pressure offset."""

    PARAMETERS = (
        Parameter("dcx_m2", 0.0, "m^2", (-0.5, 0.5), "fitted"),
        Parameter("dcy_m2", 0.0, "m^2", (-0.5, 0.5), "fitted"),
        Parameter("dcz_m2", 0.0, "m^2", (-0.5, 0.5), "fitted"),
        Parameter("x_cp_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="centre of pressure ahead of CG"),
        Parameter("z_cp_m", 0.0, "m", (-1.0, 1.0), "fitted", doc="centre of pressure below CG"),
    )
    REQUIRES = ("rigid_body",)

    def forces(self, ctx, p) -> None:
        v = np.array(ctx.air_velocity_at(np.zeros(3)), dtype=float)
        wake = getattr(ctx, "rotor_wake_m_s", None)
        if wake is not None:
            v[:, 2] += np.asarray(wake, float)
        dc = vec3(p.dcx_m2, p.dcy_m2, p.dcz_m2)
        rho = np.reshape(np.asarray(ctx.air_density_kg_m3, float), (-1, 1))
        force = rho / 6.0 * dc * v * np.abs(v)
        r_cp = vec3(p.x_cp_m, 0.0, p.z_cp_m)
        ctx.add_load(self.name, force, cross(np.broadcast_to(r_cp, force.shape), force))
