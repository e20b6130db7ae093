"""Mass and centre-of-gravity error (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, cross, kernel


@register_effect("cg_offset")
class CgOffset(Effect):
    """The true CG is at r = (x, y, z) from the model's reference CG and the true mass is
    M + dM (payload, battery placement, a camera). Every aerodynamic load of the model is
    computed about the reference point; about the true CG its moment is
        M_true = M_ref - r x F_aero          (gravity acts at the true CG: no moment)
    and the specific force is F_aero / (M + dM). Applied to the measurement (the rigid
    body's sensed force F = M a_meas): acc <- acc M/(M + dM); omega_dot <- omega_dot
    + I^-1 (-r x F) (eq 5.2's inertia with I_xz). Signature: pitch/roll residuals
    proportional to the rotor force (a hover trim shift) and az residual proportional to
    the specific force (mass). r = 0, dM = 0 switch it off."""

    PARAMETERS = (
        Parameter("x_m", 0.0, "m", (-0.3, 0.3), "fitted", doc="true CG ahead of the model's"),
        Parameter("y_m", 0.0, "m", (-0.3, 0.3), "fitted", doc="true CG right of the model's"),
        Parameter("z_m", 0.0, "m", (-0.3, 0.3), "fitted", doc="true CG below the model's"),
        Parameter("mass_error_kg", 0.0, "kg", (-3.0, 3.0), "fitted",
                  doc="true mass minus the model's"),
    )
    REQUIRES = ("rigid_body",)

    @kernel
    def measurement(q, p, s, ds, load, scratch):
        mass = q[Q.mass_kg]
        fx, fy, fz = q[Q.meas] * mass, q[Q.meas + 1] * mass, q[Q.meas + 2] * mass
        mx, my, mz = cross(p.x_m, p.y_m, p.z_m, fx, fy, fz)
        mx, my, mz = -mx, -my, -mz
        ixx, iyy, izz, ixz = (q[Q.inertia], q[Q.inertia + 1], q[Q.inertia + 2],
                              q[Q.inertia + 3])
        det = ixx * izz - ixz * ixz
        q[Q.meas + 3] += (izz * mx + ixz * mz) / det
        q[Q.meas + 4] += my / iyy
        q[Q.meas + 5] += (ixz * mx + ixx * mz) / det
        total = mass + p.mass_error_kg
        q[Q.meas] = fx / total
        q[Q.meas + 1] = fy / total
        q[Q.meas + 2] = fz / total
