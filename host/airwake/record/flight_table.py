"""Flight tables: the analysis format (docs/flight-table.md), Parquet or CSV.

    ft = load_flight_table("flight.parquet")      # -> FlightTable(df, metadata, path)
    write_flight_table(df, "flight.csv", {"frame": "ned", "scenario": "hover", "seed": 1})
    cols = measured_columns(ft.df)                # everything except truth_*

Validation raises `FlightTableError` (one line naming file, column, row and value) for a
missing file, unknown extension, missing columns, and — in the columns the caller reads
(`required` and `reads`) — NaNs, non-monotonic or duplicated time and values outside
plausible unit ranges (degrees where radians are expected, rpm for rad/s, …). The same
faults in a column the caller does not read are one `FlightTableWarning` each (column,
rows, values) and the table is used as it is: a command is never refused for a column it
does not read. A column with a validity flag (`marker_*` and `marker_valid`, ...:
`VALIDITY_FLAGS`) is checked only where its flag is 1; elsewhere its values are held and
mean nothing. Extra columns are kept. Metadata: Parquet schema metadata key "airwake"
(JSON); CSV: a first line `# airwake-metadata: {json}`.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from airwake.errors import AirwakeError

TIME = "t_s"
INPUTS = ("delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad")
STATES = (
    "pos_n_m", "pos_e_m", "pos_d_m",
    "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
    "roll_rad", "pitch_rad", "yaw_rad",
    "p_rad_s", "q_rad_s", "r_rad_s",
)
MEASUREMENTS = (
    "acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2",
    "pdot_rad_s2", "qdot_rad_s2", "rdot_rad_s2",
)
ROTOR = ("rotor_speed_rad_s",)
HEIGHT = ("height_agl_m",)
# The minimal column contract of ARCHITECTURE.md.
CONTRACT_COLUMNS = (TIME, *INPUTS, *STATES, *MEASUREMENTS, *ROTOR, *HEIGHT)
TRUTH_WIND = (
    "truth_wind_vx_m_s", "truth_wind_vy_m_s", "truth_wind_vz_m_s",
    "truth_wind_wx_rad_s", "truth_wind_wy_rad_s", "truth_wind_wz_rad_s",
)
METADATA_KEY = "airwake"
_CSV_META = "# airwake-metadata:"

_PI = math.pi + 1e-6
# Plausible ranges per column (inclusive); a column matching a prefix/suffix rule below
# is checked too. Chosen so that a unit mistake (deg for rad, rpm for rad/s, g for m/s^2)
# lands outside.
RANGES: dict[str, tuple[float, float]] = {
    "roll_rad": (-_PI, _PI),
    "pitch_rad": (-math.pi / 2 - 1e-6, math.pi / 2 + 1e-6),
    "yaw_rad": (-2 * math.pi - 1e-6, 2 * math.pi + 1e-6),
    "rotor_speed_rad_s": (0.0, 400.0),
    "height_agl_m": (-1.0, math.inf),
}
SUFFIX_RANGES: dict[str, tuple[float, float]] = {
    "_rad_s2": (-500.0, 500.0),
    "_m_s2": (-200.0, 200.0),
    "_rad_s": (-20.0, 20.0),  # body rates, vorticity (rotor speed has its own rule)
    "_m_s": (-100.0, 100.0),
    "_us": (500.0, 2500.0),  # PWM pulse widths
}
PREFIX_RANGES: dict[str, tuple[float, float]] = {
    "delta_": (-0.6, 0.6),  # blade pitch commands, rad (35 deg)
}
# Columns allowed to hold +inf (unknown height above ground).
INF_OK = {"height_agl_m"}
# Columns whose rows mean something only where a flag column is 1 (an optional stream's
# `<name>_valid`, docs/flight-table.md): by name prefix, the flag itself excluded.
VALIDITY_FLAGS: dict[str, str] = {
    "marker_": "marker_valid",
    "tracker_pos_": "tracker_valid",
    "anemo_": "anemo_valid",
    "hub_ship_": "hub_ship_valid",
    "ship_": "ship_valid",
    "tail_servo_": "tail_servo_valid",
}


class FlightTableError(AirwakeError):
    """A flight table that cannot be used as is (file, column, row and value named)."""


class FlightTableWarning(UserWarning):
    """An implausible value in a column the command does not read (one line: file,
    column, rows, values); the command goes on. `airwake` prints it as
    `airwake COMMAND: warning: ...`."""


@dataclass
class FlightTable:
    df: pd.DataFrame
    metadata: dict = field(default_factory=dict)
    path: Path | None = None

    def __len__(self) -> int:
        return len(self.df)


def measured_columns(df: pd.DataFrame) -> list[str]:
    """Every column except simulated truth (`truth_*`): what an analysis may read."""
    return [c for c in df.columns if not str(c).startswith("truth_")]


def _range_for(column: str) -> tuple[float, float] | None:
    name = column[len("truth_") :] if column.startswith("truth_") else column
    if name in RANGES:
        return RANGES[name]
    for prefix, rng in PREFIX_RANGES.items():
        if name.startswith(prefix):
            return rng
    for suffix, rng in SUFFIX_RANGES.items():
        if name.endswith(suffix):
            return rng
    return None


def validity_flag(column: str) -> str | None:
    """The flag column saying where `column` holds data (`VALIDITY_FLAGS`), or None."""
    for prefix, flag in VALIDITY_FLAGS.items():
        if column.startswith(prefix) and column != flag:
            return flag
    return None


def _spans(rows: np.ndarray, most: int = 3) -> str:
    """'7536-8120, 9000' for sorted row indexes (the first `most` runs, then a count)."""
    cut = np.flatnonzero(np.diff(rows) > 1) + 1
    runs = [(int(r[0]), int(r[-1])) for r in np.split(rows, cut)]
    text = ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in runs[:most])
    return text + (f" and {len(runs) - most} more spans" if len(runs) > most else "")


def _implausible(df: pd.DataFrame, column: str) -> tuple[np.ndarray, str] | None:
    """(bad rows, what is wrong) of one numeric column, on the rows its flag marks valid."""
    v = df[column].to_numpy(dtype=float)
    flag = validity_flag(column)
    where = (df[flag].to_numpy(dtype=float) > 0.5) if flag in df.columns else None
    bad = np.isnan(v) if column in INF_OK else ~np.isfinite(v)
    if where is not None:
        bad &= where
    if bad.any():
        return bad, "NaN/non-finite"
    rng = _range_for(column)
    if rng is None:
        return None
    out = (v < rng[0]) | (v > rng[1])
    if where is not None:
        out &= where
    if out.any():
        return out, f"outside the plausible range [{rng[0]:g}, {rng[1]:g}]"
    return None


def validate_flight_table(
    df: pd.DataFrame, source: str = "<table>", required: Sequence[str] = CONTRACT_COLUMNS,
    reads: Sequence[str] = (),
) -> pd.DataFrame:
    """Check the columns a command reads — `required` (must be there) and `reads` (read
    when present) — for NaNs, time order and unit ranges; returns df (unchanged) or raises
    `FlightTableError`. Every other column with such a fault is a `FlightTableWarning`
    naming it and its rows; the table is still returned."""
    missing = [c for c in required if c not in df.columns]
    if missing:
        raise FlightTableError(
            f"{source}: missing column(s) {missing}; a flight table needs {list(required)} "
            "(see docs/flight-table.md)"
        )
    checked = set(required) | set(reads) | {TIME}
    for c in df.columns:
        if not pd.api.types.is_numeric_dtype(df[c]):
            if c in required:
                raise FlightTableError(f"{source}: column '{c}' is not numeric ({df[c].dtype})")
            continue
        found = _implausible(df, str(c))
        if found is None:
            continue
        bad, what = found
        rows = np.flatnonzero(bad)
        v = df[c].to_numpy(dtype=float)
        i = int(rows[0])
        if c in checked:
            if what.startswith("NaN"):
                raise FlightTableError(
                    f"{source}: column '{c}' has {rows.size} NaN/non-finite value(s), "
                    f"first at row {i} ({float(v[i])!r})"
                )
            raise FlightTableError(
                f"{source}: column '{c}' value {float(v[i])!r} at row {i} {what} (wrong "
                "unit? names carry SI units)"
            )
        flag = validity_flag(str(c))
        flagged = f" where {flag} is 1" if flag in df.columns else ""
        warnings.warn(FlightTableWarning(
            f"{source}: column '{c}' has {rows.size} value(s) {what}{flagged}, rows "
            f"{_spans(rows)} (e.g. {float(v[i])!r} at row {i}); not read here, left as is"),
            stacklevel=2)
    if TIME in df.columns:
        t = df[TIME].to_numpy(dtype=float)
        dt = np.diff(t)
        if (dt <= 0).any():
            i = int(np.argmax(dt <= 0)) + 1
            what = "duplicated" if dt[i - 1] == 0 else "decreasing"
            raise FlightTableError(
                f"{source}: time '{TIME}' is {what} at row {i} "
                f"({float(t[i - 1])!r} -> {float(t[i])!r}); it must increase strictly"
            )
    return df


def read_flight_table(path) -> tuple[pd.DataFrame, dict]:
    """(DataFrame, metadata) of a Parquet or CSV flight table, not validated: partial
    tables (a real flight with NaN stretches) are read as they are."""
    p = Path(path)
    if not p.is_file():
        raise FlightTableError(f"flight table {p} not found")
    ext = p.suffix.lower()
    metadata: dict = {}
    try:
        if ext in (".parquet", ".pq"):
            import pyarrow.parquet as pq

            table = pq.read_table(p)
            raw = (table.schema.metadata or {}).get(METADATA_KEY.encode())
            if raw:
                metadata = json.loads(raw.decode())
            df = table.to_pandas()
        elif ext == ".csv":
            with p.open() as fh:
                first = fh.readline()
            if first.startswith(_CSV_META):
                metadata = json.loads(first[len(_CSV_META) :])
            skip = 1 if metadata or first.startswith("#") else 0
            df = pd.read_csv(p, skiprows=skip)
        else:
            raise FlightTableError(
                f"{p}: unknown flight-table extension '{p.suffix}'; use .parquet or .csv"
            )
    except FlightTableError:
        raise
    except Exception as exc:  # noqa: BLE001 — a corrupt file is a user error, say which
        raise FlightTableError(f"{p}: cannot read: {type(exc).__name__}: {exc}") from None
    return df, metadata


def read_flight_metadata(path) -> dict:
    """The metadata of a Parquet or CSV flight table without reading its rows (the Parquet
    footer, the CSV's first line)."""
    p = Path(path)
    if not p.is_file():
        raise FlightTableError(f"flight table {p} not found")
    ext = p.suffix.lower()
    try:
        if ext in (".parquet", ".pq"):
            import pyarrow.parquet as pq

            raw = (pq.read_schema(p).metadata or {}).get(METADATA_KEY.encode())
            return json.loads(raw.decode()) if raw else {}
        if ext == ".csv":
            with p.open() as fh:
                first = fh.readline()
            return json.loads(first[len(_CSV_META):]) if first.startswith(_CSV_META) else {}
    except Exception as exc:  # noqa: BLE001 — a corrupt file is a user error, say which
        raise FlightTableError(f"{p}: cannot read: {type(exc).__name__}: {exc}") from None
    raise FlightTableError(
        f"{p}: unknown flight-table extension '{p.suffix}'; use .parquet or .csv")


def load_flight_table(path, required: Sequence[str] = CONTRACT_COLUMNS,
                      reads: Sequence[str] = ()) -> FlightTable:
    """Load and validate a Parquet or CSV flight table for a command that reads the
    `required` columns and, when present, `reads` (`validate_flight_table`)."""
    df, metadata = read_flight_table(path)
    validate_flight_table(df, str(path), required, reads)
    return FlightTable(df, metadata, Path(path))


def write_flight_table(df: pd.DataFrame, path, metadata: Mapping | None = None) -> Path:
    """Write a flight table (Parquet or CSV by extension) with its metadata."""
    p = Path(path)
    meta = dict(metadata or {})
    text = json.dumps(meta, sort_keys=True, default=str)
    ext = p.suffix.lower()
    if ext in (".parquet", ".pq"):
        import pyarrow as pa
        import pyarrow.parquet as pq

        table = pa.Table.from_pandas(df, preserve_index=False)
        schema_meta = dict(table.schema.metadata or {})
        schema_meta[METADATA_KEY.encode()] = text.encode()
        pq.write_table(table.replace_schema_metadata(schema_meta), p)
    elif ext == ".csv":
        with p.open("w") as fh:
            fh.write(f"{_CSV_META} {text}\n")
            df.to_csv(fh, index=False, float_format="%.17g")
    else:
        raise FlightTableError(
            f"{p}: unknown flight-table extension '{p.suffix}'; use .parquet or .csv"
        )
    return p


FINGERPRINT_COLUMNS = ("t_s", "acc_z_m_s2", "p_rad_s")


def flight_fingerprint(flight_df) -> dict:
    """What identifies a flight table: rows, time span (to the microsecond) and a digest of
    its time and two measured columns (two simulated flights share rows and span)."""
    import hashlib

    t = np.asarray(flight_df["t_s"], float)
    h = hashlib.sha1()
    for c in FINGERPRINT_COLUMNS:
        if c in flight_df.columns:
            h.update(np.ascontiguousarray(np.asarray(flight_df[c], np.float64)).tobytes())
    return {"rows": int(t.size), "t0_s": round(float(t[0]), 6) if t.size else None,
            "t1_s": round(float(t[-1]), 6) if t.size else None, "digest": h.hexdigest()[:16]}
