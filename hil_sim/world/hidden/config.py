"""Scenario settings of the hidden effects (`[hidden.<name>]` tables), validated.

A table present in the scenario switches its effect on unless it says `enabled = false`;
an absent table leaves it off. Every key is a field below (units in the names); unknown
keys and bad values raise `ValueError` naming the key path and the value
(`hidden.servo_lag: tau_swash_s = -0.1: must be a finite number > 0`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from hil_sim.sensors.config import (
    check_finite,
    check_nonnegative,
    check_positive,
    check_range,
    config_from_dict,
    config_to_dict,
)

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class GroundEffectConfig:
    """Cheeseman-Bennett ground/deck effect on the rotor's mean induced inflow.

    lambda_0 <- lambda_0 (1 - k),  k = strength (R / 4 z)^2 / (1 + (mu/lambda_0)^2) * taper(z/R)
    with z the hub height above ground/deck, floored at `min_height_ratio` R, and a taper
    that fades the effect out between `fade_start_ratio` R and `fade_end_ratio` R.
    """

    enabled: bool = True
    strength: float = 1.0
    min_height_ratio: float = 0.5
    fade_start_ratio: float = 2.0
    fade_end_ratio: float = 3.0

    def __post_init__(self) -> None:
        check_range("strength", self.strength, 0.0, 3.0)
        check_range("min_height_ratio", self.min_height_ratio, 0.3, 2.0)
        check_positive("fade_start_ratio", self.fade_start_ratio)
        if not self.fade_end_ratio > self.fade_start_ratio:
            raise ValueError(f"fade_end_ratio = {self.fade_end_ratio!r}: must be > "
                             f"fade_start_ratio = {self.fade_start_ratio!r}")


@dataclass(frozen=True)
class LeverArmConfig:
    """The INS/IMU mounted at `position_m` (body FRD, from the CG): the accelerometers read
    a_cg + w_dot x r + w x (w x r); gyros are unaffected. INS velocity and position are
    those of the IMU point too (what a VN200 reports without a configured offset)."""

    enabled: bool = True
    position_m: Vec3 = (0.10, -0.05, -0.12)

    def __post_init__(self) -> None:
        check_finite("position_m", self.position_m)
        for v in self.position_m:
            check_range("position_m", v, -1.0, 1.0)


@dataclass(frozen=True)
class ServoLagConfig:
    """Servo dynamics between the recorded RC command and the blade pitch:
    a pure delay `delay_s` then a first-order lag (time constants per servo group)."""

    enabled: bool = True
    tau_swash_s: float = 0.06  # collective and cyclic servos (swashplate)
    tau_tail_s: float = 0.04  # tail servo
    delay_s: float = 0.0

    def __post_init__(self) -> None:
        check_range("tau_swash_s", self.tau_swash_s, 0.002, 0.5)
        check_range("tau_tail_s", self.tau_tail_s, 0.002, 0.5)
        check_range("delay_s", self.delay_s, 0.0, 0.2)


@dataclass(frozen=True)
class RotorDroopConfig:
    """Rotor-speed governor with finite gain and the rotor/drivetrain inertia:

        I_R dOmega/dt = Q_engine - Q_rotor,  Q_engine = Q_ff + K (Omega_set - Omega)

    Q_ff (the governor's feed-forward) is trimmed so the hover runs at Omega_set unless
    `feedforward_torque_nm` is given; Omega_set defaults to the model's nominal speed."""

    enabled: bool = True
    rotor_inertia_kg_m2: float = 0.06
    governor_gain_nm_s: float = 0.05  # N m per rad/s of speed error
    speed_setpoint_rad_s: float | None = None
    feedforward_torque_nm: float | None = None

    def __post_init__(self) -> None:
        check_range("rotor_inertia_kg_m2", self.rotor_inertia_kg_m2, 0.005, 1.0)
        check_range("governor_gain_nm_s", self.governor_gain_nm_s, 0.005, 10.0)
        if self.speed_setpoint_rad_s is not None:
            check_range("speed_setpoint_rad_s", self.speed_setpoint_rad_s, 50.0, 400.0)
        if self.feedforward_torque_nm is not None:
            check_range("feedforward_torque_nm", self.feedforward_torque_nm, 0.0, 50.0)


@dataclass(frozen=True)
class DynamicInflowConfig:
    """First-order lag of the rotor's mean inflow toward its quasi-static value:
    tau dlambda_0/dt = lambda_0,static - lambda_0 (thrust overshoot on collective steps)."""

    enabled: bool = True
    tau_s: float = 0.08

    def __post_init__(self) -> None:
        check_range("tau_s", self.tau_s, 0.005, 1.0)


@dataclass(frozen=True)
class WakeRecirculationConfig:
    """Ground-vortex recirculation: near the ground at low airspeed the rotor re-ingests
    its own wake; the mean inflow rises (thrust loss) and more at the upstream edge:

        d lambda_0 = A lambda_0 F(z/R) G(V/V_peak),   d lambda_up = g d lambda_0
        F = 1 below `full_height_ratio`, smoothly 0 at `zero_height_ratio`;
        G(x) = x^2 exp(1 - x^2) (0 in hover, 1 at V = V_peak, gone at high speed)."""

    enabled: bool = True
    inflow_increase: float = 0.25  # A
    peak_airspeed_m_s: float = 3.0
    full_height_ratio: float = 1.0
    zero_height_ratio: float = 2.5
    gradient_fraction: float = 0.5  # g

    def __post_init__(self) -> None:
        check_range("inflow_increase", self.inflow_increase, 0.0, 2.0)
        check_positive("peak_airspeed_m_s", self.peak_airspeed_m_s)
        check_positive("full_height_ratio", self.full_height_ratio)
        if not self.zero_height_ratio > self.full_height_ratio:
            raise ValueError(f"zero_height_ratio = {self.zero_height_ratio!r}: must be > "
                             f"full_height_ratio = {self.full_height_ratio!r}")
        check_nonnegative("gradient_fraction", self.gradient_fraction)
        check_range("gradient_fraction", self.gradient_fraction, 0.0, 3.0)


HIDDEN_CONFIGS: dict[str, type] = {
    "ground_effect": GroundEffectConfig,
    "lever_arm": LeverArmConfig,
    "servo_lag": ServoLagConfig,
    "rotor_droop": RotorDroopConfig,
    "dynamic_inflow": DynamicInflowConfig,
    "wake_recirculation": WakeRecirculationConfig,
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
