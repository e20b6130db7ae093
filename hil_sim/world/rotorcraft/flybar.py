"""Bell-Hiller flybar: a free teetering rotor of its own, with aerodynamic paddles.

Sources: Mettler, Tischler & Kanade 2002 (J. AHS 47(1): the flybar as a "stabilizer
bar", a lightly damped gyroscopic rotor whose tip-path plane lags the shaft with time
constant tau_f = 16 / (gamma_f Omega) and feeds the main-rotor cyclic through the Hiller
mixer); Gavrilets, Mettler & Feron 2001 (X-Cell flybar Lock number ~0.8).

Geometry: the bar turns with the shaft, paddle 0 leading main blade 0 by 90 deg
(azimuth psi + pi/2), teetering freely (no spring, bearing friction only) on the shaft
through the same kinematics as a main blade (blade_element.teeter_point). The rod is two
point masses at r = tip / sqrt(3) (its teeter inertia exactly); each paddle is
`elements` blade elements (aerodynamic, carrying the paddle mass). The paddle pitch comes
from the swashplate (main_rotor.swash_feathering with the paddle gain); the paddles fly
in the main rotor's induced flow at their radius and sample the wind field where they are.

Element table rows: [sign, r, dr, mass, chord, aero (1/0)].
"""

from __future__ import annotations

import math

import numpy as np

from hil_sim.world.rotorcraft.airframe import Airframe
from hil_sim.world.rotorcraft.blade_element import element_stations

FB_DAMPING, FB_PHASE_LEAD = range(2)
N_FB_PARAMS = 2


def pack(airframe: Airframe) -> tuple[np.ndarray, np.ndarray]:
    """(parameter vector, element table (2 (n + 1), 6))."""
    f = airframe.part("flybar")
    r, dr = element_stations(f["paddle_inner_m"], f["tip_radius_m"], f["elements"])
    mass = np.full(r.size, f["paddle_mass_kg"] / r.size)
    rows = []
    for sign in (1.0, -1.0):
        rows.append(np.column_stack([np.full(r.size, sign), r, dr, mass,
                                     np.full(r.size, f["paddle_chord_m"]), np.ones(r.size)]))
        rows.append(np.array([[sign, f["tip_radius_m"] / math.sqrt(3.0), 0.0,
                               0.5 * f["rod_mass_kg"], 0.0, 0.0]]))
    params = np.zeros(N_FB_PARAMS)
    params[FB_DAMPING] = f["damping_nms_rad"]
    params[FB_PHASE_LEAD] = 0.5 * math.pi
    return params, np.vstack(rows)
