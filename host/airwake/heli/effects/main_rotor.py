"""Main rotor: blade-element loads, centre-spring flapping and lead-lag (eq 5.5-5.11)."""

from __future__ import annotations

import numpy as np

from airwake.heli.context import cross
from airwake.heli.effects.base import Effect, Parameter, State, col, register_effect

# Azimuth quadrature. Every integrand is a trigonometric polynomial of degree <= 5 in the
# blade azimuth psi (first-harmonic states times blade-element products), so an 8-point
# rectangle rule gives the rotor averages and first harmonics exactly.
N_PSI = 8
PSI = 2.0 * np.pi * np.arange(N_PSI) / N_PSI
COS = np.cos(PSI)
SIN = np.sin(PSI)
# columns: mean, mean*cos, mean*sin
_W3 = np.column_stack([np.ones(N_PSI), COS, SIN]) / N_PSI
_BASIS = np.vstack([np.ones(N_PSI), COS, SIN])  # (3, N_PSI)


def _harm(a: np.ndarray) -> np.ndarray:
    """(N, N_PSI) samples -> (N, 3): <a>, <a cos psi>, <a sin psi>."""
    return a @ _W3


def _series(x0, xc, xs):
    """First-harmonic series x0 + xc cos psi + xs sin psi sampled at PSI, (N, N_PSI)."""
    n = max(np.size(x0), np.size(xc), np.size(xs))
    return np.column_stack(np.broadcast_arrays(x0, xc, xs, np.zeros(n))[:3]) @ _BASIS


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
                  fixed=True, doc="used when the flight table has no measured rotor speed"),
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

    # -- stages -----------------------------------------------------------------------
    def environment(self, ctx, p) -> None:
        h = np.asarray(p.hub_height_m, dtype=float)
        ctx.wind_origin_m = np.stack([np.zeros_like(h), np.zeros_like(h), -h], -1)
        ctx.rotor_sense = p.rotation

    def rotor_speed(self, ctx, p) -> None:
        meas = ctx.rotor_speed_meas_rad_s
        ctx.rotor_speed_rad_s = np.where(np.isfinite(meas), meas, p.nominal_speed_rad_s)

    def rotor_setup(self, ctx, p) -> None:
        s = np.asarray(p.rotation, dtype=float)
        om = ctx.rotor_speed_rad_s
        vtip = om * p.radius_m
        r_hub = ctx.wind_origin_m
        v0 = ctx.air_velocity_at(r_hub)
        # rotor frame: vectors y -> s*y, pseudo-vectors (rates) x, z -> s*x, s*z
        v0r = v0 * np.stack([np.ones_like(s), s, np.ones_like(s)], -1)
        w_rel = ctx.wind_w_rad_s - ctx.omega_b_rad_s
        wr = w_rel * np.stack([s, np.ones_like(s), s], -1)
        body_r = ctx.omega_b_rad_s * np.stack([s, np.ones_like(s), s], -1)
        ctx.hub_air_velocity_m_s = v0
        ctx.advance_ratio = np.hypot(v0r[:, 0], v0r[:, 1]) / vtip
        ctx.axial_flow_ratio = v0r[:, 2] / vtip
        ctx._cache["rotor_frame"] = dict(v0=v0r, w=wr, body=body_r, vtip=vtip, om=om)

    def blade_pitch(self, ctx, p) -> None:
        # Rotor-frame swashplate: + lateral command tilts the disk right (roll right),
        # + longitudinal command tilts it forward (nose down), whatever the rotor sense.
        ctx.swash_c = -np.asarray(p.rotation) * ctx.delta_lat_rad
        ctx.swash_s = -ctx.delta_lon_rad
        ctx.theta_0 = ctx.delta_col_rad
        ctx.theta_c = ctx.swash_c
        ctx.theta_s = ctx.swash_s

    def rotor_loading(self, ctx, p) -> None:
        rf = ctx._cache["rotor_frame"]
        v0, wr, vtip, om = rf["v0"], rf["w"], rf["vtip"], rf["om"]
        st = ctx.state(self.name)
        b0, bc, bs, db0, dbc, dbs = (st[:, i] for i in range(6))
        z0, zc, zs, dz0, dzc, dzs = (st[:, i] for i in range(6, 12))
        vt = col(vtip)
        omc = col(om)
        # U_T = a + b rbar, U_P = c + d rbar  (c, d without inflow)
        a = -(col(v0[:, 0]) * SIN + col(v0[:, 1]) * COS) / vt
        zeta_p = _series(dz0 / om, dzc / om + zs, dzs / om - zc)
        b = 1.0 + col(wr[:, 2]) / omc + zeta_p
        beta = _series(b0, bc, bs)
        beta_p = _series(db0 / om, dbc / om + bs, dbs / om - bc)
        er_v0 = -col(v0[:, 0]) * COS + col(v0[:, 1]) * SIN
        c = -col(v0[:, 2]) / vt - beta * er_v0 / vt
        d = -(col(wr[:, 0]) * SIN + col(wr[:, 1]) * COS) / omc - beta_p
        theta = _series(ctx.theta_0, ctx.theta_c, ctx.theta_s)
        t0 = a + 0.5 * b
        t1 = 0.5 * a + b / 3.0
        t2 = a / 3.0 + 0.25 * b
        i0tt = a * a + a * b + b * b / 3.0
        i1tt = 0.5 * a * a + 2.0 / 3.0 * a * b + 0.25 * b * b
        lift = theta * i0tt + c * t0 + d * t1
        mom = theta * i1tt + c * t1 + d * t2
        # Loads in coefficient form [C_T, m_c, m_s] (m: first harmonics of the lift moment,
        # normalised by rho pi R^2 (Omega R)^2 R), affine in the inflow (l0, lc, ls).
        k_t = np.asarray(p.blade_count * p.lock_number * p.flap_inertia_kg_m2
                         / (2.0 * ctx.air_density_kg_m3 * np.pi * p.radius_m**5), dtype=float)
        base = np.column_stack([(lift @ _W3)[:, 0], (mom @ _W3)[:, 1:]]) * col(k_t)
        h_t0 = t0 @ _W3
        h_t1 = t1 @ _W3
        cc = (t2 * (COS * COS)).mean(1)
        cs = (t2 * (COS * SIN)).mean(1)
        ss = (t2 * (SIN * SIN)).mean(1)
        jac = -np.stack(
            [
                np.stack([h_t0[:, 0], h_t1[:, 1], h_t1[:, 2]], -1),
                np.stack([h_t1[:, 1], cc, cs], -1),
                np.stack([h_t1[:, 2], cs, ss], -1),
            ],
            -2,
        ) * np.reshape(k_t, (-1, 1, 1))
        ctx.rotor_load_base = base
        ctx.rotor_load_jac = jac
        ctx._cache["main_rotor"] = dict(
            a=a, b=b, c=c, d=d, theta=theta, beta=beta, zeta_p=zeta_p, t0=t0, t1=t1, t2=t2,
            i0tt=i0tt, i1tt=i1tt, k_t=k_t,
        )
        for name in ("inflow_0", "inflow_c", "inflow_s"):
            if not hasattr(ctx, name):
                setattr(ctx, name, np.zeros(ctx.n))

    def forces(self, ctx, p) -> None:
        cm = ctx._cache["main_rotor"]
        rf = ctx._cache["rotor_frame"]
        om = rf["om"]
        theta, beta = cm["theta"], cm["beta"]
        t0, t1, t2, i0tt, i1tt = cm["t0"], cm["t1"], cm["t2"], cm["i0tt"], cm["i1tt"]
        c = cm["c"] - col(ctx.inflow_0)
        d = cm["d"] - (col(ctx.inflow_c) * COS + col(ctx.inflow_s) * SIN)
        i0tp = c * t0 + d * t1
        i1tp = c * t1 + d * t2
        i0pp = c * c + c * d + d * d / 3.0
        i1pp = 0.5 * c * c + 2.0 / 3.0 * c * d + 0.25 * d * d
        lift = theta * i0tt + i0tp  # int F_L drbar            (5.7, 5.10)
        mom = theta * i1tt + i1tp  # int F_L rbar drbar       (5.8)
        ct = cm["k_t"] * lift.mean(1)
        k_drag = col((p.drag_delta0 + p.drag_delta2 * ct * ct) / p.lift_slope_per_rad)
        drag0 = i0pp + theta * i0tp - k_drag * i0tt  # int F_D drbar   (5.7)
        drag1 = i1pp + theta * i1tp - k_drag * i1tt  # int F_D rbar drbar
        nb = p.blade_count
        gam = p.lock_number
        scale = nb * gam * p.flap_inertia_kg_m2 * om * om / (2.0 * p.radius_m)
        # eq 5.10: rotor-averaged force, n = -z - beta e_r, e_r = (-cos, sin, 0)
        bl = beta * lift
        fx = (bl * COS + drag0 * SIN).mean(1) * scale
        fy = (-bl * SIN + drag0 * COS).mean(1) * scale
        fz = -lift.mean(1) * scale
        # eq 5.8 in multi-blade coordinates
        st = ctx.state(self.name)
        b0, bc, bs, db0, dbc, dbs = (st[:, i] for i in range(6))
        z0, zc, zs, dz0, dzc, dzs = (st[:, i] for i in range(6, 12))
        body = rf["body"]
        hm = mom @ _W3
        r0 = 0.5 * gam * hm[:, 0]
        rc = 2.0 * body[:, 0] / om + gam * hm[:, 1]
        rs = -2.0 * body[:, 1] / om + gam * hm[:, 2]
        om2 = om * om
        lb2 = 1.0 + p.flap_stiffness_nm_rad / (p.flap_inertia_kg_m2 * om2)
        ddb0 = om2 * (r0 - lb2 * b0)
        ddbc = om2 * (rc - (lb2 - 1.0) * bc) - 2.0 * om * dbs
        ddbs = om2 * (rs - (lb2 - 1.0) * bs) + 2.0 * om * dbc
        # eq 5.9 (lead positive) with structural damping, multi-blade coordinates
        e = p.lag_hinge_offset
        lz2 = 1.5 * e / (1.0 - e) + p.lag_stiffness_nm_rad / (p.flap_inertia_kg_m2 * om2)
        lz = np.sqrt(lz2)
        rhs_z = 0.5 * col(gam) * drag1 - col(2.0 * p.lag_damping_ratio * lz) * cm["zeta_p"]
        hz = rhs_z @ _W3
        ddz0 = om2 * (hz[:, 0] - lz2 * z0)
        ddzc = om2 * (2.0 * hz[:, 1] - (lz2 - 1.0) * zc) - 2.0 * om * dzs
        ddzs = om2 * (2.0 * hz[:, 2] - (lz2 - 1.0) * zs) + 2.0 * om * dzc
        ctx.set_rates(
            self.name,
            np.column_stack([db0, dbc, dbs, ddb0, ddbc, ddbs, dz0, dzc, dzs, ddz0, ddzc, ddzs]),
        )
        # eq 5.11: hub spring moments and the torque through the lag spring
        mx = -0.5 * nb * p.flap_stiffness_nm_rad * bs
        my = -0.5 * nb * p.flap_stiffness_nm_rad * bc
        mz = -nb * p.flap_inertia_kg_m2 * om2 * lz2 * z0
        s = np.asarray(p.rotation, dtype=float)
        force = np.column_stack([fx, s * fy, fz])
        moment = np.column_stack([s * mx, my, s * mz]) + cross(ctx.wind_origin_m, force)
        ctx.add_load(self.name, force, moment)
        rho = ctx.air_density_kg_m3
        thrust = -fz
        ctx.thrust_n = thrust
        ctx.thrust_coeff = ct
        ctx.rotor_torque_nm = -scale * p.radius_m * drag1.mean(1)
        ctx.rotor_wake_m_s = ctx.inflow_0 * rf["vtip"] + np.sqrt(
            np.maximum(thrust, 0.0) / (2.0 * rho * p.disk_area_m2)
        )
        ctx.flapping_rad = np.column_stack([b0, bc, bs])
