"""Fuselage and empennage aerodynamics: coefficient tables in angle of attack and sideslip
for the fuselage (with its tail boom), lifting-surface elements for the stabiliser and fin.

Fuselage tables. A small helicopter's pod is a bluff, slender body; its six force and
moment coefficients over the full sphere of flow directions are tabulated once per
airframe from the classical slender-body model and then looked up bilinearly like
wind-tunnel data (a measured table can replace them one for one):

- axial force: frontal drag, -C_D0 S_front cos(a_t) |cos(a_t)| (Hoerner, *Fluid-Dynamic
  Drag*, 1965, ch. 3 and 13);
- crossflow force: the viscous crossflow of Allen & Perkins (NACA TR 1048, 1951), each
  part (pod, boom) a cylinder-like body, -C_dc S_c |c| c with c the crossflow part of the
  unit flow direction and S_c its projected area seen along c (plan area for flow from
  below, side area from the side), acting at that area's centroid;
- Munk's moment (Munk 1924, NACA TR 184): the potential-flow pitching/yawing moment of an
  elongated body, 2 (k2 - k1) Vol (x . v)(v x x) per unit dynamic pressure, turning the nose
  away from the flow (Lamb's k2 - k1 for a prolate spheroid).

With the unit flow v = (cos a cos b, sin b, sin a cos b) (the body's velocity relative to
the air, a = atan2(v_z, v_x), b = asin(v_y)) the table holds
C = [C_X, C_Y, C_Z, C_l, C_m, C_n] about `reference_point_m`: F = q S_ref C[:3],
M = q S_ref l_ref C[3:], S_ref = width x height, l_ref = length.

Empennage: each surface is one lifting element (blade_element.section_load with the NACA
0012 section) whose lift slope is scaled to the finite wing by Helmbold's equation,
a = 2 pi A / (2 + sqrt(A^2 + 4)) (Helmbold 1942; Anderson, *Fundamentals of
Aerodynamics*, §5.3), plus the induced drag C_L^2 / (pi e A), e = 0.9.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from hil_sim.world.rotorcraft.airfoil import section_coefficients
from hil_sim.world.rotorcraft.airframe import Airframe
from hil_sim.world.rotorcraft.blade_element import section_load

ALPHA_STEP_DEG = 5.0
BETA_STEP_DEG = 5.0
FUS_REF_X, FUS_REF_Y, FUS_REF_Z, FUS_S_REF, FUS_L_REF = range(5)
N_FUS_PARAMS = 5
# empennage rows: [x, y, z, chord, span, incidence, lift factor, 1 / (pi e A), e_u x, e_u y, e_u z]
N_EMP_COLUMNS = 11
OSWALD_E = 0.9


def slender_body_coefficients(airframe: Airframe, alpha_rad: np.ndarray,
                              beta_rad: np.ndarray) -> np.ndarray:
    """(..., 6) coefficients at the flow angles (module docstring)."""
    f = airframe.part("fuselage")
    length, width, height = f["length_m"], f["width_m"], f["height_m"]
    s_ref = width * height
    ref_x = f["reference_point_m"][0]
    a = np.asarray(alpha_rad, float)
    b = np.asarray(beta_rad, float)
    v = np.stack([np.cos(a) * np.cos(b), np.sin(b), np.sin(a) * np.cos(b)], axis=-1)
    force = np.zeros(v.shape)
    moment = np.zeros(v.shape)
    # axial (frontal) drag
    force[..., 0] = -f["frontal_drag_coefficient"] * s_ref * v[..., 0] * np.abs(v[..., 0])
    # crossflow on the pod (centroid at the reference point) and the boom (behind it)
    boom_x = -0.5 * length + ref_x - 0.5 * f["boom_length_m"]
    parts = ((length * width, length * height, 0.0),
             (f["boom_length_m"] * f["boom_diameter_m"], f["boom_length_m"] *
              f["boom_diameter_m"], boom_x - ref_x))
    cy, cz = v[..., 1], v[..., 2]
    c2 = cy * cy + cz * cz
    c = np.sqrt(c2)
    with np.errstate(invalid="ignore", divide="ignore"):
        uy = np.where(c > 1e-12, cy / np.where(c > 1e-12, c, 1.0), 0.0)
        uz = np.where(c > 1e-12, cz / np.where(c > 1e-12, c, 1.0), 0.0)
    for plan, side, arm in parts:
        area = plan * uz * uz + side * uy * uy
        fy = -f["crossflow_drag_coefficient"] * area * c * cy
        fz = -f["crossflow_drag_coefficient"] * area * c * cz
        force[..., 1] += fy
        force[..., 2] += fz
        # moment of a force at (arm, 0, 0): r x F = (0, -arm fz, arm fy)
        moment[..., 1] += -arm * fz
        moment[..., 2] += arm * fy
    # Munk's moment 2 (k2 - k1) Vol (x . v) (v x x), v x x = (0, v_z, -v_y)
    vol = math.pi / 6.0 * length * width * height
    k = 2.0 * f["added_mass_factor"] * vol
    moment[..., 1] += k * v[..., 0] * v[..., 2]
    moment[..., 2] += -k * v[..., 0] * v[..., 1]
    out = np.concatenate([force / s_ref, moment / (s_ref * length)], axis=-1)
    return out


def pack(airframe: Airframe) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(fuselage parameters, coefficient table (n_alpha, n_beta, 6), empennage rows)."""
    f = airframe.part("fuselage")
    alpha = np.radians(np.arange(-180.0, 180.0 + 0.5 * ALPHA_STEP_DEG, ALPHA_STEP_DEG))
    beta = np.radians(np.arange(-90.0, 90.0 + 0.5 * BETA_STEP_DEG, BETA_STEP_DEG))
    aa, bb = np.meshgrid(alpha, beta, indexing="ij")
    table = np.ascontiguousarray(slender_body_coefficients(airframe, aa, bb))
    p = np.zeros(N_FUS_PARAMS)
    p[FUS_REF_X:FUS_REF_Z + 1] = f["reference_point_m"]
    p[FUS_S_REF] = f["width_m"] * f["height_m"]
    p[FUS_L_REF] = f["length_m"]
    rows = []
    for name, normal, incidence in (
            ("horizontal_stabilizer", (0.0, 0.0, -1.0), airframe[
                "horizontal_stabilizer.incidence_deg"]),
            ("vertical_fin", (0.0, -1.0, 0.0), 0.0)):
        s = airframe.part(name)
        if s["area_m2"] <= 0:
            continue
        aspect = s["span_m"] ** 2 / s["area_m2"]
        slope = 2.0 * math.pi * aspect / (2.0 + math.sqrt(aspect**2 + 4.0))
        rows.append([*s["position_m"], s["area_m2"] / s["span_m"], s["span_m"],
                     math.radians(incidence), slope / (2.0 * math.pi),
                     1.0 / (math.pi * OSWALD_E * aspect), *normal])
    emp = np.array(rows, dtype=float).reshape(-1, N_EMP_COLUMNS)
    return p, table, emp


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def fuselage_coefficients(vx, vy, vz, table):
    """Bilinear lookup of the six coefficients at the body's unit flow direction."""
    alpha = math.atan2(vz, vx)
    beta = math.asin(max(-1.0, min(1.0, vy)))
    xa = (alpha + math.pi) / math.radians(ALPHA_STEP_DEG)
    xb = (beta + 0.5 * math.pi) / math.radians(BETA_STEP_DEG)
    ia = min(max(int(xa), 0), table.shape[0] - 2)
    ib = min(max(int(xb), 0), table.shape[1] - 2)
    fa = min(max(xa - ia, 0.0), 1.0)
    fb = min(max(xb - ib, 0.0), 1.0)
    out = np.empty(6)
    for j in range(6):
        out[j] = ((1 - fa) * (1 - fb) * table[ia, ib, j] + fa * (1 - fb) * table[ia + 1, ib, j]
                  + (1 - fa) * fb * table[ia, ib + 1, j] + fa * fb * table[ia + 1, ib + 1, j])
    return out


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def surface_load(ux, uy, uz, row, rho, table):
    """Force (Fx, Fy, Fz) on one empennage surface (module docstring) from the air
    velocity U relative to it (body axes); the surface moves along +x."""
    nx, ny, nz = row[8], row[9], row[10]
    fx, fy, fz, alpha, ut, up = section_load(ux, uy, uz, 1.0, 0.0, 0.0, nx, ny, nz, row[5],
                                             row[3], row[4], rho, row[6], table)
    v2 = ut * ut + up * up
    if v2 < 1e-12:
        return fx, fy, fz
    cl, _ = section_coefficients(alpha, table)
    cl *= row[6]
    drag = 0.5 * rho * v2 * row[3] * row[4] * cl * cl * row[7] / math.sqrt(v2)
    # induced drag along the relative wind (-U_T e_t + U_P e_u) / V, e_t = +x
    return fx - drag * ut + drag * up * nx, fy + drag * up * ny, fz + drag * up * nz
