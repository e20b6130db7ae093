"""Recordings and flight tables.

`airwake.record.flight_table` holds the flight-table schema, loader and writer
(docs/flight-table.md); crash-safe recordings and their export live beside it.
The flight-table names below are imported lazily: importing `airwake.record` (as the
daemon does for the recorder) must not pull in pandas.
"""

from airwake.lazy import lazy_exports

__all__ = [
    "CONTRACT_COLUMNS",
    "FlightTable",
    "FlightTableError",
    "FlightTableWarning",
    "load_flight_table",
    "measured_columns",
    "validate_flight_table",
    "write_flight_table",
]
__getattr__, __dir__ = lazy_exports(__name__, dict.fromkeys(__all__, "airwake.record.flight_table"))
