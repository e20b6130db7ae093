"""Tail rotor: two rigid blades geared to the main shaft, blade-element loads, its own
inflow, in the main rotor's wake.

Sources: Padfield 2007 §3.2.4 (tail rotor), here as blade elements rather than the
closed form; inflow in inflow.py (uniform, one-state dynamic momentum, Pitt & Peters
1981), the main rotor's wake on it from the skewed-wake geometry (inflow.wake_velocity).

Geometry: hub at `hub_position_m`, shaft along body y, turning at gear_ratio x Omega. Blade
azimuth phi from the top; with `rotation = "top_blade_aft"` (s_t = +1) the top blade
moves aft. The point at radius r: p = r e_r(phi),

    e_r(phi) = (-s_t sin phi, 0, -cos phi),   e_t(phi) = d e_r / d phi = (-s_t cos phi, 0, sin phi),

and the lift normal of a positive pitch is -y: thrust to the left, which yaws the nose to
the right (`delta_ped` positive) against a clockwise main rotor's torque. The blades'
mass is not integrated point by point: their polar inertia is the tail rotor's.
Element table rows: [sign (+1 blade 0, -1 blade 1), r, dr].
"""

from __future__ import annotations

import math

import numba
import numpy as np

from hil_sim.world.rotorcraft.airframe import Airframe
from hil_sim.world.rotorcraft.blade_element import element_stations

TR_RADIUS, TR_SENSE, TR_GEAR, TR_HUB_X, TR_HUB_Y, TR_HUB_Z, TR_INERTIA, TR_CHORD, TR_AREA, \
    TR_N_BLADES = range(10)
N_TR_PARAMS = 10


def pack(airframe: Airframe) -> tuple[np.ndarray, np.ndarray]:
    t = airframe.part("tail_rotor")
    r, dr = element_stations(t["root_cutout_m"], t["radius_m"], t["elements"])
    rows = [np.column_stack([np.full(r.size, sign), r, dr]) for sign in (1.0, -1.0)]
    p = np.zeros(N_TR_PARAMS)
    p[TR_RADIUS] = t["radius_m"]
    p[TR_SENSE] = 1.0 if t["rotation"] == "top_blade_aft" else -1.0
    p[TR_GEAR] = t["gear_ratio"]
    p[TR_HUB_X:TR_HUB_Z + 1] = t["hub_position_m"]
    p[TR_INERTIA] = t["polar_inertia_kg_m2"]
    p[TR_CHORD] = t["chord_m"]
    p[TR_AREA] = math.pi * t["radius_m"] ** 2
    p[TR_N_BLADES] = 2.0
    return p, np.vstack(rows)


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def tail_point(c, s, s_t, r):
    """(p relative to the tail hub, dp/dphi, e_t) of the point at radius r, azimuth phi
    (given as c = cos phi, s = sin phi)."""
    p = (-s_t * s * r, 0.0, -c * r)
    e_t = (-s_t * c, 0.0, s)
    return p, (r * e_t[0], 0.0, r * e_t[2]), e_t
