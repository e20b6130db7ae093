"""Servos, swashplate mixing and the rigging between the radio's commands and blade pitch.

Sources: hobby digital servos as a second-order position loop with a rate limit (their
data sheets give the no-load speed, e.g. Align DS610 0.08 s / 60 deg; small-signal
bandwidths of 4-8 Hz are the class's measured values, cf. the actuator models of
Mettler, Tischler & Kanade 2002); 120 deg CCPM swashplate mixing (three servos at 120 deg
push the swashplate; collective = their mean, cyclic = its tilt); the linkage's
geometric nonlinearity (a servo arm of radius a turned by theta moves its ball link by
a sin(theta)).

The radio (what the RC receiver records, in the host's nominal blade-pitch units) asks
each swash servo for the height h_i = col - lon x_i - lat y_i of its ball at
(x_i, y_i) = (cos a_i, sin a_i), i.e. an arm angle h_i / k_arm. What this airframe really
does (`rigging`, unknown to the host):

    arm angle command   theta_i* = (1 + g_i) h_i / k_arm                   (end-point error)
    servo               theta_i'' = wn^2 (theta_i* - theta_i) - 2 zeta wn theta_i'
                        with |theta_i'| <= rate
    ball height         h_i' = k_arm sin(theta_i) + o_i                     (linkage, centring)

and the swashplate plane through the three balls gives collective and the two tilts
(main_rotor.swash_feathering applies them to each blade with the phase error). The tail
servo does the same for the tail pitch, commanded by the yaw gyro (`tail_gyro`) from
the rudder channel. The rate limit is a stiff soft limiter on the servo speed.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from hil_sim.world.rotorcraft.airframe import Airframe

SRV_WN, SRV_ZETA, SRV_RATE, SRV_TAIL_WN, SRV_TAIL_ZETA, SRV_TAIL_RATE, SRV_K_ARM, \
    SRV_K_TAIL, SRV_TAIL_CENTER, SRV_TAIL_GAIN, SRV_TAIL_OFFSET, SRV_GYRO_GAIN, \
    SRV_GYRO_HOLD = range(13)
SRV_POS = 13  # (3) servo x_i, then y_i (3), gain errors (3), offsets (3), plane inverse (9)
N_SRV_PARAMS = SRV_POS + 21
RATE_LIMITER_GAIN = 800.0  # 1/s: how hard the soft limiter holds the servo speed


def pack(airframe: Airframe) -> np.ndarray:
    s = airframe.part("servos")
    r = airframe.part("rigging")
    p = np.zeros(N_SRV_PARAMS)
    p[SRV_WN] = 2.0 * math.pi * s["swash_natural_hz"]
    p[SRV_ZETA] = s["swash_damping"]
    p[SRV_RATE] = math.radians(s["swash_rate_deg_s"])
    p[SRV_TAIL_WN] = 2.0 * math.pi * s["tail_natural_hz"]
    p[SRV_TAIL_ZETA] = s["tail_damping"]
    p[SRV_TAIL_RATE] = math.radians(s["tail_rate_deg_s"])
    p[SRV_K_ARM] = s["swash_pitch_per_arm_rad"]
    p[SRV_K_TAIL] = s["tail_pitch_per_arm_rad"]
    p[SRV_TAIL_CENTER] = math.radians(s["tail_pitch_center_deg"])
    p[SRV_TAIL_GAIN] = r["tail_gain_error"]
    p[SRV_TAIL_OFFSET] = math.radians(r["tail_offset_deg"])
    gyro = airframe.part("tail_gyro")
    if gyro["mode"] != "off":
        p[SRV_GYRO_GAIN] = gyro["gain_pitch_per_rad_s"]
    if gyro["mode"] == "heading_hold":
        p[SRV_GYRO_HOLD] = gyro["heading_hold_per_s"]
    ang = np.radians(s["ccpm_angles_deg"])
    x, y = np.cos(ang), np.sin(ang)
    p[SRV_POS:SRV_POS + 3] = x
    p[SRV_POS + 3:SRV_POS + 6] = y
    p[SRV_POS + 6:SRV_POS + 9] = r["servo_gain_error"]
    p[SRV_POS + 9:SRV_POS + 12] = np.radians(r["servo_offset_deg"])
    # h_i = h0 - sigma_lon x_i - sigma_lat y_i  ->  [h0, sigma_lat, sigma_lon] = A^-1 h
    a = np.column_stack([np.ones(3), -y, -x])
    p[SRV_POS + 12:SRV_POS + 21] = np.linalg.inv(a).ravel()
    return p


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def tail_gyro(delta_ped, yaw_rate, hold_integral, p):
    """(tail pitch command, d integral / dt) of the yaw gyro: rate mode sends
    delta_ped - K r; heading hold reads the rudder as a rate command r* = delta_ped / K and
    adds the integral of K (r* - r) at `heading_hold_per_s` (its state)."""
    k = p[SRV_GYRO_GAIN]
    if k <= 0.0:
        return delta_ped, 0.0
    if p[SRV_GYRO_HOLD] > 0.0:
        return delta_ped - k * yaw_rate + hold_integral, p[SRV_GYRO_HOLD] * (delta_ped
                                                                             - k * yaw_rate)
    return delta_ped - k * yaw_rate, 0.0


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def servo_commands(delta, tail_cmd, p, out):
    """Arm-angle commands (4,) from the radio's [col, lat, lon] (rad of pitch) and the
    gyro's tail pitch command."""
    for i in range(3):
        h = delta[0] - delta[2] * p[SRV_POS + i] - delta[1] * p[SRV_POS + 3 + i]
        out[i] = (1.0 + p[SRV_POS + 6 + i]) * h / p[SRV_K_ARM]
    out[3] = (1.0 + p[SRV_TAIL_GAIN]) * tail_cmd / p[SRV_K_TAIL]


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def servo_acceleration(pos, vel, cmd, wn, zeta, rate):
    """Second-order servo with a soft rate limit."""
    acc = wn * wn * (cmd - pos) - 2.0 * zeta * wn * vel
    excess = abs(vel) - rate
    if excess > 0.0:
        acc -= RATE_LIMITER_GAIN * excess * (1.0 if vel > 0.0 else -1.0)
    return acc


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def swash_and_tail(angles, p):
    """(h0, sigma_lat, sigma_lon, tail pitch) from the four servo arm angles."""
    h = np.empty(3)
    for i in range(3):
        h[i] = p[SRV_K_ARM] * math.sin(angles[i]) + p[SRV_POS + 9 + i]
    inv = p[SRV_POS + 12:SRV_POS + 21]
    h0 = inv[0] * h[0] + inv[1] * h[1] + inv[2] * h[2]
    slat = inv[3] * h[0] + inv[4] * h[1] + inv[5] * h[2]
    slon = inv[6] * h[0] + inv[7] * h[1] + inv[8] * h[2]
    tail = p[SRV_K_TAIL] * math.sin(angles[3]) + p[SRV_TAIL_OFFSET] + p[SRV_TAIL_CENTER]
    return h0, slat, slon, tail
