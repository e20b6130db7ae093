"""The flight as the analysis sees it: measured columns only, validated, split into runs.

`load_flight(source)` accepts a path (.parquet / .csv, docs/flight-table.md), a
`FlightTable` or a DataFrame. It keeps only `measured_columns` (never `truth_*`) and
never looks at the table's metadata (a simulated table's metadata may name its hidden
effect), so the analysis of a flight is the same with or without them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from airwake.discrepancy.errors import DiscrepancyError
from airwake.discrepancy.settings import AnalysisSettings
from airwake.heli.context import MEAS_CHANNELS
from airwake.heli.model import INPUT_NAMES

BODY_COLUMNS = (
    "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
    "roll_rad", "pitch_rad", "yaw_rad",
    "p_rad_s", "q_rad_s", "r_rad_s",
)
# What the analysis needs; rotor speed, height and positions are optional (the candidates
# that need them say so when they are missing).
REQUIRED_COLUMNS = ("t_s", *INPUT_NAMES, *BODY_COLUMNS, *MEAS_CHANNELS)
OPTIONAL_COLUMNS = ("rotor_speed_rad_s", "height_agl_m", "pos_n_m", "pos_e_m", "pos_d_m")
CHANNEL_LABELS = {
    "acc_x_m_s2": "ax", "acc_y_m_s2": "ay", "acc_z_m_s2": "az",
    "pdot_rad_s2": "pdot", "qdot_rad_s2": "qdot", "rdot_rad_s2": "rdot",
}
CHANNEL_UNITS = {c: ("m/s²" if c.startswith("acc") else "rad/s²") for c in MEAS_CHANNELS}


@dataclass
class Flight:
    """A validated flight: df (measured columns only), t (T,), z (T, 6) measured channels,
    runs (contiguous sample ranges without time gaps), name (for messages)."""

    df: pd.DataFrame
    name: str
    t: np.ndarray = field(init=False)
    z: np.ndarray = field(init=False)
    runs: list = field(init=False)
    rate_hz: float = field(init=False)

    def __post_init__(self) -> None:
        from airwake.record.differentiate import split_runs

        self.t = self.df["t_s"].to_numpy(dtype=float)
        self.z = np.column_stack([self.df[c].to_numpy(dtype=float) for c in MEAS_CHANNELS])
        self.runs = split_runs(self.t)
        self.rate_hz = 1.0 / float(np.median(np.diff(self.t)))

    def __len__(self) -> int:
        return self.t.size

    def has(self, column: str) -> bool:
        if column not in self.df.columns:
            return False
        if column == "height_agl_m":
            return bool(np.isfinite(self.df[column].to_numpy(dtype=float)).any())
        return True

    def column(self, name: str) -> np.ndarray:
        return self.df[name].to_numpy(dtype=float)


def load_flight(source, settings: AnalysisSettings | None = None) -> Flight:
    """Path / FlightTable / DataFrame -> Flight (measured columns, validated)."""
    from airwake.record.flight_table import (
        FlightTable,
        FlightTableError,
        load_flight_table,
        measured_columns,
        validate_flight_table,
    )

    settings = settings or AnalysisSettings()
    if isinstance(source, Flight):
        return source
    try:
        if isinstance(source, str | Path):
            name = str(source)
            df = load_flight_table(source, REQUIRED_COLUMNS, OPTIONAL_COLUMNS).df
        elif isinstance(source, FlightTable):
            name = str(source.path) if source.path else "<flight table>"
            df = validate_flight_table(source.df, name, REQUIRED_COLUMNS, OPTIONAL_COLUMNS)
        elif isinstance(source, pd.DataFrame):
            name = "<data frame>"
            df = validate_flight_table(source, name, REQUIRED_COLUMNS, OPTIONAL_COLUMNS)
        else:
            raise DiscrepancyError(f"cannot read a flight from {type(source).__name__}")
    except FlightTableError as exc:
        raise DiscrepancyError(str(exc)) from None
    df = df[measured_columns(df)].reset_index(drop=True)
    if len(df) < 100:
        raise DiscrepancyError(f"{name}: only {len(df)} samples; the analysis needs >= 100 "
                               f"(a few seconds of flight)")
    flight = Flight(df, name)
    dur = flight.t[-1] - flight.t[0]
    if dur < 2 * (settings.skip_start_s + settings.edge_s) + 1.0:
        raise DiscrepancyError(f"{name}: {dur:.2f} s of flight is too short for the analysis "
                               f"(skip {settings.skip_start_s} s + edges); need > "
                               f"{2 * (settings.skip_start_s + settings.edge_s) + 1.0:.1f} s")
    return flight
