"""What the networks read from a flight table, from full or partial tables.

    flight = load_net_flight("flight.parquet", target="rates")   # -> NetFlight
    flight = net_flight_from_df(df, source="…", target="accel")

Only the columns the networks need are required and validated, so real logs with NaN
in unsupported columns (docs/flight-table.md) load. Pilot inputs, in this order of
preference, from whichever complete set the table has (a column that is entirely NaN
counts as absent):

    delta_{lat,lon,col,ped}_rad        blade-pitch commands (rad)
    pwm_ch{1,2,3,4}_us                 raw RC pulse widths (ch1 lat, ch2 lon, ch3 col, ch4 tail)
    rc_{lat,lon,col,ped}_norm          normalised sticks (e.g. a Pixhawk log)

plus `t_s`, `roll_rad`, `pitch_rad`, `p_rad_s`, `q_rad_s`, `r_rad_s`, and for the angular
acceleration target `pdot_rad_s2`, `qdot_rad_s2`. Problems raise `FlightTableError` in
one line naming the file and the column(s).
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import pandas as pd

from airwake.record.flight_table import (
    FlightTableError,
    flight_fingerprint,
    read_flight_table,
    validate_flight_table,
)

INPUT_SOURCES = {
    "delta": ("delta_lat_rad", "delta_lon_rad", "delta_col_rad", "delta_ped_rad"),
    "pwm": ("pwm_ch1_us", "pwm_ch2_us", "pwm_ch3_us", "pwm_ch4_us"),
    "rc_norm": ("rc_lat_norm", "rc_lon_norm", "rc_col_norm", "rc_ped_norm"),
}
RATE_COLUMNS = ("p_rad_s", "q_rad_s", "r_rad_s")
ATTITUDE_COLUMNS = ("roll_rad", "pitch_rad")
ACCEL_COLUMNS = ("pdot_rad_s2", "qdot_rad_s2")
TARGETS = ("rates", "accel")


@dataclass
class NetFlight:
    """One flight as the networks see it; arrays are (T,) or (T, k), SI units."""

    source: str
    t_s: np.ndarray
    inputs: np.ndarray  # (T, 4) lat, lon, col, ped in the table's input unit
    input_source: str  # a key of INPUT_SOURCES
    roll_rad: np.ndarray
    pitch_rad: np.ndarray
    rates_rad_s: np.ndarray  # (T, 3) p, q, r
    accel_rad_s2: np.ndarray | None  # (T, 2) pdot, qdot where the target needs it
    rate_hz: float
    fingerprint: dict
    # the simulator's noise-free target (truth_<column>), only for scoring: None elsewhere
    truth: np.ndarray | None = None

    def __len__(self) -> int:
        return int(self.t_s.size)

    def crop(self, from_s: float | None = None, to_s: float | None = None) -> NetFlight:
        """The rows with from_s <= t_s <= to_s (a touchdown or spool-up left out)."""
        keep = np.ones(len(self), bool)
        if from_s is not None:
            keep &= self.t_s >= from_s
        if to_s is not None:
            keep &= self.t_s <= to_s
        if keep.sum() < 2:
            raise FlightTableError(f"{self.source}: no rows left in t_s [{from_s}, {to_s}] "
                                   f"(the flight spans {self.t_s[0]:g}-{self.t_s[-1]:g} s)")
        idx = np.flatnonzero(keep)
        sl = slice(idx[0], idx[-1] + 1)
        return NetFlight(
            self.source, self.t_s[sl], self.inputs[sl], self.input_source, self.roll_rad[sl],
            self.pitch_rad[sl], self.rates_rad_s[sl],
            None if self.accel_rad_s2 is None else self.accel_rad_s2[sl], self.rate_hz,
            {**self.fingerprint, "crop_s": [from_s, to_s]},
            None if self.truth is None else self.truth[sl])


def read_table(path) -> pd.DataFrame:
    """A Parquet or CSV flight table as a DataFrame, not validated (partial tables)."""
    return read_flight_table(path)[0]


def _present(df: pd.DataFrame, col: str) -> bool:
    if col not in df.columns:
        return False
    v = pd.to_numeric(df[col], errors="coerce")
    return bool(v.notna().any())


def pick_input_source(df: pd.DataFrame, source: str, prefer: str | None = None) -> str:
    """The first complete input set (INPUT_SOURCES order), or `prefer` if given."""
    if prefer is not None:
        missing = [c for c in INPUT_SOURCES[prefer] if not _present(df, c)]
        if missing:
            raise FlightTableError(
                f"{source}: the net reads pilot inputs from {prefer} columns; missing or all-NaN "
                f"column(s) {missing}")
        return prefer
    for name, cols in INPUT_SOURCES.items():
        if all(_present(df, c) for c in cols):
            return name
    have = {n: [c for c in cols if _present(df, c)] for n, cols in INPUT_SOURCES.items()}
    raise FlightTableError(
        f"{source}: no complete set of pilot inputs; need one of "
        + "; ".join(f"{list(cols)} (has {have[n] or 'none'})" for n, cols in INPUT_SOURCES.items()))


def required_columns(target: str, input_source: str) -> tuple[str, ...]:
    if target not in TARGETS:
        raise ValueError(f"target must be one of {TARGETS}, got {target!r}")
    need = ("t_s", *INPUT_SOURCES[input_source], *ATTITUDE_COLUMNS, *RATE_COLUMNS)
    return need + (ACCEL_COLUMNS if target == "accel" else ())


def net_flight_from_df(df: pd.DataFrame, source: str = "<table>", target: str = "rates",
                       input_source: str | None = None) -> NetFlight:
    """Validate the columns the networks need (only those) and build a NetFlight."""
    src = pick_input_source(df, source, input_source)
    need = required_columns(target, src)
    missing = [c for c in need if not _present(df, c)]
    if missing:
        raise FlightTableError(f"{source}: missing or all-NaN column(s) {missing} "
                               f"(the {target} network needs {list(need)})")
    sub = df.loc[:, list(need)]
    validate_flight_table(sub, source, need)
    t = sub["t_s"].to_numpy(float)
    if t.size < 10:
        raise FlightTableError(f"{source}: only {t.size} rows; a network needs a flight")
    dt = np.diff(t)
    rate_hz = 1.0 / float(np.median(dt))
    gap = dt > 5.0 / rate_hz
    if gap.any():
        i = int(np.argmax(gap))
        raise FlightTableError(
            f"{source}: time 't_s' has a gap of {dt[i]:.3g} s at row {i + 1} "
            f"({t[i]:g} -> {t[i + 1]:g}); the features assume a uniform rate (~{rate_hz:.4g} Hz)")
    accel = sub[list(ACCEL_COLUMNS)].to_numpy(float) if target == "accel" else None
    fp = flight_fingerprint(df)
    truth_cols = [f"truth_{c}" for c in (ACCEL_COLUMNS if target == "accel" else RATE_COLUMNS)]
    truth = None
    if all(c in df.columns for c in truth_cols):
        truth = df[truth_cols].to_numpy(float)
        truth = truth if np.isfinite(truth).all() else None
    return NetFlight(
        source=source, t_s=t, inputs=sub[list(INPUT_SOURCES[src])].to_numpy(float),
        input_source=src, roll_rad=sub["roll_rad"].to_numpy(float),
        pitch_rad=sub["pitch_rad"].to_numpy(float),
        rates_rad_s=sub[list(RATE_COLUMNS)].to_numpy(float), accel_rad_s2=accel,
        rate_hz=rate_hz, fingerprint=json.loads(json.dumps(fp)), truth=truth)


def load_net_flight(path, target: str = "rates", input_source: str | None = None) -> NetFlight:
    """Read a (possibly partial) flight table and keep what the networks need."""
    return net_flight_from_df(read_table(path), str(path), target, input_source)
