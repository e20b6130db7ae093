"""Scenario files: loader and validator (`hil_sim/scenarios/*.toml`, docs/scenarios.md).

    scenario = load_scenario("still_air_calibration")       # by name (package dir)
    scenario = load_scenario("my_flight.toml")               # or by path
    scenario = scenario.replace(duration_s=10.0, seed=3)

A scenario is one TOML file; `extends = "other"` starts from another scenario (by name,
or a path relative to this file) and overrides it key by key (tables merge, everything
else - lists included - is replaced). Top-level keys:

    extends, description, duration_s, seed, rate_hz, wind_rate_hz
    [helicopter]  model ("effects" | "blade_element"), pilot ("full_state" | "crossover"),
                  spec ("truth" | shipped host spec | path; effects), airframe (name | path;
                  blade_element), [helicopter.overrides]
    [site]        type = "hall" | "field" | "ship", temperature_c, pressure_hpa
    [ship]        hil_sim.world.ship.ShipConfig (site "ship" only)
    [wind]        a `build_wind_field` table (type = still_air | uniform | fans_indoor | ...)
    [pilot]       hil_sim.world.pilot.PilotConfig + [[pilot.segments]]
    [sensors]     SensorsConfig below (each device's config table)
    [hidden.*]    hil_sim.world.hidden configs (ground_effect, lever_arm, ...)
    [faults]      link impairments for the SIL boards (validated here, applied by hil_sim.boards)

Unknown keys and bad values raise `ScenarioError` naming the file, the key path and the
value.
"""

from __future__ import annotations

import copy
import dataclasses
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from airwake.errors import AirwakeError

from hil_sim.sensors.config import (
    check_choice,
    check_finite,
    check_nonnegative,
    check_positive,
    check_range,
    config_from_dict,
    config_to_dict,
)
from hil_sim.sensors.imu import RotorVibration
from hil_sim.sensors.rc import RcConfig, TailServoConfig
from hil_sim.sensors.rotor import RotorTachConfig
from hil_sim.sensors.rtk import RtkConfig
from hil_sim.sensors.vn200 import Vn200Config
from hil_sim.world.hidden import HiddenConfig, hidden_from_dict
from hil_sim.world.pilot import PilotConfig, pilot_from_dict
from hil_sim.world.ship import ShipConfig

SCENARIO_DIR = Path(__file__).resolve().parents[1] / "scenarios"
TOP_LEVEL_KEYS = ("extends", "description", "duration_s", "seed", "rate_hz", "wind_rate_hz",
                  "helicopter", "site", "ship", "wind", "pilot", "sensors", "hidden", "faults")
SITE_TYPES = ("hall", "field", "ship")
BOARDS = ("losa", "marker", "rover", "base")
Vec3 = tuple[float, float, float]


class ScenarioError(AirwakeError):
    """A scenario that cannot be read or is invalid (file, key path and value named)."""


# ---------------------------------------------------------------------------
# Sections
# ---------------------------------------------------------------------------


TRUTH_MODELS = ("effects", "blade_element")
PILOT_MODELS = ("full_state", "crossover")
# who flies each truth where a command picks the truth: the blade-element airframe the
# human-like crossover pilot (a pilot slower than the turbulence, as the shipped scenarios
# say), our own effect model the LQR it was written for
TRUTH_PILOTS = {"blade_element": "crossover", "effects": "full_state"}


@dataclass(frozen=True)
class HelicopterConfig:
    """`[helicopter]`: which truth flies and who flies it.

    `model`: "effects" (the host's effect catalogue with its own "truth" parameters and
    the hidden effects; for tests that need a known catalogue effect) or "blade_element"
    (hil_sim.world.rotorcraft: the independent blade-element helicopter of `airframe`).
    `pilot`: "full_state" (an LQR that sees the true state) or "crossover" (a human-like
    pilot on the deck, hil_sim.world.crossover_pilot). `overrides` are "effect.param"
    (effects) or "part.param" (an airframe parameter, blade_element) = number."""

    spec: str = "truth"
    overrides: dict = field(default_factory=dict)
    model: str = "effects"
    airframe: str = "600"
    pilot: str = "full_state"

    def __post_init__(self) -> None:
        check_choice("model", self.model, TRUTH_MODELS)
        check_choice("pilot", self.pilot, PILOT_MODELS)
        if not isinstance(self.airframe, str) or not self.airframe:
            raise ValueError(f"airframe = {self.airframe!r}: expected an airframe name or path")
        if not isinstance(self.spec, str) or not self.spec:
            raise ValueError(f"spec = {self.spec!r}: expected a spec name or path")
        for k, v in self.overrides.items():
            if not (isinstance(k, str) and "." in k):
                raise ValueError(f"overrides: key {k!r} must be 'effect.parameter'")
            if isinstance(v, bool) or not isinstance(v, int | float):
                raise ValueError(f"overrides.{k} = {v!r}: expected a number")


@dataclass(frozen=True)
class SiteConfig:
    """Where the flight happens: indoor "hall" (no GNSS: no RTK), outdoor "field" (flat
    ground at D = 0, RTK base on a tripod), or a "ship" (RTK base and base INS aboard)."""

    type: str = "hall"
    temperature_c: float = 20.0
    pressure_hpa: float = 1013.25

    def __post_init__(self) -> None:
        check_choice("type", self.type, SITE_TYPES)
        check_range("temperature_c", self.temperature_c, -40.0, 50.0)
        check_range("pressure_hpa", self.pressure_hpa, 800.0, 1100.0)


@dataclass(frozen=True)
class SensorsConfig:
    """Device configs (hil_sim.sensors dataclasses) and mounting positions.

    `vibration_scale` scales `RotorVibration.typical_600_class()` into the rover VN200
    unless `vn200.imu.vibration` is given explicitly (0 = off). The RTK runs at the field
    and ship sites (`rtk_enabled` forces it on/off). Positions: `rover_antenna_m` body FRD
    from the CG; `base_antenna_m` NED at the field, ship frame on a ship; `base_ins_m`
    ship frame; `base_antenna_height_m` the base antenna above the ground / deck that
    the flight-table builder uses for the height above ground."""

    vn200: Vn200Config = field(default_factory=Vn200Config)
    rc: RcConfig = field(default_factory=RcConfig)
    tail_servo: TailServoConfig = field(default_factory=TailServoConfig)
    rotor: RotorTachConfig = field(default_factory=RotorTachConfig)
    rtk: RtkConfig = field(default_factory=RtkConfig)
    base_vn200: Vn200Config = field(default_factory=lambda: Vn200Config(startup_offset_s=30.0))
    vibration_scale: float = 0.0
    rtk_enabled: bool | None = None
    rover_antenna_m: Vec3 = (-0.30, 0.0, -0.20)
    base_antenna_m: Vec3 = (-20.0, 0.0, -1.0)
    base_antenna_height_m: float | None = None
    base_ins_m: Vec3 = (2.0, 0.0, -1.6)

    def __post_init__(self) -> None:
        check_range("vibration_scale", self.vibration_scale, 0.0, 5.0)
        for name in ("rover_antenna_m", "base_antenna_m", "base_ins_m"):
            check_finite(name, getattr(self, name))
        if self.base_antenna_height_m is not None:
            check_finite("base_antenna_height_m", self.base_antenna_height_m)


@dataclass(frozen=True)
class LinkFaults:
    """Impairments of one board's link (reserved for the SIL boards layer)."""

    byte_loss_probability: float = 0.0
    bit_flip_probability: float = 0.0
    throttle_baud: int | None = None

    def __post_init__(self) -> None:
        check_range("byte_loss_probability", self.byte_loss_probability, 0.0, 1.0)
        check_range("bit_flip_probability", self.bit_flip_probability, 0.0, 1.0)
        if self.throttle_baud is not None:
            check_positive("throttle_baud", self.throttle_baud)


@dataclass(frozen=True)
class FaultEvent:
    """A timed event on one board: a stall/unplug lasting `duration_s`, or a reset."""

    board: str
    at_s: float
    duration_s: float = 0.0

    def __post_init__(self) -> None:
        check_choice("board", self.board, BOARDS)
        check_nonnegative("at_s", self.at_s)
        check_nonnegative("duration_s", self.duration_s)


@dataclass(frozen=True)
class FaultsConfig:
    """`[faults]`: defaults for every link, per-board overrides, and timed events.
    Validated here; the SIL boards layer applies them (`sim table` has no links)."""

    byte_loss_probability: float = 0.0
    bit_flip_probability: float = 0.0
    throttle_baud: int | None = None
    boards: dict = field(default_factory=dict)  # board -> LinkFaults
    stalls: tuple[FaultEvent, ...] = ()
    unplugs: tuple[FaultEvent, ...] = ()
    resets: tuple[FaultEvent, ...] = ()

    def link(self, board: str) -> LinkFaults:
        base = LinkFaults(self.byte_loss_probability, self.bit_flip_probability,
                          self.throttle_baud)
        return self.boards.get(board, base)

    @property
    def any(self) -> bool:
        return bool(self.byte_loss_probability or self.bit_flip_probability
                    or self.throttle_baud or self.boards or self.stalls or self.unplugs
                    or self.resets)


def faults_from_dict(table: Mapping[str, Any] | None, where: str = "faults") -> FaultsConfig:
    if table is None:
        return FaultsConfig()
    if not isinstance(table, Mapping):
        raise ValueError(f"{where}: expected a table, got {table!r}")
    link_keys = [f.name for f in dataclasses.fields(LinkFaults)]
    known = link_keys + ["stalls", "unplugs", "resets", *BOARDS]
    for key in table:
        if key not in known:
            raise ValueError(f"{where}: unknown key {key!r} (known: {', '.join(known)})")
    base = config_from_dict(LinkFaults, {k: table[k] for k in link_keys if k in table}, where)
    boards = {}
    for b in BOARDS:
        if b in table:
            merged = {**config_to_dict(base), **dict(table[b])} if isinstance(
                table[b], Mapping) else table[b]
            boards[b] = config_from_dict(LinkFaults, merged, f"{where}.{b}")
    events = {}
    for kind in ("stalls", "unplugs", "resets"):
        items = table.get(kind, [])
        if not isinstance(items, list):
            raise ValueError(f"{where}.{kind}: expected a list of tables")
        events[kind] = tuple(config_from_dict(FaultEvent, e, f"{where}.{kind}[{i}]")
                             for i, e in enumerate(items))
    return FaultsConfig(base.byte_loss_probability, base.bit_flip_probability,
                        base.throttle_baud, boards, **events)


# ---------------------------------------------------------------------------
# The scenario
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Scenario:
    """A validated scenario (module docstring). `table` is the merged TOML table."""

    name: str
    path: Path | None
    description: str
    duration_s: float
    seed: int
    rate_hz: float
    wind_rate_hz: float
    helicopter: HelicopterConfig
    site: SiteConfig
    ship: ShipConfig | None
    wind: dict
    pilot: PilotConfig
    sensors: SensorsConfig
    hidden: HiddenConfig
    faults: FaultsConfig
    table: dict = field(repr=False, compare=False, default_factory=dict)

    def replace(self, **changes) -> Scenario:
        """A copy with top-level values changed (validated like the file's)."""
        for key, value in changes.items():
            _check_top(key, value)
        return dataclasses.replace(self, **changes)

    def with_helicopter(self, **changes) -> Scenario:
        """A copy with `[helicopter]` values changed (model, pilot, ...; validated like
        the file's): who flies it, e.g. `with_helicopter(model="effects",
        pilot="full_state")` for our own model."""
        return dataclasses.replace(self, helicopter=dataclasses.replace(self.helicopter,
                                                                        **changes))

    @property
    def rtk_enabled(self) -> bool:
        if self.sensors.rtk_enabled is not None:
            return self.sensors.rtk_enabled
        return self.site.type in ("field", "ship")

    def describe(self) -> dict:
        """Plain dict of the resolved scenario (for metadata)."""
        return {
            "name": self.name, "path": None if self.path is None else str(self.path),
            "description": self.description, "duration_s": self.duration_s,
            "seed": self.seed, "rate_hz": self.rate_hz, "wind_rate_hz": self.wind_rate_hz,
            "helicopter": {"model": self.helicopter.model, "pilot": self.helicopter.pilot,
                           "spec": self.helicopter.spec, "airframe": self.helicopter.airframe,
                           "overrides": dict(self.helicopter.overrides)},
            "site": self.site.type,
            "ship": None if self.ship is None else config_to_dict(self.ship),
            "wind": dict(self.wind), "pilot": config_to_dict(self.pilot),
            "sensors": config_to_dict(self.sensors), "hidden": self.hidden.to_dict(),
            "faults": config_to_dict(self.faults),
        }


def _check_top(key: str, value) -> None:
    if key == "duration_s":
        check_positive("duration_s", value)
    elif key == "seed":
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise ValueError(f"seed = {value!r}: expected an integer >= 0")
    elif key == "rate_hz":
        check_range("rate_hz", value, 1000.0, 20000.0)
    elif key == "wind_rate_hz":
        check_range("wind_rate_hz", value, 10.0, 1000.0)


def scenario_names() -> list[str]:
    """Names of the scenarios shipped in hil_sim/scenarios/."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.toml"))


def find_scenario(name_or_path: str | Path, relative_to: Path | None = None) -> Path:
    """A scenario file by path, or by name in the package's scenario directory."""
    text = str(name_or_path)
    candidates = []
    p = Path(text)
    if p.suffix == ".toml" or p.exists() or "/" in text:
        candidates.append(p if p.is_absolute() or relative_to is None else relative_to / p)
        candidates.append(p)
    else:
        if relative_to is not None:
            candidates.append(relative_to / f"{text}.toml")
        candidates.append(SCENARIO_DIR / f"{text}.toml")
    for c in candidates:
        if c.is_file():
            return c.resolve()
    raise ScenarioError(f"scenario {text!r} not found (looked for {candidates[0]}); "
                        f"shipped scenarios: {', '.join(scenario_names())}")


def _merge(base: dict, over: Mapping) -> dict:
    out = copy.deepcopy(base)
    for k, v in over.items():
        if isinstance(v, Mapping) and isinstance(out.get(k), dict):
            out[k] = _merge(out[k], v)
        else:
            out[k] = copy.deepcopy(v)
    return out


def _read_table(path: Path, chain: tuple[Path, ...] = ()) -> dict:
    if path in chain:
        names = " -> ".join(str(p.name) for p in (*chain, path))
        raise ScenarioError(f"{path}: extends loops ({names})")
    try:
        data = tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise ScenarioError(f"scenario file {path} not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    parent = data.pop("extends", None)
    if parent is None:
        return data
    if not isinstance(parent, str):
        raise ScenarioError(f"{path}: extends = {parent!r}: expected a scenario name or path")
    base = _read_table(find_scenario(parent, path.parent), (*chain, path))
    return _merge(base, data)


def load_scenario(name_or_path: str | Path) -> Scenario:
    """Load, merge (`extends`) and validate a scenario (ScenarioError on any problem)."""
    path = find_scenario(name_or_path)
    table = _read_table(path)
    try:
        return scenario_from_table(table, name=path.stem, path=path)
    except ValueError as exc:
        raise ScenarioError(f"{path}: {exc}") from None


def scenario_from_table(table: Mapping[str, Any], name: str = "scenario",
                        path: Path | None = None) -> Scenario:
    """Validate a merged scenario table (ValueError naming the key path and value)."""
    for key in table:
        if key not in TOP_LEVEL_KEYS:
            raise ValueError(f"unknown key {key!r} (known: {', '.join(TOP_LEVEL_KEYS)})")
    top = {"duration_s": table.get("duration_s", 60.0), "seed": table.get("seed", 0),
           "rate_hz": table.get("rate_hz", 1000.0),
           "wind_rate_hz": table.get("wind_rate_hz", 100.0)}
    for k, v in top.items():
        if k != "seed" and (isinstance(v, bool) or not isinstance(v, int | float)):
            raise ValueError(f"{k} = {v!r}: expected a number")
        _check_top(k, v)
    description = table.get("description", "")
    if not isinstance(description, str):
        raise ValueError(f"description = {description!r}: expected a string")
    heli_t = dict(table.get("helicopter", {}))
    helicopter = config_from_dict(HelicopterConfig, heli_t, "helicopter")
    helicopter = _validate_helicopter(helicopter, path)
    site = config_from_dict(SiteConfig, table.get("site"), "site")
    ship = None
    if site.type == "ship":
        ship = config_from_dict(ShipConfig, table.get("ship", {}), "ship")
    elif "ship" in table:
        raise ValueError(f"ship: a [ship] table needs site.type = 'ship' (site is "
                         f"{site.type!r})")
    wind = dict(table.get("wind", {"type": "still_air"}))
    _validate_wind(wind)
    if wind.get("type") == "ship_airwake" and ship is None:
        raise ValueError("wind.type = 'ship_airwake': needs site.type = 'ship'")
    pilot = pilot_from_dict(table.get("pilot"), "pilot")
    if pilot.frame == "ship" and ship is None:
        raise ValueError("pilot.frame = 'ship': needs site.type = 'ship'")
    sensors = config_from_dict(SensorsConfig, table.get("sensors"), "sensors")
    hidden = hidden_from_dict(table.get("hidden"), "hidden")
    faults = faults_from_dict(table.get("faults"), "faults")
    return Scenario(name=name, path=path, description=description,
                    duration_s=float(top["duration_s"]), seed=int(top["seed"]),
                    rate_hz=float(top["rate_hz"]), wind_rate_hz=float(top["wind_rate_hz"]),
                    helicopter=helicopter, site=site, ship=ship, wind=wind, pilot=pilot,
                    sensors=sensors, hidden=hidden, faults=faults, table=dict(table))


def _validate_helicopter(heli: HelicopterConfig, path: Path | None) -> HelicopterConfig:
    """The spec (effects) or airframe (blade_element) loads and every override names a
    parameter in range; a relative path is resolved against the scenario file's
    directory."""
    if heli.model == "blade_element":
        from hil_sim.world.rotorcraft.airframe import load_airframe

        airframe = heli.airframe
        if path is not None and ("/" in airframe or airframe.endswith(".toml")) and not Path(
                airframe).is_absolute():
            airframe = str((path.parent / airframe).resolve())
            heli = dataclasses.replace(heli, airframe=airframe)
        try:
            load_airframe(airframe, heli.overrides)
        except ValueError as exc:
            raise ValueError(f"helicopter.airframe = {heli.airframe!r}: {exc}") from None
        return heli
    from airwake.heli import load_spec
    from airwake.heli.spec import SpecError

    from hil_sim.world.truth import resolve_spec

    spec = resolve_spec(heli.spec)
    if isinstance(spec, str) and path is not None and ("/" in spec or spec.endswith(".toml")):
        if not Path(spec).is_absolute():
            spec = str((path.parent / spec).resolve())
            heli = dataclasses.replace(heli, spec=spec)
    try:
        model = load_spec(spec)
        if heli.overrides:
            model.with_parameters(dict(heli.overrides))
    except SpecError as exc:
        raise ValueError(f"helicopter.spec = {heli.spec!r}: {exc}") from None
    except ValueError as exc:
        raise ValueError(f"helicopter.overrides: {exc}") from None
    return heli


def _validate_wind(wind: dict) -> None:
    from hil_sim.world.wind import WIND_FIELD_TYPES

    kind = wind.get("type")
    if kind not in WIND_FIELD_TYPES:
        raise ValueError(f"wind.type = {kind!r}: must be one of {', '.join(WIND_FIELD_TYPES)}")
    config_from_dict(WIND_FIELD_TYPES[kind], {k: v for k, v in wind.items() if k != "type"},
                     "wind")


def vibration_for(sensors: SensorsConfig) -> RotorVibration:
    """The rover IMU's rotor vibration: explicit config, else the scaled typical level."""
    explicit = sensors.vn200.imu.vibration
    if explicit.enabled or sensors.vibration_scale == 0.0:
        return explicit
    typical = RotorVibration.typical_600_class()
    s = sensors.vibration_scale

    def scale(v):
        return tuple(s * x for x in v)

    return dataclasses.replace(typical, accel_1p_m_s2=scale(typical.accel_1p_m_s2),
                               accel_2p_m_s2=scale(typical.accel_2p_m_s2),
                               gyro_1p_rad_s=scale(typical.gyro_1p_rad_s),
                               gyro_2p_rad_s=scale(typical.gyro_2p_rad_s))
