"""The yaw gyro's share of a fitted yaw damping acts on the inertial rate (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, kernel


@register_effect("yaw_gyro")
class YawGyro(Effect):
    """A rate gyro between the rudder channel and the tail servo sends the servo the rudder
    plus a gain times the yaw rate it senses, and it senses the airframe's inertial rate r
    (a MEMS rate sensor on the frame): tail pitch = rudder + g r, g < 0 (it opposes the
    rate). The model reads the rudder as the tail pitch, so a calibration takes the gyro's
    loop into the model's own yaw damping — the tail rotor's and the fin's, which answer
    the yaw rate relative to the air, r - omega_z (omega_z the wind's rotation about body
    z, eq 5.3). In still air omega_z = 0 and the two cannot be told apart: a still-air fit
    is right there and wrong wherever the air rotates, where the gyro's share answers a
    rotation of the air that it does not feel. The model then reads omega_z from the yaw
    acceleration as strongly as it reads r, and claims an omega_z that the airframe does
    not show (docs/calibration.md, "What the fit bends on this airframe").

    A tail-pitch increment on the rudder the model reads (inputs stage, after servo lag):
        delta_ped += g omega_z,
    which turns the gyro's share of a fitted damping, g (r - omega_z), into g r. It is zero
    in still air: it changes no fit and no still-air residual, and a still-air flight
    cannot fit it. g is measured, not fitted: the tail-servo capture gives the airframe's
    aerodynamic damping N_a (the measured yaw acceleration regressed on the tail pitch the
    servo flies), and g = -(N_m - N_a) / B_m takes the rest of the model's damping N_m
    off its answer to omega_z (B_m its yaw acceleration per pedal;
    `airwake.calibrate.yaw_gyro.effect_gain`, `airwake calibrate --yaw-gyro`). Gyro loop:
    Padfield, Helicopter Flight Dynamics, §4.3 (stability augmentation by rate feedback);
    Mettler, Identification Modeling and Characteristics of Miniature Rotorcraft, §4 (the
    yaw-rate gyro in a small helicopter's yaw dynamics). g = 0 switches it off. It assumes
    the fitted damping holds the gyro's loop (a model fitted with the rudder as the tail
    pitch); a model that reads the tail servo itself must leave it off.
    """

    PARAMETERS = (
        Parameter("gain_rad_per_rad_s", 0.0, "s", (-1.0, 1.0), "measured",
                  doc="tail pitch the gyro adds per rad/s of yaw rate (negative: opposes it)"),
    )
    REQUIRES = ("tail_rotor",)

    @kernel
    def inputs(q, p, s, ds, load, scratch):
        q[Q.delta_ped_rad] += p.gain_rad_per_rad_s * q[Q.wind_w_rad_s + 2]
