"""The airframe file: every parameter of the blade-element truth with its unit and source.

    airframe = load_airframe()                                  # airframe_600.toml
    airframe = load_airframe("my_heli.toml", overrides={"main_rotor.chord_m": 0.055})
    airframe["main_rotor.radius_m"]  -> 0.675
    airframe.source("drive.gear_ratio") -> "T-REX 600E: 150T main gear, 13T pinion"

The file is TOML with one table per physical part (body, main_rotor, flybar, tail_rotor,
fuselage, horizontal_stabilizer, vertical_fin, drive, servos, tail_gyro, rigging, imu); each entry
is `{ value = ..., source = "..." }`: a parameter without a source is refused. Units are
in the names (SI). The shipped file `airframe_600.toml` is an electric 600-class
helicopter with a Bell-Hiller flybar; see docs/truth-world.md for the table.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

AIRFRAME_DIR = Path(__file__).resolve().parent
DEFAULT_AIRFRAME = AIRFRAME_DIR / "airframe_600.toml"

# part -> parameter -> kind: "pos" (> 0), "nonneg" (>= 0), "real", "vec3", "vec3pos",
# "int" (>= 1), "choice:a|b"
SCHEMA: dict[str, dict[str, str]] = {
    "body": {"mass_kg": "pos", "Ixx_kg_m2": "pos", "Iyy_kg_m2": "pos", "Izz_kg_m2": "pos",
             "Ixz_kg_m2": "real"},
    "main_rotor": {"rotation": "choice:clockwise|counterclockwise", "radius_m": "pos",
                   "blade_root_m": "nonneg", "root_cutout_m": "nonneg", "chord_m": "pos",
                   "twist_deg": "real", "blade_mass_kg": "pos", "hub_position_m": "vec3",
                   "elements": "int", "hub_spring_nm_rad": "nonneg",
                   "hub_damping_nms_rad": "nonneg", "bell_ratio": "nonneg",
                   "hiller_ratio": "pos", "imbalance_mass_kg": "nonneg",
                   "imbalance_radius_m": "nonneg", "track_error_deg": "real"},
    "flybar": {"tip_radius_m": "pos", "paddle_inner_m": "pos", "paddle_chord_m": "pos",
               "paddle_mass_kg": "pos", "rod_mass_kg": "nonneg", "damping_nms_rad": "nonneg",
               "elements": "int"},
    "tail_rotor": {"rotation": "choice:top_blade_aft|top_blade_forward", "radius_m": "pos",
                   "root_cutout_m": "nonneg", "chord_m": "pos", "gear_ratio": "pos",
                   "hub_position_m": "vec3", "polar_inertia_kg_m2": "pos", "elements": "int"},
    "fuselage": {"reference_point_m": "vec3", "length_m": "pos", "width_m": "pos",
                 "height_m": "pos", "frontal_drag_coefficient": "nonneg",
                 "crossflow_drag_coefficient": "nonneg", "boom_diameter_m": "nonneg",
                 "boom_length_m": "nonneg", "added_mass_factor": "nonneg"},
    "horizontal_stabilizer": {"area_m2": "nonneg", "span_m": "pos", "position_m": "vec3",
                              "incidence_deg": "real"},
    "vertical_fin": {"area_m2": "nonneg", "span_m": "pos", "position_m": "vec3"},
    "drive": {"motor_kv_rpm_per_v": "pos", "motor_resistance_ohm": "pos",
              "no_load_current_a": "nonneg", "gear_ratio": "pos", "battery_cells": "int",
              "cell_voltage_v": "pos", "battery_resistance_ohm": "nonneg",
              "shaft_inertia_kg_m2": "pos", "governor_speed_rpm": "pos",
              "governor_kp_per_rad_s": "nonneg", "governor_ki_per_rad": "nonneg"},
    "servos": {"swash_natural_hz": "pos", "swash_damping": "pos", "swash_rate_deg_s": "pos",
               "tail_natural_hz": "pos", "tail_damping": "pos", "tail_rate_deg_s": "pos",
               "ccpm_angles_deg": "vec3", "swash_pitch_per_arm_rad": "pos",
               "tail_pitch_per_arm_rad": "pos", "tail_pitch_center_deg": "real"},
    "tail_gyro": {"mode": "choice:rate|heading_hold|off", "gain_pitch_per_rad_s": "nonneg",
                  "heading_hold_per_s": "nonneg"},
    "rigging": {"servo_gain_error": "vec3", "servo_offset_deg": "vec3",
                "phase_error_deg": "real", "tail_gain_error": "real",
                "tail_offset_deg": "real"},
    "imu": {"position_m": "vec3", "isolator_natural_hz": "pos", "isolator_damping": "pos"},
}


class AirframeError(ValueError):
    """An airframe file or override that cannot be used: file, key and value named."""


def _check(where: str, kind: str, value: Any) -> Any:
    if kind.startswith("choice:"):
        options = kind.split(":", 1)[1].split("|")
        if value not in options:
            raise AirframeError(f"{where} = {value!r}: must be one of {', '.join(options)}")
        return value
    if kind in ("vec3", "vec3pos"):
        if (not isinstance(value, list | tuple) or len(value) != 3 or not all(
                isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                for v in value)):
            raise AirframeError(f"{where} = {value!r}: expected three finite numbers")
        return tuple(float(v) for v in value)
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise AirframeError(f"{where} = {value!r}: expected an integer >= 1")
        return int(value)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise AirframeError(f"{where} = {value!r}: expected a finite number")
    if kind == "pos" and value <= 0:
        raise AirframeError(f"{where} = {value!r}: must be > 0")
    if kind == "nonneg" and value < 0:
        raise AirframeError(f"{where} = {value!r}: must be >= 0")
    return float(value)


@dataclass(frozen=True)
class Airframe:
    """Parameter values and their sources, addressed as "part.name"."""

    values: dict[str, Any]
    sources: dict[str, str]
    path: str
    overrides: dict = field(default_factory=dict)

    def __getitem__(self, key: str) -> Any:
        try:
            return self.values[key]
        except KeyError:
            raise AirframeError(f"{self.path}: no parameter {key!r}") from None

    def part(self, name: str) -> dict[str, Any]:
        """{parameter: value} of one part."""
        prefix = name + "."
        return {k[len(prefix):]: v for k, v in self.values.items() if k.startswith(prefix)}

    def source(self, key: str) -> str:
        return self.sources[key]

    def describe(self) -> dict[str, Any]:
        """Plain description for flight metadata."""
        return {"airframe": self.path, "overrides": dict(self.overrides)}


def load_airframe(path: str | Path | None = None,
                  overrides: Mapping[str, Any] | None = None) -> Airframe:
    """Read and validate an airframe file; `overrides` {"part.name": value} replace values
    (their source becomes "scenario override")."""
    p = Path(path) if path is not None else DEFAULT_AIRFRAME
    if not p.is_file() and path is not None and (AIRFRAME_DIR / f"airframe_{path}.toml").is_file():
        p = AIRFRAME_DIR / f"airframe_{path}.toml"
    try:
        raw = tomllib.loads(p.read_text())
    except FileNotFoundError:
        raise AirframeError(f"airframe file {str(p)!r} not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise AirframeError(f"{p}: not valid TOML ({exc})") from None
    values: dict[str, Any] = {}
    sources: dict[str, str] = {}
    for part, table in raw.items():
        if part not in SCHEMA:
            raise AirframeError(f"{p}: unknown part [{part}] (known: {', '.join(SCHEMA)})")
        if not isinstance(table, Mapping):
            raise AirframeError(f"{p}: [{part}] must be a table")
        for name, entry in table.items():
            where = f"{p.name}: {part}.{name}"
            if name not in SCHEMA[part]:
                raise AirframeError(f"{where}: unknown parameter (known: "
                                    f"{', '.join(SCHEMA[part])})")
            if not (isinstance(entry, Mapping) and "value" in entry and isinstance(
                    entry.get("source"), str) and entry["source"].strip()):
                raise AirframeError(f"{where}: expected {{ value = ..., source = \"...\" }} "
                                    "(every parameter names its source)")
            values[f"{part}.{name}"] = _check(where, SCHEMA[part][name], entry["value"])
            sources[f"{part}.{name}"] = entry["source"]
    missing = [f"{part}.{n}" for part, names in SCHEMA.items() for n in names
               if f"{part}.{n}" not in values]
    if missing:
        raise AirframeError(f"{p}: missing parameters {', '.join(missing)}")
    for key, value in (overrides or {}).items():
        part, _, name = str(key).partition(".")
        if part not in SCHEMA or name not in SCHEMA[part]:
            raise AirframeError(f"override {key!r}: no such airframe parameter "
                                "(use 'part.parameter', e.g. 'main_rotor.chord_m')")
        values[key] = _check(f"override {key}", SCHEMA[part][name], value)
        sources[key] = "scenario override"
    if values["main_rotor.root_cutout_m"] >= values["main_rotor.radius_m"]:
        raise AirframeError(f"{p}: main_rotor.root_cutout_m must be below radius_m")
    if values["flybar.paddle_inner_m"] >= values["flybar.tip_radius_m"]:
        raise AirframeError(f"{p}: flybar.paddle_inner_m must be below tip_radius_m")
    return Airframe(values=values, sources=sources, path=str(p), overrides=dict(overrides or {}))
