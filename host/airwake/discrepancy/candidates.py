"""The catalogue as the diagnosis sees it: how to screen, fit and explain each effect.

A `Candidate` names a registered catalogue effect (`airwake.heli.effects.catalogue`) and says

- `screen`: the parameters whose first-order sensitivities d z_hat / d theta are the
  candidate's regressors, each with the step of a forward difference taken from "off"
  (amplitude-like parameters: bias, lever, strength, tau, gain);
- `base`: the values the other parameters hold while screening (the others at "off");
- `shapes`: alternatives for nonlinear shape parameters (heights, peak airspeed) tried in
  the screening (each a dict of values; the best by cross-validation is kept);
- `fit`: the parameters the nonlinear refinement and `add` fit;
- `needs`: flight columns without which the candidate cannot be tested;
- `condition`: what else the flight must hold for the signature to show (a key of
  `CONDITIONS`: near the ground, through the air at speed, in a known air that rotates,
  a rotor speed that moves);
- `reuse_hidden`: the effect only transforms the measurement, or adds a load the rotor's
  states do not feel, so the baseline's reconstructed rotor states can be reused (one
  model evaluation instead of a relaxation);
- `manoeuvre`: what a flight should contain to separate it from look-alikes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Candidate:
    name: str
    title: str
    screen: dict
    fit: tuple
    base: dict = field(default_factory=dict)
    shapes: tuple = ({},)
    needs: tuple = ()
    reuse_hidden: bool = False
    manoeuvre: str = ""
    condition: str = ""  # a key of CONDITIONS: what the flight must hold beyond `needs`


# advance_cyclic / advance_torque: the in-plane airspeed that shows their signature
MIN_ADVANCE_AIRSPEED_M_S = 1.5
MIN_ADVANCE_FRACTION = 0.02  # ... on at least this share of the samples
# yaw_gyro: the known wind's rotation about z that shows it (std over the flight)
MIN_AIR_ROTATION_RAD_S = 0.05


def air_velocity_uv(flight, wind=None) -> tuple[np.ndarray, np.ndarray]:
    """In-plane air velocity (body x, y) over the flight: the known wind ((T, 6), body axes)
    minus the body velocity, or minus the body velocity alone in still air."""
    u, v = -flight.column("vel_u_m_s"), -flight.column("vel_v_m_s")
    if wind is not None:
        u, v = u + np.asarray(wind)[:, 0], v + np.asarray(wind)[:, 1]
    return u, v


# What a flight must hold beyond its columns for a candidate's signature to show: each
# `(flight, model, wind) -> None | why not` (a short phrase), named by `Candidate.condition`.
def _near_ground(flight, model, wind) -> str | None:
    radius = float(model["main_rotor"].parameters()["radius_m"])
    z = flight.column("height_agl_m")
    low = np.isfinite(z) & (z < 3.0 * radius)
    if low.sum() < 0.02 * z.size:
        return "the flight never comes within 3 rotor radii of the ground"
    return None


def _airspeed(flight, model, wind) -> str | None:
    fast = np.hypot(*air_velocity_uv(flight, wind)) > MIN_ADVANCE_AIRSPEED_M_S
    if np.mean(fast) < MIN_ADVANCE_FRACTION:
        return (f"the flight never flies faster than {MIN_ADVANCE_AIRSPEED_M_S} m/s "
                "through the air across the disc")
    return None


def _air_rotates(flight, model, wind) -> str | None:
    if wind is None or np.std(np.asarray(wind)[:, 5]) < MIN_AIR_ROTATION_RAD_S:
        return ("the air does not rotate about z (still air, or no known wind): a still-air "
                "flight cannot show it; its gain is the tail-servo capture's "
                "(airwake calibrate)")
    return None


def _rotor_speed_moves(flight, model, wind) -> str | None:
    if np.ptp(flight.column("rotor_speed_rad_s")) < 1e-6:
        return "the measured rotor speed is constant"
    return None


CONDITIONS = {"near_ground": _near_ground, "airspeed": _airspeed,
              "air_rotates": _air_rotates, "rotor_speed_moves": _rotor_speed_moves}


CANDIDATES: tuple[Candidate, ...] = (
    Candidate(
        "ground_effect", "ground effect",
        screen={"strength": 0.5},
        base={},
        shapes=({"fade_start_ratio": 2.0, "fade_end_ratio": 3.0},
                {"fade_start_ratio": 1.5, "fade_end_ratio": 2.5},
                {"fade_start_ratio": 3.0, "fade_end_ratio": 5.0}),
        fit=("strength", "fade_start_ratio", "fade_end_ratio"),
        needs=("height_agl_m",),
        condition="near_ground",
        manoeuvre="hovers at several heights between 0.5 R and 3 R (zero airspeed) with slow "
                  "collective changes",
    ),
    Candidate(
        "imu_lever_arm", "IMU lever arm",
        screen={"x_m": 0.1, "y_m": 0.1, "z_m": 0.1},
        fit=("x_m", "y_m", "z_m"),
        manoeuvre="rapid roll, pitch and yaw reversals (large angular accelerations and "
                  "rates) at constant thrust",
    ),
    Candidate(
        "servo_lag", "servo lag",
        screen={"tau_swash_s": 0.03, "tau_tail_s": 0.03},
        base={"tau_swash_s": 0.002, "tau_tail_s": 0.002},
        fit=("tau_swash_s", "tau_tail_s"),
        manoeuvre="cyclic, collective and pedal chirps up to 4-5 Hz (the lag grows with "
                  "input frequency)",
    ),
    Candidate(
        "rotor_droop", "rotor-speed droop",
        screen={"tachometer_gain": 0.5},
        base={"tachometer_gain": 0.0},
        fit=("tachometer_gain",),
        needs=("rotor_speed_rad_s",),
        condition="rotor_speed_moves",
        manoeuvre="large collective steps with the tachometer recorded (the governor droops "
                  "and recovers)",
    ),
    Candidate(
        "dynamic_inflow", "inflow dynamics",
        screen={"tau_s": 0.05},
        base={"tau_s": 0.005},
        fit=("tau_s",),
        manoeuvre="collective steps and chirps up to ~4 Hz out of ground effect (thrust "
                  "overshoot on each step)",
    ),
    Candidate(
        "wake_recirculation", "wake recirculation",
        screen={"inflow_increase": 0.2},
        base={"inflow_increase": 0.0, "gradient_fraction": 0.5},
        shapes=tuple({"peak_airspeed_m_s": v, "full_height_ratio": 1.0,
                      "zero_height_ratio": h} for v in (1.5, 3.0, 5.0) for h in (2.0, 3.5)),
        fit=("inflow_increase", "peak_airspeed_m_s", "gradient_fraction",
             "full_height_ratio", "zero_height_ratio"),
        needs=("height_agl_m",),
        condition="near_ground",
        manoeuvre="low passes near the ground at 1-6 m/s and hovers at the same height (no "
                  "recirculation in hover, where ground effect is largest)",
    ),
    Candidate(
        "accel_bias", "accelerometer bias",
        screen={"bx_m_s2": 0.1, "by_m_s2": 0.1, "bz_m_s2": 0.1},
        fit=("bx_m_s2", "by_m_s2", "bz_m_s2"),
        reuse_hidden=True,
        manoeuvre="steady hovers at different thrust and attitude (a bias stays constant, a "
                  "misalignment scales with the specific force)",
    ),
    Candidate(
        "accel_misalignment", "accelerometer misalignment",
        screen={"ex_rad": 0.01, "ey_rad": 0.01, "ez_rad": 0.01},
        fit=("ex_rad", "ey_rad", "ez_rad"),
        reuse_hidden=True,
        manoeuvre="collective steps in hover (a misalignment scales with the specific "
                  "force, a bias does not)",
    ),
    Candidate(
        "cg_offset", "mass / CG offset",
        screen={"x_m": 0.01, "y_m": 0.01, "z_m": 0.01, "mass_error_kg": 0.1},
        fit=("x_m", "y_m", "z_m", "mass_error_kg"),
        reuse_hidden=True,
        manoeuvre="hovers at different thrust and forward flight (moment offsets scale with "
                  "the rotor force)",
    ),
    Candidate(
        "fuselage_drag_error", "fuselage drag error",
        screen={"dcx_m2": 0.02, "dcy_m2": 0.02, "dcz_m2": 0.02},
        base={"x_cp_m": 0.0, "z_cp_m": 0.0},
        fit=("dcx_m2", "dcy_m2", "dcz_m2", "x_cp_m", "z_cp_m"),
        manoeuvre="forward, sideward and vertical flight at several speeds (>= 3 m/s)",
    ),
    Candidate(
        "advance_cyclic", "cyclic trim vs advance ratio",
        # screened on the two direct terms (forward speed -> theta_c, sideward -> theta_s;
        # the cross terms come in the refinement and `add`): half the rotor relaxations
        screen={"k_cx": 0.3, "k_sy": 0.3},
        fit=("k_cx", "k_cy", "k_sx", "k_sy"),
        condition="airspeed",
        manoeuvre="forward, backward and sideward legs at 2-4 m/s, held for several seconds "
                  "(the cyclic trim changes with the airspeed across the disc)",
    ),
    Candidate(
        "advance_torque", "rotor torque vs airspeed",
        screen={"k_q": 0.1},
        fit=("k_q",),
        reuse_hidden=True,  # a couple on the body: the rotor's states do not feel it
        condition="airspeed",
        manoeuvre="forward, backward and sideward legs at 2-4 m/s, held for several seconds "
                  "(the torque falls with the airspeed squared in every direction, a tail "
                  "or fin error changes sign with the sideslip)",
    ),
    Candidate(
        "yaw_gyro", "yaw gyro on the inertial rate",
        screen={"gain_rad_per_rad_s": 0.05},
        fit=("gain_rad_per_rad_s",),
        reuse_hidden=True,  # a tail pitch: the main rotor's states do not feel it
        condition="air_rotates",
        manoeuvre="a flight in a known rotating air (a vortex, a turntable's swirl): still "
                  "air cannot show it; `airwake calibrate` measures its gain from the "
                  "tail-servo capture instead",
    ),
)


def candidate(name: str) -> Candidate | None:
    for c in CANDIDATES:
        if c.name == name:
            return c
    return None


def effect_with(name: str, values: dict):
    """An instance of the registered effect `name` with `values` (others default)."""
    from airwake.heli.effects.base import effect_class

    return effect_class(name)(**values)


def flight_can_test(cand: Candidate, flight, model, wind=None) -> str | None:
    """None when the flight can test `cand`, else why not (a short phrase). `wind`: the
    known wind given as the model's input ((T, 6), body axes), else still air."""
    for col in cand.needs:
        if not flight.has(col):
            return f"the flight has no {col}"
    return CONDITIONS[cand.condition](flight, model, wind) if cand.condition else None
