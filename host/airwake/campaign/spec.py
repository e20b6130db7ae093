"""The campaign file (TOML, docs/campaigns.md): read and validated before anything runs.

    campaign = load_campaign("campaign.toml")
    campaign.flights          # (Flight, ...) name, source, helicopter, beta_deg, day
    campaign.helicopters      # {name: Helicopter(model, calibration, still_air)}
    campaign.steps            # the steps that run, in order
    campaign.options["estimate"]   # keyword options of that step's API call

    name = "..."                         description = "..."
    [grid]           cell_m, layer_m, min_seconds, deck_length_m, beam_m, hangar_length_m,
                     hangar_width_m, aft_m, height_m = [lo, hi]
    [steps]          run = ["export", "calibrate", "still_air_net", "estimate", "map",
                            "report"]
    [steps.<step>]   that step's options (STEP_OPTIONS)
    [helicopters.<name>]  model = spec (shipped name or path), calibration = still-air flight,
                     still_air = [more still-air flights for its still-air wind net]
    [[flights]]      path = glob, helicopter?, beta_deg?, day?

Paths are relative to the campaign file. A flight's beta, helicopter and day come from
its entry, else from its metadata (a `campaign` table: what `airwake sim campaign`
writes; beta also from a simulated ship flight's relative wind), else (helicopter) the
campaign's only helicopter. Every problem is one `CampaignError` naming the file, the key
and the value, raised before any step runs.

The estimate: with the `still_air_net` step, a helicopter with a `still_air` list (speed
legs in still air) gets a still-air wind net on those flights and its calibration flight,
and its flights' wind is `method = "anchored"` unless the file says otherwise: the net's
mean flow, its interval widened by the helicopter's model, anchors the model's smoother,
which reads the rotation given it (what `make demo` maps: on a helicopter the model was
not written for the model's own mean flow is biased, docs/calibration.md). A helicopter
without a `still_air` list keeps the smoother (a net on the calibration flight's short
legs alone reads ~80 % of a steady headwind, docs/networks.md); `method = "anchored"`
named in the file anchors every flying helicopter on a net of its still-air flights (the
calibration flight at least) and refuses one that has none.
"""

from __future__ import annotations

import glob
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from airwake.campaign.errors import CampaignError

STEPS = ("export", "calibrate", "still_air_net", "estimate", "map", "report")
TABLE_SUFFIXES = (".parquet", ".pq", ".csv")
TOP_KEYS = ("name", "description", "grid", "steps", "helicopters", "flights")
FLIGHT_KEYS = ("path", "helicopter", "beta_deg", "day")
HELICOPTER_KEYS = ("model", "calibration", "still_air")
# the estimate with a still-air net: the net's mean flow (its interval widened by the
# helicopter's model) anchors the model's smoother, which reads the rotation given it
ANCHORED = "anchored"


@dataclass(frozen=True)
class Option:
    """One step option: its TOML type ("float", "int", "bool", "str", "strs", "floats",
    "path": a file relative to the campaign file),
    bounds or choices, the length of a list, and the keyword of the API call it feeds."""

    kind: str
    api: str
    lo: float | None = None
    hi: float | None = None
    choices: tuple[str, ...] = ()
    length: int | None = None
    lo_open: bool = False


# what each step accepts: the options of `airwake export`, `calibrate`, `nets train`,
# `wind estimate`, `wind map` and `model report` (their docs), spelled as in those commands
STEP_OPTIONS: dict[str, dict[str, Option]] = {
    "export": {
        "latency_correction": Option("bool", "remove_stamp_latency"),
        "ned_origin": Option("floats", "ned_origin_lla", length=3),
        "base_antenna_height_m": Option("float", "base_antenna_height_above_deck_m"),
        "base_antenna_ship_m": Option("floats", "base_antenna_ship_xy_m", length=2),
        "rover_antenna_to_hub_m": Option("floats", "rover_antenna_to_hub_frd_m", length=3),
        "tracker_height_m": Option("float", "tracker_height_above_ground_m"),
    },
    "calibrate": {
        "method": Option("str", "method", choices=("lsq", "pso")),
        "params": Option("strs", "params"),
        "window_s": Option("float", "window_s", lo=0.0, lo_open=True),
        "warmup_s": Option("float", "warmup_s", lo=0.0),
        "max_windows": Option("int", "max_windows", lo=1),
        "seed": Option("int", "seed", lo=0),
        "particles": Option("int", "particles", lo=2),
        "iterations": Option("int", "iterations", lo=1),
        "pso_windows": Option("int", "pso_windows", lo=0),
        "max_nfev": Option("int", "max_nfev", lo=1),
        "cutoff_hz": Option("float", "cutoff_hz", lo=0.0),
        # then `model diagnose` + `model add` of the effect it names (airwake.calibrate.sequence)
        "discrepancy": Option("bool", "discrepancy"),
    },
    "still_air_net": {
        "seed": Option("int", "seed", lo=0),
        "max_rows": Option("int", "max_rows", lo=1000),
    },
    "estimate": {
        "method": Option("str", "method", choices=("smoother", "apf", "net", ANCHORED)),
        "net": Option("path", "net"),
        "cutoff_hz": Option("float", "cutoff_hz", lo=0.0),
        "rate_hz": Option("float", "rate_hz", lo=0.0, lo_open=True),
        "em_passes": Option("int", "em_passes", lo=1),
        "airspeed_m_s": Option("float", "airspeed_m_s", lo=0.0, lo_open=True),
        "ins_velocity_std": Option("float", "ins_velocity_std", lo=0.0),
        "particles": Option("int", "n_particles", lo=2),
        "seed": Option("int", "seed", lo=0),
        "sigma": Option("float", "sigma", lo=0.0, lo_open=True),
        "resampler": Option("str", "resampler",
                            choices=("systematic", "stratified", "roulette", "multinomial")),
        "jitter": Option("float", "jitter", lo=0.0),
    },
    "map": {
        "min_seconds": Option("float", "min_seconds", lo=0.0),
        "reference_speed_m_s": Option("float", "u_ref", lo=0.0, lo_open=True),
        "score": Option("bool", "score"),
    },
    "report": {
        "lowpass_hz": Option("float", "lowpass_hz", lo=0.0),
        "skip_start_s": Option("float", "skip_start_s", lo=0.0),
        "windows": Option("int", "free_sim_windows", lo=0),
        "window_s": Option("float", "free_sim_window_s", lo=0.0, lo_open=True),
        "sindy": Option("bool", "sindy"),
    },
}


@dataclass(frozen=True)
class Grid:
    """The ship-frame grid every map and merged map uses, and the deck area the coverage
    counts: the flight deck (x in [-deck_length, 0], |y| <= beam / 2) and `aft_m` behind
    it, between `height_m` above the deck."""

    cell_m: float = 1.0
    layer_m: float = 1.0
    min_seconds: float = 2.0
    deck_length_m: float = 6.0
    beam_m: float = 7.3
    hangar_length_m: float = 8.0
    hangar_width_m: float = 6.0
    aft_m: float = 6.0
    height_m: tuple[float, float] = (2.0, 3.0)

    def ship(self):
        from airwake.estimate.map_plots import ShipOutline

        return ShipOutline(self.deck_length_m, self.beam_m, self.hangar_length_m,
                           self.hangar_width_m)

    def deck_cells(self) -> list[tuple[int, int, int]]:
        """(ix, iy, iz) of the deck area's cells: those whose centre lies in it."""
        c, h = self.cell_m, self.layer_m
        x0, x1 = -(self.deck_length_m + self.aft_m), 0.0
        y1 = self.beam_m / 2
        lo, hi = self.height_m
        eps = 1e-9
        xs = [i for i in range(math.floor(x0 / c) - 1, math.ceil(x1 / c) + 1)
              if x0 - eps <= (i + 0.5) * c <= x1 + eps]
        ys = [j for j in range(math.floor(-y1 / c) - 1, math.ceil(y1 / c) + 1)
              if abs((j + 0.5) * c) <= y1 + eps]
        # z is down from the deck: height above it is -z
        zs = [k for k in range(math.floor(-hi / h) - 1, math.ceil(-lo / h) + 1)
              if lo - eps <= -(k + 0.5) * h <= hi + eps]
        return [(i, j, k) for i in xs for j in ys for k in zs]


@dataclass(frozen=True)
class Source:
    """One input file: a flight table or a daemon recording (directory or .mcap segment)."""

    path: Path
    kind: str  # "table" | "recording"


@dataclass(frozen=True)
class Helicopter:
    name: str
    model: str  # shipped spec name or absolute path
    calibration: Source | None = None
    still_air: tuple[Source, ...] = ()  # more still-air flights for its still-air net

    @property
    def still_air_flights(self) -> tuple[Source, ...]:
        """What its still-air wind net learns from: the calibration flight and the rest."""
        return ((self.calibration,) if self.calibration else ()) + self.still_air


@dataclass(frozen=True)
class Flight:
    name: str
    source: Source
    helicopter: str
    beta_deg: float
    day: str = ""


@dataclass(frozen=True)
class Campaign:
    path: Path
    name: str
    description: str
    grid: Grid
    steps: tuple[str, ...]
    options: dict = field(default_factory=dict)  # step -> {api keyword: value}
    helicopters: dict = field(default_factory=dict)  # name -> Helicopter
    flights: tuple[Flight, ...] = ()

    @property
    def betas(self) -> list[float]:
        return sorted({f.beta_deg for f in self.flights})

    def estimate_method(self, helicopter: str) -> str:
        """How the flights of `helicopter` are estimated (module docstring): the file's
        method, else anchored for a helicopter with a `still_air` list when the
        `still_air_net` step runs, else the smoother."""
        given = self.options["estimate"].get("method")
        if given is not None:
            return given
        anchored = "still_air_net" in self.steps and self.helicopters[helicopter].still_air
        return ANCHORED if anchored else "smoother"


class _Where:
    """Error messages naming the campaign file and the key path."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def error(self, key: str, value: Any, problem: str) -> CampaignError:
        return CampaignError(f"{self.path}: {key} = {value!r}: {problem}")


def _number(where: _Where, key: str, value, integer: bool = False) -> float:
    ok = (isinstance(value, int) if integer else isinstance(value, int | float))
    if isinstance(value, bool) or not ok or (not integer and not math.isfinite(value)):
        raise where.error(key, value, "expected " + ("an integer" if integer else "a number"))
    return value


def _check_option(where: _Where, key: str, opt: Option, value, base: Path | None = None):
    if opt.kind == "path":
        if not isinstance(value, str) or not value:
            raise where.error(key, value, "expected a file path")
        path = (base / value).resolve() if base is not None else Path(value)
        if not path.is_file():
            raise where.error(key, value, f"{path} does not exist")
        return str(path)
    if opt.kind == "bool":
        if not isinstance(value, bool):
            raise where.error(key, value, "expected true or false")
        return value
    if opt.kind == "str":
        if not isinstance(value, str) or (opt.choices and value not in opt.choices):
            raise where.error(key, value, f"expected one of {list(opt.choices)}")
        return value
    if opt.kind == "strs":
        if not (isinstance(value, list) and value and all(isinstance(v, str) for v in value)):
            raise where.error(key, value, "expected a list of names")
        return list(value)
    if opt.kind == "floats":
        if not (isinstance(value, list) and len(value) == opt.length):
            raise where.error(key, value, f"expected a list of {opt.length} numbers")
        return tuple(float(_number(where, key, v)) for v in value)
    v = _number(where, key, value, integer=opt.kind == "int")
    if opt.lo is not None and (v < opt.lo or (opt.lo_open and v <= opt.lo)):
        raise where.error(key, value, f"must be {'>' if opt.lo_open else '>='} {opt.lo:g}")
    if opt.hi is not None and v > opt.hi:
        raise where.error(key, value, f"must be <= {opt.hi:g}")
    return v


def _table(where: _Where, key: str, value) -> dict:
    if not isinstance(value, dict):
        raise where.error(key, value, "expected a table")
    return value


def _unknown(where: _Where, prefix: str, table: dict, known) -> None:
    for k in table:
        if k not in known:
            raise where.error(f"{prefix}{k}", table[k],
                              f"unknown key (known: {', '.join(known)})")


def _grid(where: _Where, table: dict) -> Grid:
    _unknown(where, "grid.", table, [f.name for f in Grid.__dataclass_fields__.values()])
    kw = {}
    for name in ("cell_m", "layer_m", "deck_length_m", "beam_m", "hangar_length_m",
                 "hangar_width_m"):
        if name in table:
            kw[name] = float(_check_option(where, f"grid.{name}",
                                           Option("float", name, lo=0.0, lo_open=True),
                                           table[name]))
    for name in ("min_seconds", "aft_m"):
        if name in table:
            kw[name] = float(_check_option(where, f"grid.{name}", Option("float", name, lo=0.0),
                                           table[name]))
    if "height_m" in table:
        lo, hi = _check_option(where, "grid.height_m", Option("floats", "h", length=2),
                               table["height_m"])
        if not 0 <= lo < hi:
            raise where.error("grid.height_m", table["height_m"],
                              "expected [lo, hi] heights above the deck with 0 <= lo < hi")
        kw["height_m"] = (lo, hi)
    grid = Grid(**kw)
    if not grid.deck_cells():
        raise where.error("grid.cell_m", grid.cell_m, "no cell of this size fits the deck "
                          "area (grid.height_m, grid.beam_m)")
    return grid


def _steps(where: _Where, table: dict, base: Path) -> tuple[tuple[str, ...], dict]:
    _unknown(where, "steps.", table, ["run", *STEPS])
    run = table.get("run", list(STEPS))
    if not (isinstance(run, list) and run and all(isinstance(s, str) for s in run)):
        raise where.error("steps.run", run, f"expected a list of steps out of {list(STEPS)}")
    for s in run:
        if s not in STEPS:
            raise where.error("steps.run", run, f"unknown step {s!r} (steps: {list(STEPS)})")
    for s, need in (("map", "estimate"),):
        if s in run and need not in run:
            raise where.error("steps.run", run, f"step {s!r} needs step {need!r}")
    options = {}
    for step in STEPS:
        given = _table(where, f"steps.{step}", table.get(step, {}))
        known = STEP_OPTIONS[step]
        _unknown(where, f"steps.{step}.", given, list(known))
        options[step] = {known[k].api: _check_option(where, f"steps.{step}.{k}", known[k], v,
                                                     base)
                         for k, v in given.items()}
    est = options["estimate"]
    if (est.get("method") == "net") != ("net" in est):
        raise where.error("steps.estimate.method", est.get("method", "smoother"),
                          "method 'net' needs steps.estimate.net = a wind net file (and net "
                          "needs method = 'net')")
    return tuple(s for s in STEPS if s in run), options


def _source(where: _Where, key: str, path: Path, value) -> Source:
    if path.is_dir() or path.suffix.lower() == ".mcap":
        kind = "recording"
    elif path.suffix.lower() in TABLE_SUFFIXES:
        kind = "table"
    else:
        raise where.error(key, value, f"{path}: neither a flight table (.parquet, .csv) nor "
                          "a recording (a directory or .mcap segment)")
    if not path.exists():
        raise where.error(key, value, f"{path} does not exist")
    return Source(path.resolve(), kind)


def _model_spec(where: _Where, key: str, value, base: Path) -> str:
    """A shipped spec name or an absolute path; the spec must load."""
    from airwake.heli import load_model

    if not isinstance(value, str) or not value:
        raise where.error(key, value, "expected a model spec (shipped name or .toml path)")
    spec = value
    if "/" in value or value.endswith(".toml"):
        spec = str((base / value).resolve())
    try:
        load_model(spec)
    except CampaignError:
        raise
    except Exception as exc:  # noqa: BLE001 — the spec's own error, named here
        raise where.error(key, value, str(exc)) from None
    return spec


def _helicopters(where: _Where, table: dict, base: Path) -> dict:
    if not table:
        raise where.error("helicopters", table, "at least one [helicopters.NAME] table is "
                          "needed (model = the helicopter's model spec)")
    out = {}
    for name, entry in table.items():
        prefix = f"helicopters.{name}"
        entry = _table(where, prefix, entry)
        _unknown(where, f"{prefix}.", entry, HELICOPTER_KEYS)
        model = _model_spec(where, f"{prefix}.model", entry.get("model", "table52"), base)
        cal = None
        if "calibration" in entry:
            value = entry["calibration"]
            if not isinstance(value, str):
                raise where.error(f"{prefix}.calibration", value, "expected a file path")
            cal = _source(where, f"{prefix}.calibration", base / value, value)
        still = entry.get("still_air", [])
        if not isinstance(still, list):
            raise where.error(f"{prefix}.still_air", still, "expected a list of still-air "
                              "flight paths")
        sources, seen = [], {cal.path} if cal else set()
        for i, v in enumerate(still):
            key = f"{prefix}.still_air[{i}]"
            if not (isinstance(v, str) and v):
                raise where.error(key, v, "expected a still-air flight path")
            src = _source(where, key, base / v, v)
            if src.path in seen:
                raise where.error(key, v, "listed twice (the calibration flight is in the "
                                  "still-air net already)")
            seen.add(src.path)
            sources.append(src)
        out[name] = Helicopter(name, model, cal, tuple(sources))
    return out


def flight_metadata(source: Source) -> dict:
    """A flight table's metadata (nothing read for a recording before its export)."""
    from airwake.record.flight_table import FlightTableError, read_flight_metadata

    if source.kind != "table":
        return {}
    try:
        return read_flight_metadata(source.path)
    except FlightTableError as exc:
        raise CampaignError(str(exc)) from None


def metadata_beta(meta: dict) -> float | None:
    """beta from a flight's metadata: its campaign table, or a simulated ship flight's
    relative wind heading."""
    camp = meta.get("campaign") or {}
    if isinstance(camp.get("beta_deg"), int | float):
        return float(camp["beta_deg"])
    wind = (meta.get("scenario_config") or {}).get("wind") or {}
    if wind.get("type") == "ship_airwake":
        return float(wind.get("relative_wind_heading_deg", 0.0))
    return None


def _flights(where: _Where, entries, base: Path, helis: dict, skip: set) -> tuple:
    if not (isinstance(entries, list) and entries):
        raise where.error("flights", entries, "expected [[flights]] entries (path = a glob "
                          "of flight tables or recordings)")
    out, seen = [], {}
    for i, entry in enumerate(entries):
        prefix = f"flights[{i}]"
        entry = _table(where, prefix, entry)
        _unknown(where, f"{prefix}.", entry, FLIGHT_KEYS)
        pattern = entry.get("path")
        if not isinstance(pattern, str) or not pattern:
            raise where.error(f"{prefix}.path", pattern, "expected a path or glob")
        matches = sorted(Path(p) for p in glob.glob(str(base / pattern)))
        matches = [m for m in matches if m.resolve() not in skip]
        if not matches:
            raise where.error(f"{prefix}.path", pattern, f"matches no file under {base}")
        heli = entry.get("helicopter")
        if heli is not None and heli not in helis:
            raise where.error(f"{prefix}.helicopter", heli,
                              f"no [helicopters.{heli}] (known: {', '.join(helis)})")
        beta = entry.get("beta_deg")
        if beta is not None:
            beta = float(_check_option(where, f"{prefix}.beta_deg",
                                       Option("float", "b", lo=-360.0, hi=360.0), beta))
        day = entry.get("day", "")
        if not isinstance(day, str):
            raise where.error(f"{prefix}.day", day, "expected a string (a date or a label)")
        for m in matches:
            src = _source(where, f"{prefix}.path", m, pattern)
            meta = flight_metadata(src)
            camp = meta.get("campaign") or {}
            b = beta if beta is not None else metadata_beta(meta)
            if b is None:
                raise where.error(f"{prefix}.beta_deg", None, f"{m.name}: not given and its "
                                  "metadata does not say it: add beta_deg to the entry")
            h = heli or camp.get("helicopter") or (next(iter(helis)) if len(helis) == 1
                                                   else None)
            if h not in helis:
                raise where.error(f"{prefix}.helicopter", h, f"{m.name}: which helicopter "
                                  f"flew it? (known: {', '.join(helis)})")
            d = day or str(camp.get("day") or (meta.get("start_utc") or "")[:10])
            name = m.stem if m.suffix else m.name
            if name in seen:
                raise where.error(f"{prefix}.path", pattern, f"flight name {name!r} is also "
                                  f"{seen[name]}: flights need distinct file names")
            seen[name] = str(m)
            out.append(Flight(name, src, h, b, d))
    return tuple(out)


def load_campaign(path) -> Campaign:
    """Read and validate a campaign file (module docstring)."""
    p = Path(path)
    where = _Where(p)
    try:
        data = tomllib.loads(p.read_text())
    except FileNotFoundError:
        raise CampaignError(f"campaign file {p} not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise CampaignError(f"{p}: not valid TOML: {exc}") from None
    _unknown(where, "", data, TOP_KEYS)
    base = p.resolve().parent
    for key in ("name", "description"):
        if not isinstance(data.get(key, ""), str):
            raise where.error(key, data[key], "expected a string")
    grid = _grid(where, _table(where, "grid", data.get("grid", {})))
    steps, options = _steps(where, _table(where, "steps", data.get("steps", {})), base)
    helis = _helicopters(where, _table(where, "helicopters", data.get("helicopters", {})),
                         base)
    still_files = {s.path for h in helis.values() for s in h.still_air_flights}
    flights = _flights(where, data.get("flights"), base, helis, still_files)
    recordings = [f for f in flights if f.source.kind == "recording"] + [
        s for h in helis.values() for s in h.still_air_flights if s.kind == "recording"]
    if recordings and "export" not in steps:
        raise where.error("steps.run", list(steps), "recordings need the 'export' step")
    if options["estimate"].get("method") == ANCHORED and "estimate" in steps:
        if "still_air_net" not in steps:
            raise where.error("steps.estimate.method", ANCHORED, "needs the 'still_air_net' "
                              "step in steps.run (the mean flow the smoother is anchored on)")
        for h in sorted({f.helicopter for f in flights}):
            if not helis[h].still_air_flights:
                raise where.error(f"helicopters.{h}.still_air", [], "steps.estimate.method = "
                                  "'anchored' needs still-air flights of this helicopter "
                                  "(calibration = ..., still_air = [...]) for its "
                                  "still-air wind net")
    return Campaign(p.resolve(), data.get("name", p.stem), data.get("description", ""),
                    grid, steps, options, helis, flights)
