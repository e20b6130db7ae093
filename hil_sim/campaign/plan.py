"""The flights of a simulated campaign: where each one sweeps, as scenario tables.

    flights = plan_flights(12, betas=(0, 15), seed=7)
    table = flight_scenario(flights[0])             # a scenario extending ship_airwake_b0
    table = calibration_scenario("heli1", seed=7)   # still_air_calibration, its own seed
    table = still_air_scenario("heli1", seed=7, duration_s=100)  # still_air_cruise legs

The deck area a campaign maps (`airwake.campaign.spec.Grid`: the flight deck and 6 m aft
of it, 2-3 m above the deck, 1 m cells) is cut into stations: one lateral line per row
of cells, at the row's centre. The flights at one heading share the stations out
round-robin (flight k of n flies rows k, k + n, ...: with as many flights as rows each
flies one; with fewer, each flies several, aft to fore), each at its own height in the
layer (2.25, 2.5 or 2.75 m above the deck: the rotor hub's, which the map bins; the
script says `point = "hub"` and the pilot flies the CG that much lower), sweeping
across the beam and back (`passes` = 2) at `speed_m_s` (the minimum-jerk leg's peak
speed: ~1.7 s per 1 m cell per pass at 0.6 m/s). Flights go to the headings in turn
(flight i at betas[i % len]) and to the helicopters in turn; each flight has its own seed
(its own turbulence).
"""

from __future__ import annotations

from dataclasses import dataclass

BASE_SCENARIO = "ship_airwake_b0"
CALIBRATION_SCENARIO = "still_air_calibration"
# what each helicopter's still-air wind net learns from beside its calibration flight: the
# cruise legs (the calibration flight's legs are short; the net must have flown the air
# speeds it will read: docs/networks.md); the first 100 s as `make demo` flies them
STILL_AIR_SCENARIO = "still_air_cruise"
STILL_AIR_S = 100.0
TRUTH_MODELS = ("blade_element", "effects")
HEIGHT_OFFSETS_M = (0.0, -0.25, 0.25)
HOVER_S = 3.0


@dataclass(frozen=True)
class PlannedFlight:
    name: str
    beta_deg: float
    helicopter: str
    seed: int
    stations_x_m: tuple[float, ...]
    height_m: float
    half_width_m: float
    speed_m_s: float
    passes: int = 2


def stations(grid=None) -> list[float]:
    """x of each row of the deck area's cells (their centres), aft to fore."""
    from airwake.campaign.spec import Grid

    grid = grid or Grid()
    return sorted({(ix + 0.5) * grid.cell_m for ix, _, _ in grid.deck_cells()})


def helicopter_names(n: int) -> list[str]:
    return [f"heli{i + 1}" for i in range(n)]


def plan_flights(n: int, betas, seed: int, helicopters: int = 1, speed_m_s: float = 0.6,
                 grid=None) -> list[PlannedFlight]:
    """`n` flights spread over `betas` and the stations (module docstring)."""
    from airwake.campaign.spec import Grid

    if n < 1:
        raise ValueError(f"--flights {n}: must be >= 1")
    if not betas:
        raise ValueError("--betas: give at least one heading")
    if not 0.1 <= speed_m_s <= 3.0:
        raise ValueError(f"--speed {speed_m_s}: must be within 0.1 ... 3 m/s")
    grid = grid or Grid()
    rows = stations(grid)
    lo, hi = grid.height_m
    mid = 0.5 * (lo + hi)
    heli = helicopter_names(helicopters)
    by_beta: dict[float, list[int]] = {}
    for i in range(n):
        by_beta.setdefault(float(betas[i % len(betas)]), []).append(i)
    out = []
    for beta, members in by_beta.items():
        m = len(members)
        for k, i in enumerate(members):
            mine = rows[k % len(rows)::m] if m <= len(rows) else [rows[k % len(rows)]]
            out.append(PlannedFlight(
                name=f"beta{beta:g}_{k + 1:02d}", beta_deg=beta, helicopter=heli[i % len(heli)],
                seed=seed * 1000 + i, stations_x_m=tuple(mine),
                height_m=mid + HEIGHT_OFFSETS_M[k % len(HEIGHT_OFFSETS_M)] * (hi - lo),
                half_width_m=grid.beam_m / 2 + 0.25, speed_m_s=speed_m_s))
    return sorted(out, key=lambda f: (f.beta_deg, f.name))


def _helicopter_table(truth: str | None) -> dict:
    # (imported here: the CLI builds its parser from this module, and must stay light)
    from hil_sim.world.scenario import TRUTH_PILOTS

    if truth is None:
        return {}
    if truth not in TRUTH_MODELS:
        raise ValueError(f"--truth {truth!r}: one of {', '.join(TRUTH_MODELS)}")
    return {"helicopter": {"model": truth, "pilot": TRUTH_PILOTS[truth]}}


def flight_scenario(f: PlannedFlight, truth: str | None = None,
                    duration_s: float | None = None) -> dict:
    """The scenario table of one flight (extends `BASE_SCENARIO`; lists replace its)."""
    from hil_sim.world.pilot import pilot_from_dict, script_duration

    z = -f.height_m
    y = f.half_width_m
    segments = [{"type": "hover", "duration_s": HOVER_S}]
    for x in f.stations_x_m:
        segments.append({"type": "sweep", "a_m": [x, -y, z], "b_m": [x, y, z],
                         "passes": f.passes, "speed_m_s": f.speed_m_s})
    segments.append({"type": "hover", "duration_s": 2.0})
    # the heights are the rotor hub's (what the map bins): the pilot flies its CG lower
    pilot = {"frame": "ship", "point": "hub", "start_m": [f.stations_x_m[0], -y, z],
             "segments": segments}
    planned = script_duration(pilot_from_dict(pilot)) + 1.0
    xs = ", ".join(f"{x:g}" for x in f.stations_x_m)
    return {"extends": BASE_SCENARIO,
            "description": f"campaign flight {f.name}: relative wind from {f.beta_deg:g} deg, "
                           f"lateral sweeps at x = {xs} m, {f.height_m:g} m above the deck",
            "duration_s": round(min(planned, duration_s) if duration_s else planned, 3),
            "seed": f.seed, **_helicopter_table(truth),
            "wind": {"relative_wind_heading_deg": f.beta_deg}, "pilot": pilot}


def calibration_scenario(helicopter: str, seed: int, truth: str | None = None,
                         duration_s: float | None = None) -> dict:
    """The still-air calibration flight of one helicopter."""
    table = {"extends": CALIBRATION_SCENARIO,
             "description": f"still-air calibration flight of {helicopter}",
             "seed": seed, **_helicopter_table(truth)}
    if duration_s:
        table["duration_s"] = float(duration_s)
    return table


def still_air_scenario(helicopter: str, seed: int, truth: str | None = None,
                       duration_s: float = STILL_AIR_S) -> dict:
    """The still-air cruise flight of one helicopter, for its still-air wind net."""
    return {"extends": STILL_AIR_SCENARIO,
            "description": f"still-air cruise legs of {helicopter} (its still-air wind net)",
            "seed": seed, "duration_s": float(duration_s), **_helicopter_table(truth)}
