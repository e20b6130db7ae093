"""Tail rotor (eq 5.12) with momentum-theory inflow."""

from __future__ import annotations

import math

import numpy as np

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, add_load, air_velocity_at, cross, kernel

_ITERATIONS = 6


@register_effect("tail_rotor")
class TailRotor(Effect):
    """Tail rotor at r_T = (-l_T, 0, -h_T), thrust Y_T along -y for positive blade pitch
    theta_T = delta_ped (so + pedal yaws the nose right), Omega_T = N_T Omega.

    Blade-element thrust (eq 5.12) with uniform induced inflow lambda_i:
        C_T = (sigma a_0T / 2) [theta_T/3 (1 + 3/2 mu^2) - (lambda_i + lambda_y)/2]
        lambda_i = C_T / (2 sqrt(mu^2 + (lambda_i + lambda_y)^2))       (momentum theory)
        Y_T = C_T rho pi R_T^2 (Omega_T R_T)^2,  F_T = (0, -Y_T, 0),  M_T = r_T x F_T
    with v_T = eq 5.3 wind at r_T minus the tail's velocity (v_H + omega_H x r_T),
    lambda_y = v_T,y/(Omega_T R_T) (flow in the direction the rotor blows), mu the in-plane
    part, sigma = N_b c_T/(pi R_T). Deviation: the reference neglects the induced inflow
    (its thrust is linear in pitch); momentum theory is kept here because the tail rotor
    at trim has lambda_i ~ 0.05, comparable to theta_T/3.
    Also exposes ctx.tail_wash_m_s = sign(Y_T) sqrt(|Y_T|/(2 rho A_dT)) (+y wake speed)
    for the vertical fin (eq 5.14).
    """

    PARAMETERS = (
        Parameter("radius_m", 0.13, "m", (0.03, 0.5), "Table 5.1 (R_T)"),
        Parameter("speed_ratio", 3.85, "-", (1.0, 10.0), "Table 5.1 (N_T)", fixed=True),
        Parameter("chord_m", 0.027, "m", (0.005, 0.1), "Table 5.1 (c_T)", fixed=True),
        Parameter("lift_slope_per_rad", 6.08, "1/rad", (1.0, 10.0), "Table 5.1 (a_0T)"),
        Parameter("blade_count", 2.0, "-", (2.0, 6.0), "T-Rex 600E", fixed=True,
                  choices=(2.0, 3.0, 4.0, 5.0, 6.0)),
        Parameter("arm_m", 0.79, "m", (0.1, 3.0), "Table 5.1 (l_T)"),
        Parameter("height_m", 0.012, "m", (-0.5, 0.5), "Table 5.1 (h_T)"),
        Parameter("disk_area_m2", 3.3e-2, "m^2", (0.001, 1.0), "Table 5.1 (A_dT)"),
    )
    REQUIRES = ("main_rotor",)
    ITERATIONS = _ITERATIONS

    @kernel
    def forces(q, p, s, ds, load, scratch):
        rx, ry, rz = -p.arm_m, 0.0, -p.height_m
        vx, vy, vz = air_velocity_at(q, rx, ry, rz)
        tip = p.speed_ratio * q[Q.rotor_speed_rad_s] * p.radius_m
        mu2 = (vx**2 + vz**2) / (tip * tip)
        lam_y = vy / tip
        theta = q[Q.delta_ped_rad]
        q[Q.tail_pitch_rad] = theta
        k = p.blade_count * p.chord_m / (np.pi * p.radius_m) * p.lift_slope_per_rad / 2.0
        c_geo = k * (theta / 3.0 * (1.0 + 1.5 * mu2) - 0.5 * lam_y)  # C_T at lambda_i = 0
        lam = np.sign(c_geo) * math.sqrt(abs(c_geo) / 2.0 + 1e-12) * 0.5
        for _ in range(_ITERATIONS):
            # f(l) = 2 l S(l) - C_T(l),  C_T(l) = c_geo - k l / 2
            lt = lam + lam_y
            sq = math.sqrt(mu2 + lt * lt + 1e-8)
            f = 2.0 * lam * sq - (c_geo - 0.5 * k * lam)
            fp = 2.0 * sq + 2.0 * lam * lt / sq + 0.5 * k
            step = f / fp
            lam = lam - step
            if abs(step) <= 1e-13 * abs(lam):
                break  # converged (Newton: the next step would be ~1e-26)
        ct = c_geo - 0.5 * k * lam
        rho = q[Q.air_density_kg_m3]
        thrust = ct * rho * np.pi * p.radius_m**2 * tip * tip
        mx, my, mz = cross(rx, ry, rz, 0.0, -thrust, 0.0)
        add_load(load, 0.0, -thrust, 0.0, mx, my, mz)
        q[Q.tail_thrust_n] = thrust
        q[Q.tail_inflow] = lam
        q[Q.tail_wash_m_s] = np.sign(thrust) * math.sqrt(abs(thrust) / (2.0 * rho * p.disk_area_m2))
