"""Recordings and flight tables.

`airwake.record.flight_table` holds the flight-table schema, loader and writer
(docs/flight-table.md); crash-safe recordings and their export live beside it.
"""

from airwake.record.flight_table import (
    CONTRACT_COLUMNS,
    FlightTable,
    FlightTableError,
    load_flight_table,
    measured_columns,
    validate_flight_table,
    write_flight_table,
)

__all__ = [
    "CONTRACT_COLUMNS",
    "FlightTable",
    "FlightTableError",
    "load_flight_table",
    "measured_columns",
    "validate_flight_table",
    "write_flight_table",
]
