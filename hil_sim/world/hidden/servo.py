"""Truth RC servos: transport delay, deadband, second-order position loop, slew-rate limit.

An RC servo is a DC motor in a position loop: its electronics turn the position error
into a motor speed command, which the motor follows with its mechanical time constant
and cannot exceed its no-load speed (the "0.10 s/60 deg" of a data sheet). Written as
the cascade (per channel j, blade-pitch radians; delta the command, theta the pitch):

    e   = dz(delta - theta),  dz(e) = e - h sign(e) for |e| > h, else 0   (deadband 2h)
    v   = sat(w_p e, +-r)                                  (speed command, slew limit r)
    theta'' = w_a (v - theta')                              (motor speed follows)

which in its linear range is the second-order actuator with a time delay,
w_n^2 e^{-tau s} / (s^2 + 2 zeta w_n s + w_n^2), that Tischler & Remple identify for
helicopter actuators (Tischler & Remple 2012, "Aircraft and Rotorcraft System
Identification", 2nd ed., AIAA; w_n^2 = w_a w_p, 2 zeta w_n = w_a), with the motor's
speed saturation and the electronics' deadband on top: |theta'| never exceeds r
(theta'' = w_a (v - theta') pulls it back from the limit), and a command change inside
the deadband leaves the servo where it is. The pure delay (PWM frame + processing) is
applied to the command by the simulation loop (`delay_s`). The swashplate's three
servos are lumped per axis (collective, lateral, longitudinal) with one dynamics; the
tail servo has its own.
States: the four blade pitches (col, lat, lon, ped), then their four rates.
"""

from __future__ import annotations

import math

import numpy as np
from airwake.heli.effects.base import Effect, Parameter, State
from airwake.heli.kernel import Q, kernel, kernel_function


@kernel_function
def servo_acceleration(command, theta, rate, half_band, w_p, w_a, rate_limit):
    """theta'' of one servo channel (module docstring)."""
    e = command - theta
    if e > half_band:
        e -= half_band
    elif e < -half_band:
        e += half_band
    else:
        e = 0.0
    v = min(max(w_p * e, -rate_limit), rate_limit)
    return w_a * (v - rate)


class SecondOrderServo(Effect):
    """Rate-limited second-order servos with a deadband (inputs stage; module docstring).
    The rest of the model sees the servo positions; the recorded commands are delta."""

    name = "hil_servo"
    PARAMETERS = (
        Parameter("natural_frequency_rad_s", 2 * math.pi * 8.0, "rad/s", (5.0, 400.0),
                  "swashplate servos w_n"),
        Parameter("damping_ratio", 0.65, "-", (0.2, 2.0), "swashplate servos zeta"),
        Parameter("rate_limit_rad_s", 3.5, "rad/s", (0.2, 50.0), "swashplate slew rate"),
        Parameter("tail_natural_frequency_rad_s", 2 * math.pi * 12.0, "rad/s", (5.0, 400.0),
                  "tail servo w_n"),
        Parameter("tail_damping_ratio", 0.6, "-", (0.2, 2.0), "tail servo zeta"),
        Parameter("tail_rate_limit_rad_s", 8.0, "rad/s", (0.2, 50.0), "tail slew rate"),
        Parameter("deadband_rad", 0.0014, "rad", (0.0, 0.02), "full width, blade pitch"),
    )
    STATES = (
        State("col_rad", "rad", "collective pitch the servos hold"),
        State("lat_rad", "rad", "lateral cyclic the servos hold"),
        State("lon_rad", "rad", "longitudinal cyclic the servos hold"),
        State("ped_rad", "rad", "tail pitch the servo holds"),
        State("col_rate_rad_s", "rad/s", "collective servo speed"),
        State("lat_rate_rad_s", "rad/s", "lateral servo speed"),
        State("lon_rate_rad_s", "rad/s", "longitudinal servo speed"),
        State("ped_rate_rad_s", "rad/s", "tail servo speed"),
    )
    SCRATCH = 4  # the commands, from the inputs stage to state_rates

    @kernel
    def inputs(q, p, s, ds, load, scratch):
        # the four commands sit in consecutive context slots, col, lat, lon, ped
        for j in range(4):
            scratch[j] = q[Q.delta_col_rad + j]
            q[Q.delta_col_rad + j] = s[j]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        h = 0.5 * p.deadband_rad
        w_a = 2.0 * p.damping_ratio * p.natural_frequency_rad_s
        w_p = p.natural_frequency_rad_s / (2.0 * p.damping_ratio)
        for j in range(3):
            ds[j] = s[4 + j]
            ds[4 + j] = servo_acceleration(scratch[j], s[j], s[4 + j], h, w_p, w_a,
                                           p.rate_limit_rad_s)
        w_a = 2.0 * p.tail_damping_ratio * p.tail_natural_frequency_rad_s
        w_p = p.tail_natural_frequency_rad_s / (2.0 * p.tail_damping_ratio)
        ds[3] = s[7]
        ds[7] = servo_acceleration(scratch[3], s[3], s[7], h, w_p, w_a,
                                   p.tail_rate_limit_rad_s)

    def rest_state(self, u: np.ndarray, ctx) -> np.ndarray:
        """Servos at the command, not moving."""
        return np.concatenate([np.asarray(u, float), np.zeros(4)])

    def linear_values(self) -> dict:
        """Parameter values that remove the non-smooth parts (the deadband) for the
        pilot's linear design and the trim: the rate limit does not act near a trim."""
        return {"deadband_rad": 0.0}

    @staticmethod
    def positions(states: np.ndarray) -> np.ndarray:
        """(N, 4) servo positions from (N, 8) servo states."""
        return states[:, :4]
