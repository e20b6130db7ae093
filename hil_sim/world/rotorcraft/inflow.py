"""Induced inflow: Pitt-Peters dynamic inflow on the main rotor, a one-state dynamic
momentum inflow on the tail rotor, the main rotor's skewed wake on everything behind
and below it, and ground/deck effect by images of the rotor's source flow.

Main rotor (Pitt & Peters 1981, "Theoretical prediction of dynamic-inflow derivatives",
Vertica 5; Peters & HaQuang 1988, "Dynamic inflow for practical applications", J. AHS
33(4)). Induced velocity (down the shaft) over the disc, linear in the hub-plane
coordinates x, y of an element relative to the hub:

    nu(x, y) = nu_0 + nu_x x / R + nu_y y / R

Nondimensionally (lambda = nu / (Omega R)) and in the wind-aligned axes of the disc
(d: downstream in-plane direction of the air relative to the rotor, l perpendicular):

    M dlambda/dtau = F - V Lt^-1 lambda,   tau = Omega t,
    lambda = (lambda_0, lambda_l, lambda_d),   F = (C_T, C_l, C_d),
    M = diag(8 / (3 pi), 16 / (45 pi), 16 / (45 pi)),   V = diag(V_T, V_m, V_m),
    Lt = [[1/2, 0, -k], [0, 4 / (1 + cos chi), 0], [k, 0, 4 cos chi / (1 + cos chi)]],
    k = (15 pi / 64) tan(chi / 2),   chi = atan(mu / lambda_tot) (wake skew),
    V_T = sqrt(mu^2 + lambda_tot^2),   V_m = (mu^2 + lambda_tot (lambda_tot + lambda_0)) / V_T

with lambda_tot = mu_z + lambda_0 the total flow down through the disc, C_T the thrust
coefficient and C_l, C_d the aerodynamic moment coefficients whose positive sense puts
more lift on the +l / downstream side (more lift on a side draws more inflow there:
in hover lambda_d = 2 C_d / V_m, the actuator-disc momentum balance). This is Peters &
HaQuang's matrix written for these forcing signs (their {C_T, -C_L, -C_M}).

Radial distribution: the Pitt-Peters states are the disc's mean and first harmonics; along
the radius the mean is distributed as an untwisted blade's blade-element-momentum inflow,
lambda(r) ~ sqrt(r) (Johnson 1980 §4.1: lambda = (sigma a / 16)(sqrt(1 + 32 theta r /
(sigma a)) - 1) ~ sqrt(sigma a theta r / 8)), normalised to keep the area mean:

    nu(r) = nu_0 (5/4) sqrt(r / R)

so the blade roots and the flybar paddles near the hub fly in the weaker inflow there
(a uniform distribution would put the whole mean on them).

Tail rotor: uniform inflow with the first Pitt-Peters row, (8 / (3 pi)) dlambda/dtau =
C_T - 2 V_T lambda.

Skewed wake (Heyson & Katzoff 1957, NACA TR 1319; the semi-infinite actuator-disc vortex
cylinder): points below the disc inside the wake cylinder skewed aft by chi see an extra
downwash along the shaft growing from nu_0 at the disc to 2 nu_0 far below,

    w(z) = nu_0 (1 + z' / sqrt(z'^2 + R^2)),   z' = z / cos chi,

with a smooth edge over 10 % of R. It acts on the fuselage, stabiliser, fin and tail rotor.

Ground and deck effect (Cheeseman & Bennett 1955, "The effect of the ground on a
helicopter rotor in forward flight", ARC R&M 3021): the rotor's inflow is a source of
strength A nu / (4 pi); the surface below is the mirror plane of an image source, whose
upwash at the disc cuts the inflow (over a flat ground at height z: by (R / 4z)^2). Here
the disc is seven sub-sources, each mirrored in the surface directly below it (deck,
hangar roof, sea or hall floor, whatever is under that part of the disc), so a rotor over
the deck edge feels the deck under one side only. `ground_upwash` gives the upwash per
unit nu_0 at points of the disc.
"""

from __future__ import annotations

import math

import numba
import numpy as np

M0_PITT_PETERS = 8.0 / (3.0 * math.pi)
M1_PITT_PETERS = 16.0 / (45.0 * math.pi)
SKEW_COUPLING = 15.0 * math.pi / 64.0
MAX_SKEW_RAD = math.radians(85.0)
MAX_GROUND_UPWASH = 0.6  # Cheeseman & Bennett hold for z / R >= 0.5: (1/2)^2 ... capped


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def pitt_peters_rates(nu0, nux, nuy, c_t, c_x, c_y, vx, vy, vz, omega, radius):
    """d(nu_0, nu_x, nu_y)/dt (m/s^2) of the main rotor (module docstring).

    c_x, c_y: moment coefficients with more lift at +x (forward) / +y (right); vx, vy, vz:
    air velocity relative to the hub in hub axes (vz > 0 flowing down through the disc)."""
    vtip = max(omega * radius, 1.0)
    l0 = nu0 / vtip
    mu = math.sqrt(vx * vx + vy * vy) / vtip
    lam_tot = vz / vtip + l0
    if mu > 1e-9:
        dx = vx / (mu * vtip)
        dy = vy / (mu * vtip)
    else:
        dx, dy = -1.0, 0.0
    lx, ly = -dy, dx
    chi = math.atan2(mu, lam_tot)
    if chi > MAX_SKEW_RAD:
        chi = MAX_SKEW_RAD
    if chi < 0.0:
        chi = 0.0
    cchi = math.cos(chi)
    k = SKEW_COUPLING * math.tan(0.5 * chi)
    vt = max(math.sqrt(mu * mu + lam_tot * lam_tot), 1e-3)
    vm = max((mu * mu + lam_tot * (lam_tot + l0)) / vt, 1e-3)
    # wind-axis components
    ld = (nux * dx + nuy * dy) / vtip
    ll = (nux * lx + nuy * ly) / vtip
    cd = c_x * dx + c_y * dy
    cl = c_x * lx + c_y * ly
    # Lt^-1: the (0, d) block [[1/2, -k], [k, c4]] and the lateral entry c2
    c2 = 4.0 / (1.0 + cchi)
    c4 = 4.0 * cchi / (1.0 + cchi)
    det = 0.5 * c4 + k * k
    inv00, inv01 = c4 / det, k / det
    inv10, inv11 = -k / det, 0.5 / det
    r0 = c_t - vt * (inv00 * l0 + inv01 * ld)
    rd = cd - vm * (inv10 * l0 + inv11 * ld)
    rl = cl - vm * ll / c2
    scale = omega * vtip
    d0 = scale * r0 / M0_PITT_PETERS
    dd = scale * rd / M1_PITT_PETERS
    dl = scale * rl / M1_PITT_PETERS
    return d0, dd * dx + dl * lx, dd * dy + dl * ly


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def radial_shape(r_over_radius):
    """The mean inflow's radial distribution (module docstring), area mean 1."""
    return 1.25 * math.sqrt(max(r_over_radius, 0.0))


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def momentum_inflow_rate(nu, c_t, v_inplane, v_through, omega, radius):
    """d nu / dt of a uniform one-state inflow (tail rotor): v_through > 0 along the
    induced flow."""
    vtip = max(omega * radius, 1.0)
    lam = nu / vtip
    mu = v_inplane / vtip
    lt = v_through / vtip + lam
    vt = max(math.sqrt(mu * mu + lt * lt), 1e-3)
    return omega * vtip * (c_t - 2.0 * vt * lam) / M0_PITT_PETERS


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def wake_skew(vx, vy, vz, nu0):
    """(chi, d_x, d_y): wake skew angle and downstream direction from the hub-relative air
    velocity (vz > 0 flowing down) and the mean induced velocity."""
    vh = math.sqrt(vx * vx + vy * vy)
    chi = math.atan2(vh, max(vz + nu0, 1e-6))
    if chi > MAX_SKEW_RAD:
        chi = MAX_SKEW_RAD
    if vh > 1e-9:
        return chi, vx / vh, vy / vh
    return chi, -1.0, 0.0


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def wake_velocity(dx, dy, dz, radius, nu0, chi, sx, sy):
    """Extra downwash (m/s, along the shaft, down) at a point dx, dy, dz from the hub
    (dz > 0 below the disc) from the skewed wake (module docstring)."""
    if dz <= 0.0 or nu0 <= 0.0:
        return 0.0
    t = math.tan(chi)
    qx = dx - dz * t * sx
    qy = dy - dz * t * sy
    rho = math.sqrt(qx * qx + qy * qy)
    edge = (1.05 * radius - rho) / (0.1 * radius)
    if edge <= 0.0:
        return 0.0
    w = 1.0 if edge >= 1.0 else edge * edge * (3.0 - 2.0 * edge)
    zp = dz / max(math.cos(chi), 0.05)
    return w * nu0 * (1.0 + zp / math.sqrt(zp * zp + radius * radius))


def disc_sources(radius_m: float) -> tuple[np.ndarray, float]:
    """(7, 2) hub-plane positions of the disc's sub-sources (centre + a ring of six at
    0.65 R) and the area each stands for (pi R^2 / 7)."""
    ang = np.arange(6) * np.pi / 3.0
    ring = 0.65 * radius_m * np.column_stack([np.cos(ang), np.sin(ang)])
    return np.vstack([[0.0, 0.0], ring]), math.pi * radius_m**2 / 7.0


def ground_upwash(points_ned: np.ndarray, sources_ned: np.ndarray,
                  source_heights_m: np.ndarray, source_area_m2: float) -> np.ndarray:
    """(P,) upwash per unit nu_0 at points (P, 3) NED from the images of sub-sources
    (K, 3) NED mirrored in the surface `source_heights_m` (K,) below each."""
    img = sources_ned.copy()
    img[:, 2] += 2.0 * np.maximum(source_heights_m, 1e-3)
    d = img[None, :, :] - points_ned[:, None, :]  # (P, K, 3) point -> image
    dist = np.sqrt(np.sum(d * d, axis=-1))
    up = source_area_m2 / (4.0 * np.pi) * d[:, :, 2] / dist**3  # vertical part, up
    return np.minimum(np.sum(up, axis=1), MAX_GROUND_UPWASH)
