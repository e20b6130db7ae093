"""Hidden effects on the sensor side: what the recorded streams get wrong, not the flight.

- **Vibration rectification** of the accelerometers. A MEMS accelerometer's output has a
  second-order term, a_out = K0 + K1 a + K2 a^2 + ... (the model equation of IEEE Std
  1293-1998, "Standard Specification Format Guide and Test Procedure for Linear,
  Single-Axis, Nonpendulous Analog Accelerometers"); under a zero-mean vibration
  a_v(t) the K2 term leaves a mean K2 <a_v^2>: the vibration rectification error, which
  on small helicopters shows as an accelerometer offset of the order of 1 m/s^2 that
  appears when the rotor spins up. The rotor-synchronous vibration grows with the rotor
  speed, so the offset is taken as
      b(t) = b_ref (Omega(t) / Omega_ref)^n
  (n = 2: vibration amplitude proportional to Omega; n = 4: to Omega^2, a pure imbalance
  on a stiff mount). Added to the IMU point's specific force before the sensor model.
- **Input time skew**: the pilot-input stream (base board, RC receiver) and the INS
  stream (rover board) reach the log on different paths; an uncorrected latency on one
  of them leaves a constant skew. The recorded command stamped t is the one the servos
  received at t + offset (`skewed_commands`).
"""

from __future__ import annotations

import dataclasses

import numpy as np


def rectification_offset(rotor_speed_rad_s: np.ndarray, config, reference_speed_rad_s: float
                         ) -> np.ndarray:
    """(N, 3) accelerometer offset b(t) for rotor speeds (N,) (module docstring)."""
    ref = (config.reference_speed_rad_s if config.reference_speed_rad_s is not None
           else reference_speed_rad_s)
    scale = (np.maximum(np.asarray(rotor_speed_rad_s, float), 0.0) / ref) ** config.speed_exponent
    return scale[:, None] * np.asarray(config.offset_m_s2, float)[None, :]


def with_rectification(imu, config, reference_speed_rad_s: float):
    """The IMU point's Trajectory with the rectification offset in its specific force."""
    offset = rectification_offset(imu.rotor_speed_rad_s, config, reference_speed_rad_s)
    return dataclasses.replace(imu, specific_force_body_m_s2=imu.specific_force_body_m_s2
                               + offset)


def skewed_commands(t_s: np.ndarray, commands_rad: np.ndarray, offset_s: float) -> np.ndarray:
    """(N, 4) what the pilot-input stream records at times t_s: the command at t + offset
    (held at the ends). `commands_rad` (N, 4) are the commands at t_s."""
    return np.stack([np.interp(t_s + offset_s, t_s, commands_rad[:, j])
                     for j in range(commands_rad.shape[1])], -1)
