"""Truth for scoring simulated flights, from the simulator that made them.

The analysis never reads the truth; scoring does (`--score`). Column truth (`truth_*` in a
flight table) needs nothing; the truth *field* (the wind anywhere, e.g. at a map's cell
centres) comes from a provider module that knows how the flight was simulated. Providers
are named here, as the CLI names the packages that add commands, so `airwake` does not
import the simulator by name anywhere else: `hil_sim.world.truth_field` rebuilds the
wind field and ship of a `hil_sim` flight from its metadata.
"""

from __future__ import annotations

import importlib
import json
from functools import lru_cache

from airwake.estimate.errors import WindEstimationError

PROVIDERS = ("hil_sim.world.truth_field",)


def truth_field(flight_metadata: dict):
    """An object with `relative_flow(t_s, pos_m, euler_rad, frame) -> (N, 6)` and
    `mean_flow_ned(pos_ned_m) -> (N, 3)` (the time-averaged field, for steady-state maps)
    for a simulated flight; WindEstimationError when no provider knows the flight.
    Rebuilding a field synthesises its turbulence (~1 s): the last few are kept, so the
    scores of one flight's map, page and cells build it once."""
    return _truth_field(json.dumps(flight_metadata, sort_keys=True, default=str))


@lru_cache(maxsize=4)
def _truth_field(metadata_json: str):
    flight_metadata = json.loads(metadata_json)
    reasons = []
    for name in PROVIDERS:
        try:
            mod = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            reasons.append(f"{name}: {exc}")
            continue
        try:
            return mod.TruthField.from_metadata(flight_metadata)
        except (ValueError, KeyError, TypeError) as exc:
            reasons.append(f"{name}: {exc}")
    raise WindEstimationError("--score needs a simulated flight whose wind field can be "
                              "rebuilt; " + "; ".join(reasons))
