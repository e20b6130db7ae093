"""Electric drive: LiPo battery, ESC with governor, brushless motor, reduction gear.

Sources: the DC-motor model of a brushless (BLDC) motor with its electrical time constant
neglected (tens of microseconds against the rotor's ~0.1 s): back-EMF constant
K_e = 60 / (2 pi kV) V s/rad = torque constant K_t (SI), phase resistance R_m, no-load
current i_0 (Hanselman, *Brushless Permanent Magnet Motor Design*, 2nd ed., 2006, ch. 1);
a battery as open-circuit voltage behind an internal resistance (Tremblay & Dessaint 2009,
World Electric Vehicle J. 3, the static part); an ESC in governor ("heli") mode holding
the head speed with a PI law on the measured speed, the duty cycle saturating at 0 and 1
(e.g. Castle Creations, "Governor mode" set-up guide: a PI speed loop).

    duty d = clip(d_ff + K_p e + K_i xi, 0, 1),   e = Omega_set - Omega,   dxi/dt = e (held
             while the duty is saturated in the direction of e: anti-windup)
    i = (d V_oc - K_e G Omega) / (R_m + d^2 R_b),  i >= 0 (no regenerative braking)
    torque on the main shaft = G K_t (i - i_0) for i > i_0

d_ff = K_e G Omega_set / V_oc is the no-load duty. The rotor speed therefore moves with
load: the governor's integral restores it over ~1 s after a collective step.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from hil_sim.world.rotorcraft.airframe import Airframe

DRV_KE, DRV_RM, DRV_I0, DRV_GEAR, DRV_VOC, DRV_RB, DRV_SHAFT_INERTIA, DRV_SET, DRV_KP, \
    DRV_KI, DRV_DFF = range(11)
N_DRV_PARAMS = 11


def pack(airframe: Airframe) -> np.ndarray:
    d = airframe.part("drive")
    p = np.zeros(N_DRV_PARAMS)
    p[DRV_KE] = 60.0 / (2.0 * math.pi * d["motor_kv_rpm_per_v"])
    p[DRV_RM] = d["motor_resistance_ohm"]
    p[DRV_I0] = d["no_load_current_a"]
    p[DRV_GEAR] = d["gear_ratio"]
    p[DRV_VOC] = d["battery_cells"] * d["cell_voltage_v"]
    p[DRV_RB] = d["battery_resistance_ohm"]
    p[DRV_SHAFT_INERTIA] = d["shaft_inertia_kg_m2"]
    p[DRV_SET] = d["governor_speed_rpm"] * 2.0 * math.pi / 60.0
    p[DRV_KP] = d["governor_kp_per_rad_s"]
    p[DRV_KI] = d["governor_ki_per_rad"]
    p[DRV_DFF] = p[DRV_KE] * p[DRV_GEAR] * p[DRV_SET] / p[DRV_VOC]
    return p


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def drive(omega, integral, p):
    """(shaft torque N m, motor current A, duty, d integral / dt) at rotor speed omega."""
    e = p[DRV_SET] - omega
    raw = p[DRV_DFF] + p[DRV_KP] * e + p[DRV_KI] * integral
    duty = min(max(raw, 0.0), 1.0)
    dxi = e
    if (raw >= 1.0 and e > 0.0) or (raw <= 0.0 and e < 0.0):
        dxi = 0.0
    current = (duty * p[DRV_VOC] - p[DRV_KE] * p[DRV_GEAR] * omega) / (
        p[DRV_RM] + duty * duty * p[DRV_RB])
    current = max(current, 0.0)
    torque = p[DRV_GEAR] * p[DRV_KE] * max(current - p[DRV_I0], 0.0)
    return torque, current, duty, dxi
