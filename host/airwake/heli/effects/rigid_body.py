"""Rigid-body fuselage dynamics (eq 5.2) and the measurement it implies."""

from __future__ import annotations

import numpy as np

from airwake.heli.effects.base import Effect, Parameter, State, col, register_effect

_BODY_STATES = (
    State("pos_n_m", "m", "position north (NED, inertial)"),
    State("pos_e_m", "m", "position east"),
    State("pos_d_m", "m", "position down"),
    State("vel_u_m_s", "m/s", "body velocity x (forward)"),
    State("vel_v_m_s", "m/s", "body velocity y (right)"),
    State("vel_w_m_s", "m/s", "body velocity z (down)"),
    State("roll_rad", "rad", "Euler roll phi"),
    State("pitch_rad", "rad", "Euler pitch theta"),
    State("yaw_rad", "rad", "Euler yaw psi"),
    State("p_rad_s", "rad/s", "body roll rate"),
    State("q_rad_s", "rad/s", "body pitch rate"),
    State("r_rad_s", "rad/s", "body yaw rate"),
)


def body_to_ned(roll, pitch, yaw) -> np.ndarray:
    """Rotation matrices C_nb (N,3,3) for ZYX Euler angles: v_ned = C_nb @ v_body."""
    cf, sf = np.cos(roll), np.sin(roll)
    ct, st = np.cos(pitch), np.sin(pitch)
    cp, sp = np.cos(yaw), np.sin(yaw)
    return np.stack(
        [
            np.stack([cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf], -1),
            np.stack([sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf], -1),
            np.stack([-st, ct * sf, ct * cf], -1),
        ],
        -2,
    )


@register_effect("rigid_body")
class RigidBody(Effect):
    """Six-degree-of-freedom rigid fuselage, eq 5.2 (with I_xz), NED position.

    Translational (body axes, X/Y/Z = sum of all effects' forces incl. gravity):
        u' = r v - q w + X/M,  v' = p w - r u + Y/M,  w' = q u - p v + Z/M
    Rotational (I_xz product of inertia, eq 5.2 rearranged):
        I_xx p' - I_xz r' = (I_yy - I_zz) q r + I_xz p q + L
        I_yy q'           = (I_zz - I_xx) r p + I_xz (r^2 - p^2) + M
        I_zz r' - I_xz p' = (I_xx - I_yy) p q - I_xz q r + N
    Euler kinematics: phi' = p + (q sin phi + r cos phi) tan theta,
        theta' = q cos phi - r sin phi, psi' = (q sin phi + r cos phi) / cos theta.
    Measurement (at the CG): specific force = (sum of *sensed* forces)/M, i.e. without
    gravity (what an accelerometer reads), and the angular accelerations p', q', r'.
    """

    PARAMETERS = (
        Parameter("mass_kg", 4.975, "kg", (0.5, 50.0), "Table 5.1 (M_H)", fixed=True),
        Parameter("Ixx_kg_m2", 0.3173, "kg m^2", (0.01, 10.0), "Table 5.1 (CAD)"),
        Parameter("Iyy_kg_m2", 1.483, "kg m^2", (0.01, 10.0), "Table 5.1 (CAD)"),
        Parameter("Izz_kg_m2", 1.539, "kg m^2", (0.01, 10.0), "Table 5.1 (CAD)"),
        Parameter("Ixz_kg_m2", -0.0519, "kg m^2", (-1.0, 1.0), "Table 5.1 (CAD)"),
    )
    STATES = _BODY_STATES
    MEASURED_STATES = {s.name: s.name for s in _BODY_STATES}

    def environment(self, ctx, p) -> None:
        ctx.mass_kg = p.mass_kg
        ctx.inertia = (p.Ixx_kg_m2, p.Iyy_kg_m2, p.Izz_kg_m2, p.Ixz_kg_m2)

    def body_dynamics(self, ctx, p) -> None:
        f, m = ctx.total_load()
        f_sensed, _ = ctx.total_load(sensed_only=True)
        u, v, w = ctx.vel_b_m_s.T
        pr, qr, rr = ctx.omega_b_rad_s.T
        mass = p.mass_kg
        ixx, iyy, izz, ixz = p.Ixx_kg_m2, p.Iyy_kg_m2, p.Izz_kg_m2, p.Ixz_kg_m2
        # eq 5.2, translational
        udot = rr * v - qr * w + f[:, 0] / mass
        vdot = pr * w - rr * u + f[:, 1] / mass
        wdot = qr * u - pr * v + f[:, 2] / mass
        # eq 5.2, rotational: solve the 2x2 (p', r') system coupled through I_xz
        rhs_p = (iyy - izz) * qr * rr + ixz * pr * qr + m[:, 0]
        rhs_r = (ixx - iyy) * pr * qr - ixz * qr * rr + m[:, 2]
        det = ixx * izz - ixz * ixz
        pdot = (izz * rhs_p + ixz * rhs_r) / det
        rdot = (ixz * rhs_p + ixx * rhs_r) / det
        qdot = ((izz - ixx) * rr * pr + ixz * (rr * rr - pr * pr) + m[:, 1]) / iyy
        # Euler kinematics
        sf, cf = np.sin(ctx.roll_rad), np.cos(ctx.roll_rad)
        ct, tt = np.cos(ctx.pitch_rad), np.tan(ctx.pitch_rad)
        a = qr * sf + rr * cf
        rolldot = pr + a * tt
        pitchdot = qr * cf - rr * sf
        yawdot = a / ct
        ned = np.einsum("nij,nj->ni", body_to_ned(ctx.roll_rad, ctx.pitch_rad, ctx.yaw_rad),
                        ctx.vel_b_m_s)
        rates = np.column_stack(
            [ned, udot, vdot, wdot, rolldot, pitchdot, yawdot, pdot, qdot, rdot]
        )
        ctx.set_rates(self.name, rates)
        ctx.meas[:, 0:3] = f_sensed / col(mass)
        ctx.meas[:, 3] = pdot
        ctx.meas[:, 4] = qdot
        ctx.meas[:, 5] = rdot
