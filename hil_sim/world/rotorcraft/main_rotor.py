"""Main rotor: two rigid blades on a teetering hub with an elastomer spring and damper,
blade-element aerodynamics, and the Bell-Hiller pitch law.

Sources: blade-element rotor, Padfield, *Helicopter Flight Dynamics* (2nd ed., 2007)
§3.2.1 and Johnson, *Helicopter Theory* (1980) ch. 5; teetering rotor, Johnson §5.20 (a
two-bladed rotor flapping as one piece about the teeter hinge, with hub spring K_beta);
Bell-Hiller mixing on small helicopters, Mettler, Tischler & Kanade 2002 ("System
identification modeling of a small-scale unmanned rotorcraft", J. AHS 47(1)) and
Gavrilets, Mettler & Feron 2001 (X-Cell 60 model, AIAA 2001-4373).

Blades: blade 0 at azimuth psi with teeter angle beta, blade 1 at psi + pi with -beta
(blade_element.teeter_point). Each blade has `elements` equal-annulus elements from the
root cut-out to the tip; its mass is spread uniformly from the grip to the tip (the part
inboard of the first element lumped into it), blade 0 carries the stated imbalance mass.
The element table rows are

    [blade sign (+1 / -1), r (m), dr (m), mass (kg), pitch offset (rad), aero (1/0)]

Pitch law (Bell-Hiller). The swashplate (servos.py) gives collective h0 and the cyclic
tilts (sigma_lat, sigma_lon); at blade azimuth psi its cyclic feathering is

    theta_sw(psi) = s sigma_lat cos(psi + phase) - sigma_lon sin(psi + phase)

(maximum pitch 90 deg ahead of the wanted maximum flap, so + lateral tilts the disc right
and + longitudinal tilts it forward; `phase` is the rigging's phase error). Blade 0's pitch

    theta_0 = h0 + bell theta_sw(psi) + hiller beta_f + twist (r/R - 0.75)

with beta_f the flybar's teeter angle (flybar paddle 0 leads blade 0 by 90 deg, so the
flybar's tilt reaches the blades in phase with the direct swashplate path); blade 1 gets
the opposite cyclic parts and the track error. The flybar paddles see
theta_p = paddle_gain theta_sw(psi_f) with paddle_gain = (1 - bell) / hiller, so that in a
steady hover the blades' cyclic equals the swashplate's (the free flybar's disc settles
where its paddles carry no cyclic pitch).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from hil_sim.world.rotorcraft.airframe import Airframe
from hil_sim.world.rotorcraft.blade_element import element_stations

# scalar parameter vector
MR_RADIUS, MR_SENSE, MR_HUB_X, MR_HUB_Y, MR_HUB_Z, MR_SPRING, MR_DAMPING, MR_BELL, \
    MR_HILLER, MR_PADDLE_GAIN, MR_PHASE, MR_CHORD, MR_N_BLADES, MR_AREA = range(14)
N_MR_PARAMS = 14


def pack(airframe: Airframe) -> tuple[np.ndarray, np.ndarray]:
    """(parameter vector (N_MR_PARAMS,), element table (2 n, 6))."""
    m = airframe.part("main_rotor")
    radius = m["radius_m"]
    s = 1.0 if m["rotation"] == "clockwise" else -1.0
    r, dr = element_stations(m["root_cutout_m"], radius, m["elements"])
    mass_per_m = m["blade_mass_kg"] / (radius - m["blade_root_m"])
    masses = mass_per_m * dr
    masses[0] += mass_per_m * max(0.0, m["root_cutout_m"] - m["blade_root_m"])
    twist = math.radians(m["twist_deg"]) * (r / radius - 0.75)
    rows = []
    for sign in (1.0, -1.0):
        mass = masses.copy()
        if sign > 0 and m["imbalance_mass_kg"] > 0:
            mass[int(np.argmin(np.abs(r - m["imbalance_radius_m"])))] += m["imbalance_mass_kg"]
        offset = twist + (math.radians(m["track_error_deg"]) if sign < 0 else 0.0)
        rows.append(np.column_stack([np.full(r.size, sign), r, dr, mass, offset,
                                     np.ones(r.size)]))
    hub = m["hub_position_m"]
    params = np.zeros(N_MR_PARAMS)
    params[MR_RADIUS] = radius
    params[MR_SENSE] = s
    params[MR_HUB_X:MR_HUB_Z + 1] = hub
    params[MR_SPRING] = m["hub_spring_nm_rad"]
    params[MR_DAMPING] = m["hub_damping_nms_rad"]
    params[MR_BELL] = m["bell_ratio"]
    params[MR_HILLER] = m["hiller_ratio"]
    params[MR_PADDLE_GAIN] = (1.0 - m["bell_ratio"]) / m["hiller_ratio"]
    params[MR_PHASE] = math.radians(airframe["rigging.phase_error_deg"])
    params[MR_CHORD] = m["chord_m"]
    params[MR_N_BLADES] = 2.0
    params[MR_AREA] = math.pi * radius**2
    return params, np.vstack(rows)


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def swash_feathering(psi, s, phase, sigma_lat, sigma_lon):
    """Cyclic feathering the swashplate gives a blade (or paddle) at azimuth psi."""
    a = psi + phase
    return s * sigma_lat * math.cos(a) - sigma_lon * math.sin(a)


def blade_flap_inertia(elements: np.ndarray) -> float:
    """Teeter inertia of the two blades about the hinge, sum m r^2 (kg m^2)."""
    return float(np.sum(elements[:, 3] * elements[:, 1] ** 2))
