"""Recordings and flight tables.

`airwake.record.flight_table` holds the flight-table schema, loader and writer
(docs/flight-table.md); crash-safe recordings and their export live beside it.
The flight-table names below are imported lazily: importing `airwake.record` (as the
daemon does for the recorder) must not pull in pandas.
"""

from importlib import import_module

__all__ = [
    "CONTRACT_COLUMNS",
    "FlightTable",
    "FlightTableError",
    "load_flight_table",
    "measured_columns",
    "validate_flight_table",
    "write_flight_table",
]


def __getattr__(name: str):
    if name in __all__:
        return getattr(import_module("airwake.record.flight_table"), name)
    raise AttributeError(f"module 'airwake.record' has no attribute {name!r}")
