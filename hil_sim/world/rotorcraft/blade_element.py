"""Blade-element section loads, Prandtl's tip loss and teetering-blade kinematics.

Every lifting surface of the truth (main-rotor blades, flybar paddles, tail-rotor blades,
stabiliser, fin) is a set of elements, each loaded by the one strip-theory formula of
`section_load` (Padfield, *Helicopter Flight Dynamics*, 2nd ed., §3.2.1; Johnson,
*Helicopter Theory*, 1980, ch. 5), with the section coefficients of `airfoil.py` over
the full circle (stall, reverse flow):

    U      air velocity relative to the element (air minus element), body axes
    U_T = -U . e_t   in-plane component toward the trailing edge (e_t: direction of motion)
    U_P =  U . e_u   normal component from below (e_u: the section's lift normal)
    alpha = theta + atan2(U_P, U_T),   q = rho (U_T^2 + U_P^2) / 2
    dF = q c dr [ F cl(alpha) (U_P e_t + U_T e_u) / V  +  cd(alpha) (-U_T e_t + U_P e_u) / V ]

the lift perpendicular and the drag parallel to the section's relative wind (radial flow
neglected, Johnson §5.2). `F` scales the lift: Prandtl's tip-loss factor on rotor blades,
the finite-wing lift-slope ratio on the empennage.

Prandtl's tip loss (Prandtl in Betz 1919; in rotor form Johnson §4.1.2, eq. 4.8):

    F = (2/pi) arccos(exp(-f)),   f = (N/2) (1 - r/R) / ((r/R) phi)

with phi the element's inflow angle; F -> 0 at the tip, ~1 inboard.

Teetering-blade kinematics (a rigid blade through the hub, flapping as one piece): blade
at azimuth psi (from the tail, increasing in the rotation sense s = +1 clockwise seen from
above = rotation about body +z) and flap angle beta (up positive). Radial and tangential
unit vectors in the shaft plane,

    e_r(psi) = (-cos psi, -s sin psi, 0),   e_t(psi) = d e_r / d psi = (sin psi, -s cos psi, 0),

and the point at radius r:  p = r (cos beta e_r - sin beta z).  The derivatives of p that the
multibody equations need (dynamics.py) follow in closed form.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from hil_sim.world.rotorcraft.airfoil import section_coefficients


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def section_load(ux, uy, uz, tx, ty, tz, nx, ny, nz, theta, chord, dr, rho, lift_factor,
                 table):
    """(Fx, Fy, Fz, alpha, U_T, U_P) of one element (module docstring): air-relative
    velocity U, motion direction e_t, lift normal e_u, pitch theta, chord, span dr."""
    ut = -(ux * tx + uy * ty + uz * tz)
    up = ux * nx + uy * ny + uz * nz
    v2 = ut * ut + up * up
    if v2 < 1e-12:
        return 0.0, 0.0, 0.0, theta, ut, up
    v = math.sqrt(v2)
    alpha = theta + math.atan2(up, ut)
    cl, cd = section_coefficients(alpha, table)
    k = 0.5 * rho * v2 * chord * dr / v
    lift = k * lift_factor * cl
    drag = k * cd
    # lift along (U_P e_t + U_T e_u) / V, drag along (-U_T e_t + U_P e_u) / V
    a = lift * up - drag * ut
    b = lift * ut + drag * up
    return a * tx + b * nx, a * ty + b * ny, a * tz + b * nz, alpha, ut, up


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def prandtl_tip_loss(n_blades, r_over_radius, inflow_angle):
    """Prandtl's tip-loss factor F in (0, 1] (module docstring)."""
    phi = max(abs(inflow_angle), 1e-3)
    f = 0.5 * n_blades * (1.0 - r_over_radius) / (r_over_radius * phi)
    if f > 30.0:
        return 1.0
    return (2.0 / math.pi) * math.acos(math.exp(-f))


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def teeter_point(cp, sp, cb, sb, s, r):
    """Position and first derivatives of the point at radius r of a teetering blade at
    azimuth psi, flap beta (given as cos psi, sin psi, cos beta, sin beta; rotation sense
    s): p, dp/dpsi, dp/dbeta (each (x, y, z)), and the unit vectors e_t (motion) and e_u
    (blade normal, up) of the flapped blade."""
    erx, ery = -cp, -s * sp
    etx, ety = sp, -s * cp
    p = (r * cb * erx, r * cb * ery, -r * sb)
    p_psi = (r * cb * etx, r * cb * ety, 0.0)
    p_beta = (-r * sb * erx, -r * sb * ery, -r * cb)
    e_u = (-sb * erx, -sb * ery, -cb)
    return p, p_psi, p_beta, (etx, ety, 0.0), e_u


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def teeter_velocity_terms(cp, sp, cb, sb, s, r, omega, beta_dot):
    """The velocity-dependent part of the point's acceleration relative to the shaft,
    p'' at zero generalised accelerations:

        Omega^2 p_psipsi + 2 Omega beta' p_psibeta + beta'^2 p_betabeta
        p_psipsi = -r cos beta e_r,  p_psibeta = -r sin beta e_t,
        p_betabeta = -r (cos beta e_r - sin beta z) (= -p)."""
    erx, ery = -cp, -s * sp
    etx, ety = sp, -s * cp
    w2 = omega * omega
    wb = 2.0 * omega * beta_dot
    b2 = beta_dot * beta_dot
    ax = -w2 * r * cb * erx - wb * r * sb * etx - b2 * r * cb * erx
    ay = -w2 * r * cb * ery - wb * r * sb * ety - b2 * r * cb * ery
    az = b2 * r * sb
    return ax, ay, az


def element_stations(r_inner: float, r_outer: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(centres, widths) of n equal-annulus-area elements between two radii: equal areas
    put more elements outboard, where a rotor's load is (Johnson §5.2 practice)."""
    edges = np.sqrt(np.linspace(r_inner**2, r_outer**2, n + 1))
    return 0.5 * (edges[1:] + edges[:-1]), np.diff(edges)
