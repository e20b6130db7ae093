"""Rigid-body fuselage dynamics (eq 5.2) and the measurement it implies."""

from __future__ import annotations

import math

import numpy as np

from airwake.heli.effects.base import Effect, Parameter, State, register_effect
from airwake.heli.kernel import Q, kernel

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

    @kernel
    def environment(q, p, s, ds, load, scratch):
        q[Q.mass_kg] = p.mass_kg
        q[Q.inertia] = p.Ixx_kg_m2
        q[Q.inertia + 1] = p.Iyy_kg_m2
        q[Q.inertia + 2] = p.Izz_kg_m2
        q[Q.inertia + 3] = p.Ixz_kg_m2

    @kernel
    def body_dynamics(q, p, s, ds, load, scratch):
        fx, fy, fz = q[Q.force_n], q[Q.force_n + 1], q[Q.force_n + 2]
        mx, my, mz = q[Q.moment_nm], q[Q.moment_nm + 1], q[Q.moment_nm + 2]
        u, v, w = q[Q.vel_b_m_s], q[Q.vel_b_m_s + 1], q[Q.vel_b_m_s + 2]
        pr, qr, rr = q[Q.omega_b_rad_s], q[Q.omega_b_rad_s + 1], q[Q.omega_b_rad_s + 2]
        mass = p.mass_kg
        ixx, iyy, izz, ixz = p.Ixx_kg_m2, p.Iyy_kg_m2, p.Izz_kg_m2, p.Ixz_kg_m2
        # eq 5.2, translational
        udot = rr * v - qr * w + fx / mass
        vdot = pr * w - rr * u + fy / mass
        wdot = qr * u - pr * v + fz / mass
        # eq 5.2, rotational: solve the 2x2 (p', r') system coupled through I_xz
        rhs_p = (iyy - izz) * qr * rr + ixz * pr * qr + mx
        rhs_r = (ixx - iyy) * pr * qr - ixz * qr * rr + mz
        det = ixx * izz - ixz * ixz
        pdot = (izz * rhs_p + ixz * rhs_r) / det
        rdot = (ixz * rhs_p + ixx * rhs_r) / det
        qdot = ((izz - ixx) * rr * pr + ixz * (rr * rr - pr * pr) + my) / iyy
        # Euler kinematics
        roll, pitch, yaw = q[Q.roll_rad], q[Q.pitch_rad], q[Q.yaw_rad]
        sf, cf = math.sin(roll), math.cos(roll)
        st, ct = math.sin(pitch), math.cos(pitch)
        tt = st / ct
        a = qr * sf + rr * cf
        # position rate: C_nb (ZYX Euler) times the body velocity
        cp, sp = math.cos(yaw), math.sin(yaw)
        ds[0] = cp * ct * u + (cp * st * sf - sp * cf) * v + (cp * st * cf + sp * sf) * w
        ds[1] = sp * ct * u + (sp * st * sf + cp * cf) * v + (sp * st * cf - cp * sf) * w
        ds[2] = -st * u + ct * sf * v + ct * cf * w
        ds[3] = udot
        ds[4] = vdot
        ds[5] = wdot
        ds[6] = pr + a * tt
        ds[7] = qr * cf - rr * sf
        ds[8] = a / ct
        ds[9] = pdot
        ds[10] = qdot
        ds[11] = rdot
        # measurement at the CG: specific force (sensed loads / M) and angular accelerations
        q[Q.meas] = q[Q.sensed_force_n] / mass
        q[Q.meas + 1] = q[Q.sensed_force_n + 1] / mass
        q[Q.meas + 2] = q[Q.sensed_force_n + 2] / mass
        q[Q.meas + 3] = pdot
        q[Q.meas + 4] = qdot
        q[Q.meas + 5] = rdot
