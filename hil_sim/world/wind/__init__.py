"""Wind fields for the truth world (see docs/wind-fields.md).

Build one from a scenario's `[wind]` table:

    field = build_wind_field({"type": "ship_airwake", "relative_wind_heading_deg": 15},
                             rng=np.random.default_rng(seed), ship=ship)
    field.velocity_ned(t_s, pos_ned_m)             # (N, 3) air velocity, NED
    field.local_wind(t_s, hub_ned_m, quat_wxyz)    # (N, 6) eq 5.3, body frame

Types: `still_air`, `uniform`, `fans_indoor`, `ship_airwake`. The other keys are the
fields of the type's config dataclass; unknown keys and bad values raise `ValueError`
naming the key and value.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from hil_sim.sensors.config import config_from_dict
from hil_sim.world.ship import Ship
from hil_sim.world.wind.airwake import ShipAirwake, ShipAirwakeConfig
from hil_sim.world.wind.base import (
    DEFAULT_FIT,
    LOCAL_WIND_COLUMNS,
    HeldLocalWind,
    LocalWindFit,
    WindField,
)
from hil_sim.world.wind.fans import FansIndoor, FansIndoorConfig
from hil_sim.world.wind.simple import StillAir, StillAirConfig, UniformWind, UniformWindConfig

WIND_FIELD_TYPES: dict[str, type] = {
    "still_air": StillAirConfig,
    "uniform": UniformWindConfig,
    "fans_indoor": FansIndoorConfig,
    "ship_airwake": ShipAirwakeConfig,
}

__all__ = [
    "DEFAULT_FIT",
    "LOCAL_WIND_COLUMNS",
    "WIND_FIELD_TYPES",
    "FansIndoor",
    "FansIndoorConfig",
    "HeldLocalWind",
    "LocalWindFit",
    "ShipAirwake",
    "ShipAirwakeConfig",
    "StillAir",
    "StillAirConfig",
    "UniformWind",
    "UniformWindConfig",
    "WindField",
    "build_wind_field",
]


def build_wind_field(
    config: Mapping[str, Any],
    *,
    rng: np.random.Generator,
    ship: Ship | None = None,
    where: str = "wind",
) -> WindField:
    """A wind field from a plain table with a `type` key (see module doc).

    `rng` seeds the turbulence (the only random part); `ship` is required by
    `ship_airwake` in a scenario with a moving ship (a default `Ship()` otherwise).
    """
    if not isinstance(config, Mapping):
        raise ValueError(f"{where}: expected a table with a 'type' key, got {config!r}")
    kind = config.get("type")
    if kind not in WIND_FIELD_TYPES:
        raise ValueError(f"{where}.type = {kind!r}: must be one of {', '.join(WIND_FIELD_TYPES)}")
    settings = {k: v for k, v in config.items() if k != "type"}
    cfg = config_from_dict(WIND_FIELD_TYPES[kind], settings, where)
    if kind == "still_air":
        return StillAir(cfg)
    if kind == "uniform":
        return UniformWind(cfg, rng)
    if kind == "fans_indoor":
        return FansIndoor(cfg, rng)
    return ShipAirwake(cfg, rng, ship)
