"""Mass and centre-of-gravity error (catalogue effect)."""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.effects._util import cross, inertia, vec3
from airwake.heli.effects.base import Effect, Parameter, register_effect


@register_effect("cg_offset")
class CgOffset(Effect):
    """The true CG is at r = (x, y, z) from the model's reference CG and the true mass is
    M + dM (payload, battery placement, a camera). Every aerodynamic load of the model is
    computed about the reference point; about the true CG its moment is
        M_true = M_ref - r x F_aero          (gravity acts at the true CG: no moment)
    and the specific force is F_aero / (M + dM). Applied to the measurement (the rigid
    body's sensed force F = M a_meas): acc <- acc M/(M + dM); omega_dot <- omega_dot
    - I^-1 (r x F). Signature: pitch/roll residuals proportional to thrust (a hover
    trim shift) and az residual proportional to the specific force (mass)."""

    PARAMETERS = (
        Parameter("x_m", 0.0, "m", (-0.3, 0.3), "fitted", doc="true CG ahead of the model's"),
        Parameter("y_m", 0.0, "m", (-0.3, 0.3), "fitted", doc="true CG right of the model's"),
        Parameter("z_m", 0.0, "m", (-0.3, 0.3), "fitted", doc="true CG below the model's"),
        Parameter("mass_error_kg", 0.0, "kg", (-3.0, 3.0), "fitted",
                  doc="true mass minus the model's"),
    )
    REQUIRES = ("rigid_body",)

    def measurement(self, ctx, p) -> None:
        mass = np.asarray(ctx.mass_kg, float)
        meas = np.array(ctx.meas, dtype=float)
        force = meas[:, 0:3] * np.reshape(mass, (-1, 1))
        dm = -cross(vec3(p.x_m, p.y_m, p.z_m), force)
        ixx, iyy, izz, ixz = inertia(ctx)
        det = ixx * izz - ixz * ixz
        meas[:, 3] += (izz * dm[:, 0] + ixz * dm[:, 2]) / det  # eq 5.2's I_xz coupling
        meas[:, 4] += dm[:, 1] / iyy
        meas[:, 5] += (ixz * dm[:, 0] + ixx * dm[:, 2]) / det
        meas[:, 0:3] = force / np.reshape(mass + p.mass_error_kg, (-1, 1))
        ctx.meas = meas
