"""Main rotor: blade-element loads, centre-spring flapping and lead-lag (eq 5.5-5.11)."""

from __future__ import annotations

import math

import numpy as np

from airwake.heli.effects.base import Effect, Parameter, State, register_effect
from airwake.heli.kernel import Q, air_velocity_at, cross, kernel

# Azimuth quadrature. Every integrand is a trigonometric polynomial of degree <= 5 in the
# blade azimuth psi (first-harmonic states times blade-element products), so an 8-point
# rectangle rule gives the rotor averages and first harmonics exactly.
N_PSI = 8
PSI = 2.0 * np.pi * np.arange(N_PSI) / N_PSI
COS = np.cos(PSI)
SIN = np.sin(PSI)
CC = COS * COS
CS = COS * SIN
SS = SIN * SIN
W = 1.0 / N_PSI  # azimuth-average weight
_THIRD = 1.0 / 3.0

# scratch layout (per row, rotor_loading -> forces): eight azimuth samples of each
_C, _D, _TH, _BE, _ZP, _T0, _T1, _T2, _I0, _I1 = (k * N_PSI for k in range(10))
_KT = 10 * N_PSI


@register_effect("main_rotor")
class MainRotor(Effect):
    """Main rotor with first-harmonic flapping and lead-lag in multi-blade coordinates.

    Computed in a *rotor frame*: the body frame mirrored (y -> -y) for a clockwise rotor,
    so one set of equations (counter-clockwise seen from above, azimuth psi from the tail
    towards +y) serves both senses. Blade element at rbar = r/R, azimuth psi:
      e_r = (-cos psi, sin psi, 0), e_t = (sin psi, cos psi, 0)
      U_T = -V0.e_t/(Omega R) + rbar (1 + w_z/Omega + zeta')                       (5.5, 5.6)
      U_P = -V0_z/(Omega R) - beta V0.e_r/(Omega R)
            - rbar (w_x sin psi + w_y cos psi)/Omega - rbar beta' - lambda(rbar, psi)  (5.5, 5.6)
    with V0 the air velocity relative to the moving hub (eq 5.3 wind minus hub motion)
    and w = (wind rotation - body rates), both in the rotor frame; the helicopter's own
    translation is included (the reference's 5.5 leaves u, v, w out).
    Lift and drag (5.7), normalised by rho c a0 (Omega R)^2 / 2:
      F_L = U_T^2 theta + U_T U_P,  F_D = U_P^2 + U_T U_P theta - (delta/a0) U_T^2,
      delta = delta_0 + delta_2 C_T^2;  F_D > 0 pushes the blade forward (lead).
    Both are integrated analytically over rbar in [0, 1].
    Flapping (5.8), centre spring:  beta'' + lambda_b^2 beta = 2(p cos psi - q sin psi)/Omega
      + (gamma/2) int F_L rbar;  lambda_b^2 = 1 + K_beta/(I_beta Omega^2).
    Lead-lag (5.9), lead positive:  zeta'' + 2 xi lambda_z zeta' + lambda_z^2 zeta
      = (gamma/2) int F_D rbar;  lambda_z^2 = 3 e/(2(1-e)) + K_zeta/(I_beta Omega^2).
    Both are projected on multi-blade coordinates (0, c, s) by the azimuth average.
    Forces (5.10): F = N_b gamma I_beta Omega^2/(2R) <F_L n + F_D e_t>, n = -z - beta e_r.
    Moments (5.11): hub spring -(N_b/2) K_beta (beta_s, beta_c) in roll/pitch, hub torque
      -N_b I_beta Omega^2 lambda_z^2 zeta_0 (the lag spring transmits the drag torque), plus
      r_hub x F with the hub h_R above the CG.
    Deviations from the reference (see docs/effects.md): the Lock number and a0 are kept as
    separate parameters as in Table 5.2; the hub torque goes through the lag spring so that
    it equals the aerodynamic torque in steady state; a structural lag damping ratio is
    added (the aerodynamic lag damping alone is ~0.3 % of critical).
    """

    PARAMETERS = (
        Parameter("radius_m", 0.673, "m", (0.2, 1.5), "Table 5.1 (R)", fixed=True),
        Parameter("nominal_speed_rad_s", 163.3, "rad/s", (50.0, 400.0), "Table 5.1 (Omega)",
                  fixed=True, doc="constant rotor speed Omega*; a measured speed is used only "
                  "by the rotor_droop effect"),
        Parameter("blade_count", 2.0, "-", (2.0, 6.0), "T-Rex 600E", fixed=True,
                  choices=(2.0, 3.0, 4.0, 5.0, 6.0)),
        Parameter("chord_m", 0.054, "m", (0.01, 0.2), "Table 5.1 (c)", fixed=True,
                  doc="documents the Lock number rho c a0 R^4 / I_beta"),
        Parameter("lift_slope_per_rad", 6.08, "1/rad", (1.0, 8.0), "Table 5.1 (a0, NACA0012)"),
        Parameter("drag_delta0", 7.3034e-3, "-", (0.0, 0.2), "Table 5.1 (delta_0)"),
        Parameter("drag_delta2", 4.912e-3, "-", (0.0, 50.0), "Table 5.1 (delta_2)"),
        Parameter("lock_number", 4.486, "-", (0.5, 15.0), "Table 5.1 (gamma)"),
        Parameter("flap_inertia_kg_m2", 0.0184, "kg m^2", (0.001, 0.2), "Table 5.1 (I_beta)"),
        Parameter("flap_stiffness_nm_rad", 84.2, "N m/rad", (0.0, 2000.0), "Table 5.1 (K_beta)"),
        Parameter("lag_hinge_offset", 0.1071, "-", (0.0, 0.5), "Table 5.1 (e_zeta)"),
        Parameter("lag_stiffness_nm_rad", 148.8, "N m/rad", (0.0, 2000.0), "Table 5.1 (K_zeta)"),
        Parameter("lag_damping_ratio", 0.3, "-", (0.0, 2.0), "assumed (not in the reference)",
                  doc="structural lag damping (blade-grip friction/damper)"),
        Parameter("hub_height_m", 0.21, "m", (0.0, 1.0), "Table 5.1 (h_R)"),
        Parameter("disk_area_m2", 1.4116, "m^2", (0.1, 5.0), "Table 5.1 (A_d)",
                  doc="wake velocity sqrt(T/(2 rho A_d)) on fuselage and tail"),
        Parameter("rotation", -1.0, "-", (-1.0, 1.0), "T-Rex 600E: clockwise from above",
                  fixed=True, choices=(-1.0, 1.0),
                  doc="+1 counter-clockwise seen from above, -1 clockwise"),
    )
    STATES = (
        State("beta_0_rad", "rad", "coning"),
        State("beta_c_rad", "rad", "longitudinal flapping (cos psi; + = disk tilted forward)"),
        State("beta_s_rad", "rad", "lateral flapping (rotor frame sin psi)"),
        State("beta_0_dot_rad_s", "rad/s", ""),
        State("beta_c_dot_rad_s", "rad/s", ""),
        State("beta_s_dot_rad_s", "rad/s", ""),
        State("zeta_0_rad", "rad", "collective lead (+ = ahead of the hub)"),
        State("zeta_c_rad", "rad", ""),
        State("zeta_s_rad", "rad", ""),
        State("zeta_0_dot_rad_s", "rad/s", ""),
        State("zeta_c_dot_rad_s", "rad/s", ""),
        State("zeta_s_dot_rad_s", "rad/s", ""),
    )
    REQUIRES = ("rigid_body",)
    SCRATCH = _KT + 1

    # -- stages (compiled kernels, one row each) -------------------------------------
    @kernel
    def environment(q, p, s, ds, load, scratch):
        q[Q.wind_origin_m] = 0.0
        q[Q.wind_origin_m + 1] = 0.0
        q[Q.wind_origin_m + 2] = -p.hub_height_m
        q[Q.rotor_sense] = p.rotation

    @kernel
    def rotor_speed(q, p, s, ds, load, scratch):
        # The reference treats Omega as a constant (Table 5.1): the measured rotor speed
        # enters only through the `rotor_droop` catalogue effect (airwake.discrepancy).
        q[Q.rotor_speed_rad_s] = p.nominal_speed_rad_s

    @kernel
    def rotor_setup(q, p, s, ds, load, scratch):
        sense = p.rotation
        om = q[Q.rotor_speed_rad_s]
        vtip = om * p.radius_m
        v0x, v0y, v0z = air_velocity_at(q, q[Q.wind_origin_m], q[Q.wind_origin_m + 1],
                                        q[Q.wind_origin_m + 2])
        # rotor frame: vectors y -> s*y, pseudo-vectors (rates) x, z -> s*x, s*z
        v0y_r = v0y * sense
        q[Q.hub_air_velocity_m_s] = v0x
        q[Q.hub_air_velocity_m_s + 1] = v0y
        q[Q.hub_air_velocity_m_s + 2] = v0z
        q[Q.hub_air_velocity_rotor_m_s] = v0x
        q[Q.hub_air_velocity_rotor_m_s + 1] = v0y_r
        q[Q.hub_air_velocity_rotor_m_s + 2] = v0z
        for j in range(3):
            w_rel = q[Q.wind_w_rad_s + j] - q[Q.omega_b_rad_s + j]
            k = 1.0 if j == 1 else sense
            q[Q.rel_rotation_rotor_rad_s + j] = w_rel * k
            q[Q.body_rates_rotor_rad_s + j] = q[Q.omega_b_rad_s + j] * k
        q[Q.tip_speed_m_s] = vtip
        q[Q.advance_ratio] = math.hypot(v0x, v0y_r) / vtip
        q[Q.axial_flow_ratio] = v0z / vtip

    @kernel
    def blade_pitch(q, p, s, ds, load, scratch):
        # Rotor-frame swashplate: + lateral command tilts the disk right (roll right),
        # + longitudinal command tilts it forward (nose down), whatever the rotor sense.
        q[Q.swash_c] = -p.rotation * q[Q.delta_lat_rad]
        q[Q.swash_s] = -q[Q.delta_lon_rad]
        q[Q.theta_0] = q[Q.delta_col_rad]
        q[Q.theta_c] = q[Q.swash_c]
        q[Q.theta_s] = q[Q.swash_s]

    @kernel
    def rotor_loading(q, p, s, ds, load, scratch):
        v0x = q[Q.hub_air_velocity_rotor_m_s]
        v0y = q[Q.hub_air_velocity_rotor_m_s + 1]
        v0z = q[Q.hub_air_velocity_rotor_m_s + 2]
        wrx = q[Q.rel_rotation_rotor_rad_s]
        wry = q[Q.rel_rotation_rotor_rad_s + 1]
        wrz = q[Q.rel_rotation_rotor_rad_s + 2]
        vt = q[Q.tip_speed_m_s]
        om = q[Q.rotor_speed_rad_s]
        b0, bc, bs, db0, dbc, dbs = s[0], s[1], s[2], s[3], s[4], s[5]
        zc, zs, dz0, dzc, dzs = s[7], s[8], s[9], s[10], s[11]
        th0, thc, ths = q[Q.theta_0], q[Q.theta_c], q[Q.theta_s]
        inv_vt, inv_om = 1.0 / vt, 1.0 / om
        # first-harmonic series x0 + xc cos psi + xs sin psi, ' = d/dpsi
        zp0, zpc, zps = dz0 * inv_om, dzc * inv_om + zs, dzs * inv_om - zc  # zeta'
        bp0, bpc, bps = db0 * inv_om, dbc * inv_om + bs, dbs * inv_om - bc  # beta'
        b_0 = 1.0 + wrz * inv_om
        c_0 = -v0z * inv_vt
        lift_m = mom_c = mom_s = t0_m = t1_c = t1_s = cc = cs = ss = 0.0
        for k in range(N_PSI):
            ck, sk = COS[k], SIN[k]
            # U_T = a + b rbar, U_P = c + d rbar  (c, d without inflow)      (5.5, 5.6)
            a = -(v0x * sk + v0y * ck) * inv_vt
            zeta_p = zp0 + zpc * ck + zps * sk
            b = b_0 + zeta_p
            beta = b0 + bc * ck + bs * sk
            beta_p = bp0 + bpc * ck + bps * sk
            er_v0 = -v0x * ck + v0y * sk
            c = c_0 - beta * er_v0 * inv_vt
            d = -(wrx * sk + wry * ck) * inv_om - beta_p
            theta = th0 + thc * ck + ths * sk
            t0 = a + 0.5 * b
            t1 = 0.5 * a + b * _THIRD
            t2 = a * _THIRD + 0.25 * b
            i0tt = a * a + a * b + b * b * _THIRD
            i1tt = 0.5 * a * a + 2.0 / 3.0 * a * b + 0.25 * b * b
            lift = theta * i0tt + c * t0 + d * t1
            mom = theta * i1tt + c * t1 + d * t2
            lift_m += lift * W
            mom_c += mom * (COS[k] * W)
            mom_s += mom * (SIN[k] * W)
            t0_m += t0 * W
            t1_c += t1 * (COS[k] * W)
            t1_s += t1 * (SIN[k] * W)
            cc += t2 * CC[k]
            cs += t2 * CS[k]
            ss += t2 * SS[k]
            scratch[_C + k] = c
            scratch[_D + k] = d
            scratch[_TH + k] = theta
            scratch[_BE + k] = beta
            scratch[_ZP + k] = zeta_p
            scratch[_T0 + k] = t0
            scratch[_T1 + k] = t1
            scratch[_T2 + k] = t2
            scratch[_I0 + k] = i0tt
            scratch[_I1 + k] = i1tt
        # Loads in coefficient form [C_T, m_c, m_s] (m: first harmonics of the lift moment,
        # normalised by rho pi R^2 (Omega R)^2 R), affine in the inflow (l0, lc, ls).
        k_t = (p.blade_count * p.lock_number * p.flap_inertia_kg_m2
               / (2.0 * q[Q.air_density_kg_m3] * np.pi * p.radius_m**5))
        scratch[_KT] = k_t
        q[Q.rotor_load_base] = lift_m * k_t
        q[Q.rotor_load_base + 1] = mom_c * k_t
        q[Q.rotor_load_base + 2] = mom_s * k_t
        cc, cs, ss = cc * W, cs * W, ss * W
        jac = (t0_m, t1_c, t1_s, t1_c, cc, cs, t1_s, cs, ss)
        for j in range(9):
            q[Q.rotor_load_jac + j] = -jac[j] * k_t

    @kernel
    def forces(q, p, s, ds, load, scratch):
        om = q[Q.rotor_speed_rad_s]
        k_t = scratch[_KT]
        l0, lc, ls = q[Q.inflow_0], q[Q.inflow_c], q[Q.inflow_s]
        # C_T first (the profile drag depends on it): the loads are affine in the inflow
        ct = q[Q.rotor_load_base] + (q[Q.rotor_load_jac] * l0 + q[Q.rotor_load_jac + 1] * lc
                                     + q[Q.rotor_load_jac + 2] * ls)
        lift_m = ct / k_t
        k_drag = (p.drag_delta0 + p.drag_delta2 * ct * ct) / p.lift_slope_per_rad
        gam = p.lock_number
        e = p.lag_hinge_offset
        om2 = om * om
        lz2 = 1.5 * e / (1.0 - e) + p.lag_stiffness_nm_rad / (p.flap_inertia_kg_m2 * om2)
        lz = math.sqrt(lz2)
        damp = 2.0 * p.lag_damping_ratio * lz
        fx = fy = hm0 = hm1 = hm2 = hz0 = hz1 = hz2 = drag1_m = 0.0
        for k in range(N_PSI):
            ck, sk = COS[k], SIN[k]
            theta, t0, t1, t2 = (scratch[_TH + k], scratch[_T0 + k], scratch[_T1 + k],
                                 scratch[_T2 + k])
            i0tt, i1tt = scratch[_I0 + k], scratch[_I1 + k]
            c = scratch[_C + k] - l0
            d = scratch[_D + k] - (lc * ck + ls * sk)
            i0tp = c * t0 + d * t1
            i1tp = c * t1 + d * t2
            i0pp = c * c + c * d + d * d * _THIRD
            i1pp = 0.5 * c * c + 2.0 / 3.0 * c * d + 0.25 * d * d
            lift = theta * i0tt + i0tp  # int F_L drbar            (5.7, 5.10)
            mom = theta * i1tt + i1tp  # int F_L rbar drbar       (5.8)
            drag0 = i0pp + theta * i0tp - k_drag * i0tt  # int F_D drbar   (5.7)
            drag1 = i1pp + theta * i1tp - k_drag * i1tt  # int F_D rbar drbar
            # eq 5.10: rotor-averaged force, n = -z - beta e_r, e_r = (-cos, sin, 0)
            bl = scratch[_BE + k] * lift
            fx += (bl * ck + drag0 * sk) * W
            fy += (-bl * sk + drag0 * ck) * W
            hm0 += mom * W
            hm1 += mom * (ck * W)
            hm2 += mom * (sk * W)
            rhs_z = 0.5 * gam * drag1 - damp * scratch[_ZP + k]
            hz0 += rhs_z * W
            hz1 += rhs_z * (ck * W)
            hz2 += rhs_z * (sk * W)
            drag1_m += drag1 * W
        nb = p.blade_count
        scale = nb * gam * p.flap_inertia_kg_m2 * om * om / (2.0 * p.radius_m)
        fx *= scale
        fy *= scale
        fz = -lift_m * scale
        # eq 5.8 in multi-blade coordinates
        b0, bc, bs, db0, dbc, dbs = s[0], s[1], s[2], s[3], s[4], s[5]
        z0, zc, zs, dz0, dzc, dzs = s[6], s[7], s[8], s[9], s[10], s[11]
        r0 = 0.5 * gam * hm0
        rc = 2.0 * q[Q.body_rates_rotor_rad_s] / om + gam * hm1
        rs = -2.0 * q[Q.body_rates_rotor_rad_s + 1] / om + gam * hm2
        lb2 = 1.0 + p.flap_stiffness_nm_rad / (p.flap_inertia_kg_m2 * om2)
        ds[0] = db0
        ds[1] = dbc
        ds[2] = dbs
        ds[3] = om2 * (r0 - lb2 * b0)
        ds[4] = om2 * (rc - (lb2 - 1.0) * bc) - 2.0 * om * dbs
        ds[5] = om2 * (rs - (lb2 - 1.0) * bs) + 2.0 * om * dbc
        # eq 5.9 (lead positive) with structural damping, multi-blade coordinates
        ds[6] = dz0
        ds[7] = dzc
        ds[8] = dzs
        ds[9] = om2 * (hz0 - lz2 * z0)
        ds[10] = om2 * (2.0 * hz1 - (lz2 - 1.0) * zc) - 2.0 * om * dzs
        ds[11] = om2 * (2.0 * hz2 - (lz2 - 1.0) * zs) + 2.0 * om * dzc
        # eq 5.11: hub spring moments and the torque through the lag spring
        mx = -0.5 * nb * p.flap_stiffness_nm_rad * bs
        my = -0.5 * nb * p.flap_stiffness_nm_rad * bc
        mz = -nb * p.flap_inertia_kg_m2 * om2 * lz2 * z0
        sense = p.rotation
        fy *= sense
        hx, hy, hz = q[Q.wind_origin_m], q[Q.wind_origin_m + 1], q[Q.wind_origin_m + 2]
        cx, cy, cz = cross(hx, hy, hz, fx, fy, fz)
        load[0] += fx
        load[1] += fy
        load[2] += fz
        load[3] += sense * mx + cx
        load[4] += my + cy
        load[5] += sense * mz + cz
        thrust = -fz
        q[Q.thrust_n] = thrust
        q[Q.thrust_coeff] = ct
        q[Q.rotor_torque_nm] = -scale * p.radius_m * drag1_m
        q[Q.rotor_wake_m_s] = q[Q.inflow_0] * q[Q.tip_speed_m_s] + math.sqrt(
            np.maximum(thrust, 0.0) / (2.0 * q[Q.air_density_kg_m3] * p.disk_area_m2))
        q[Q.flapping_rad] = b0
        q[Q.flapping_rad + 1] = bc
        q[Q.flapping_rad + 2] = bs
