"""Scenario settings of the hidden effects (`[hidden.<name>]` tables), validated.

A table present in the scenario switches its effect on unless it says `enabled = false`;
an absent table leaves it off. Every key is a field below (units in the names); unknown
keys and bad values raise `ValueError` naming the key path and the value
(`hidden.servo_lag: damping_ratio = -0.1: must be in [0.2, 2.0]`). The physics and the
source of each effect are in its module (ground_effect.py, servo.py, electric_drive.py,
dynamic_inflow.py, ground_vortex.py, sensor_side.py) and in docs/scenarios.md.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from hil_sim.sensors.config import (
    check_finite,
    check_positive,
    check_range,
    config_from_dict,
    config_to_dict,
)

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class GroundEffectConfig:
    """Hayden's (1976) empirical ground effect on the induced inflow (ground_effect.py).

    The fit P_IGE/P_OGE = 1/(intercept + slope (2R/z)^2) at constant thrust, normalised
    to 1 out of ground effect, attenuated in forward flight by the share of the disk the
    skewed wake's ground footprint still lies under; `deck_edge`: on a ship the reduction
    is averaged over the disk, each part over the deck, the hangar roof or the sea."""

    enabled: bool = True
    power_ratio_intercept: float = 0.9926
    power_ratio_slope: float = 0.0379
    min_height_ratio: float = 0.4  # z/R below which the fit is held (outside its data)
    deck_edge: bool = True

    def __post_init__(self) -> None:
        check_range("power_ratio_intercept", self.power_ratio_intercept, 0.8, 1.2)
        check_range("power_ratio_slope", self.power_ratio_slope, 0.0, 0.2)
        check_range("min_height_ratio", self.min_height_ratio, 0.2, 2.0)


@dataclass(frozen=True)
class LeverArmConfig:
    """The INS/IMU mounted at `position_m` (body FRD, from the CG): the accelerometers read
    a_cg + w_dot x r + w x (w x r); gyros are unaffected. INS velocity and position are
    those of the IMU point too (what a VN200 reports without a configured offset). The
    default: a VN200 on the canopy frame, 14 cm ahead of, 3 cm right of and 9 cm above
    the CG."""

    enabled: bool = True
    position_m: Vec3 = (0.14, 0.03, -0.09)

    def __post_init__(self) -> None:
        check_finite("position_m", self.position_m)
        for v in self.position_m:
            check_range("position_m", v, -1.0, 1.0)


@dataclass(frozen=True)
class ServoLagConfig:
    """RC servos between the recorded command and the blade pitch (servo.py): a pure
    transport delay `delay_s` (PWM frame and the servo's processing), a deadband, then a
    second-order position loop (natural frequency, damping) whose speed is limited to
    the servo's slew rate. Swashplate servos (collective, cyclic) and the tail servo
    have their own dynamics; one deadband (blade-pitch radians) for all."""

    enabled: bool = True
    natural_frequency_hz: float = 8.0
    damping_ratio: float = 0.65
    rate_limit_rad_s: float = 3.5  # blade pitch: a 0.1 s/60 deg servo through the linkage
    tail_natural_frequency_hz: float = 12.0
    tail_damping_ratio: float = 0.6
    tail_rate_limit_rad_s: float = 8.0
    deadband_rad: float = 0.0014  # ~2 us of PWM at 7e-4 rad/us (digital servo)
    delay_s: float = 0.0

    def __post_init__(self) -> None:
        check_range("natural_frequency_hz", self.natural_frequency_hz, 1.0, 50.0)
        check_range("damping_ratio", self.damping_ratio, 0.2, 2.0)
        check_range("rate_limit_rad_s", self.rate_limit_rad_s, 0.2, 50.0)
        check_range("tail_natural_frequency_hz", self.tail_natural_frequency_hz, 1.0, 50.0)
        check_range("tail_damping_ratio", self.tail_damping_ratio, 0.2, 2.0)
        check_range("tail_rate_limit_rad_s", self.tail_rate_limit_rad_s, 0.2, 50.0)
        check_range("deadband_rad", self.deadband_rad, 0.0, 0.02)
        check_range("delay_s", self.delay_s, 0.0, 0.2)


@dataclass(frozen=True)
class RotorDroopConfig:
    """Electric drive and its governor (electric_drive.py): a brushless motor fed by the
    battery through the ESC's throttle (Q_m = K_t (V d - K_e w_m) / R, no regenerative
    braking) turns the rotor through the gear ratio; a PI governor with a throttle
    ceiling and back-calculation anti-windup holds the head speed. The rotor droops
    while the governor catches up and, once the throttle is at its ceiling, along the
    motor's torque-speed line. `speed_setpoint_rad_s` defaults to the model's nominal."""

    enabled: bool = True
    rotor_inertia_kg_m2: float = 0.055  # blades, hub, flybar, motor rotor x gear ratio^2
    battery_voltage_v: float = 22.2
    motor_kv_rpm_per_v: float = 1100.0
    circuit_resistance_ohm: float = 0.08  # battery + ESC + winding
    gear_ratio: float = 11.0
    governor_kp_per_rad_s: float = 0.004  # throttle per rad/s of speed error
    governor_ti_s: float = 1.0
    antiwindup_time_s: float = 0.3
    max_throttle: float = 0.95
    speed_setpoint_rad_s: float | None = None

    def __post_init__(self) -> None:
        check_range("rotor_inertia_kg_m2", self.rotor_inertia_kg_m2, 0.005, 1.0)
        check_range("battery_voltage_v", self.battery_voltage_v, 5.0, 60.0)
        check_range("motor_kv_rpm_per_v", self.motor_kv_rpm_per_v, 100.0, 5000.0)
        check_range("circuit_resistance_ohm", self.circuit_resistance_ohm, 0.005, 1.0)
        check_range("gear_ratio", self.gear_ratio, 1.0, 30.0)
        check_range("governor_kp_per_rad_s", self.governor_kp_per_rad_s, 1e-4, 0.1)
        check_range("governor_ti_s", self.governor_ti_s, 0.05, 20.0)
        check_range("antiwindup_time_s", self.antiwindup_time_s, 0.01, 10.0)
        check_range("max_throttle", self.max_throttle, 0.3, 1.0)
        if self.speed_setpoint_rad_s is not None:
            check_range("speed_setpoint_rad_s", self.speed_setpoint_rad_s, 50.0, 400.0)


@dataclass(frozen=True)
class DynamicInflowConfig:
    """Three-state Pitt-Peters dynamic inflow (dynamic_inflow.py): the apparent mass
    M = diag(8/(3 pi), 16/(45 pi), 16/(45 pi)) of the air through the disk and the wake-
    skew L matrix (Peters & HaQuang 1988) drive lambda_0, lambda_c, lambda_s toward the
    quasi-static inflow. `apparent_mass_scale` multiplies M (1 = the theory)."""

    enabled: bool = True
    apparent_mass_scale: float = 1.0

    def __post_init__(self) -> None:
        check_range("apparent_mass_scale", self.apparent_mass_scale, 0.1, 10.0)


@dataclass(frozen=True)
class WakeRecirculationConfig:
    """Ground-vortex recirculation (ground_vortex.py): at low airspeed near the ground the
    forward wall jet rolls up into a spanwise vortex upstream of the hub (Curtiss, Sun,
    Putman & Hanker 1984); the vortex and its ground image induce a downwash on the
    disk between the vortex and the hub (more inflow: thrust loss, an upstream gradient).
    Circulation Gamma = k v_h R F(V/v_h) exp(-z / (h_e R)); the vortex sits
    `position_ratio` R / (V/v_h) ahead of the hub and is swept away at V/v_h =
    `sweep_ratio`."""

    enabled: bool = True
    circulation_ratio: float = 2.0  # k = Gamma / (v_h R)
    position_ratio: float = 1.0  # vortex x_v/R at V = v_h
    sweep_ratio: float = 2.0  # V / v_h where the vortex is gone
    core_height_ratio: float = 0.4  # vortex core height / hub height
    core_radius_ratio: float = 0.1  # viscous core radius / R
    decay_height_ratio: float = 2.0  # h_e: wall-jet e-folding height / R

    def __post_init__(self) -> None:
        check_range("circulation_ratio", self.circulation_ratio, 0.0, 10.0)
        check_range("position_ratio", self.position_ratio, 0.2, 5.0)
        check_range("sweep_ratio", self.sweep_ratio, 0.5, 5.0)
        check_range("core_height_ratio", self.core_height_ratio, 0.05, 0.9)
        check_range("core_radius_ratio", self.core_radius_ratio, 0.01, 1.0)
        check_range("decay_height_ratio", self.decay_height_ratio, 0.2, 10.0)


@dataclass(frozen=True)
class VibrationRectificationConfig:
    """Accelerometer vibration rectification (sensor_side.py): the rotor's vibration,
    through the accelerometer's second-order (K2) nonlinearity, shifts its mean output:
    b = offset_m_s2 (Omega / Omega_ref)^speed_exponent, added to the IMU's specific force
    (truth_acc_* included: it is part of what the IMU reads, not noise).
    `reference_speed_rad_s` defaults to the model's nominal rotor speed."""

    enabled: bool = True
    offset_m_s2: Vec3 = (0.0, 0.0, 1.0)
    speed_exponent: float = 2.0
    reference_speed_rad_s: float | None = None

    def __post_init__(self) -> None:
        check_finite("offset_m_s2", self.offset_m_s2)
        for v in self.offset_m_s2:
            check_range("offset_m_s2", v, -5.0, 5.0)
        check_range("speed_exponent", self.speed_exponent, 0.0, 6.0)
        if self.reference_speed_rad_s is not None:
            check_positive("reference_speed_rad_s", self.reference_speed_rad_s)


@dataclass(frozen=True)
class InputTimeSkewConfig:
    """A constant time skew of the pilot-input stream against the INS rows
    (sensor_side.py): the recorded command stamped t is the one the servos got at
    t + offset_s (offset_s > 0: the inputs appear early, as when an INS latency is not
    removed from its rows; < 0: late)."""

    enabled: bool = True
    offset_s: float = 0.04

    def __post_init__(self) -> None:
        check_range("offset_s", self.offset_s, -0.1, 0.1)


HIDDEN_CONFIGS: dict[str, type] = {
    "ground_effect": GroundEffectConfig,
    "lever_arm": LeverArmConfig,
    "servo_lag": ServoLagConfig,
    "rotor_droop": RotorDroopConfig,
    "dynamic_inflow": DynamicInflowConfig,
    "wake_recirculation": WakeRecirculationConfig,
    "vibration_rectification": VibrationRectificationConfig,
    "input_time_skew": InputTimeSkewConfig,
}


@dataclass(frozen=True)
class HiddenConfig:
    """Which hidden effects a scenario switches on (None = off) and their settings."""

    ground_effect: GroundEffectConfig | None = None
    lever_arm: LeverArmConfig | None = None
    servo_lag: ServoLagConfig | None = None
    rotor_droop: RotorDroopConfig | None = None
    dynamic_inflow: DynamicInflowConfig | None = None
    wake_recirculation: WakeRecirculationConfig | None = None
    vibration_rectification: VibrationRectificationConfig | None = None
    input_time_skew: InputTimeSkewConfig | None = None

    def enabled(self) -> dict[str, Any]:
        """{name: config} of the effects that are on."""
        out = {}
        for name in HIDDEN_CONFIGS:
            cfg = getattr(self, name)
            if cfg is not None and cfg.enabled:
                out[name] = cfg
        return out

    def to_dict(self) -> dict:
        return {name: config_to_dict(cfg) for name, cfg in self.enabled().items()}


def hidden_from_dict(table: Mapping[str, Any] | None, where: str = "hidden") -> HiddenConfig:
    """`[hidden]` table -> HiddenConfig; unknown effect names and keys are errors."""
    if table is None:
        return HiddenConfig()
    if not isinstance(table, Mapping):
        raise ValueError(f"{where}: expected a table of hidden effects, got {table!r}")
    kwargs = {}
    for name, sub in table.items():
        if name not in HIDDEN_CONFIGS:
            raise ValueError(f"{where}: unknown hidden effect {name!r} "
                             f"(known: {', '.join(HIDDEN_CONFIGS)})")
        kwargs[name] = config_from_dict(HIDDEN_CONFIGS[name], sub, f"{where}.{name}")
    return HiddenConfig(**kwargs)
