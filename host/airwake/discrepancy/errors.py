"""The discrepancy workflow's user-facing error."""

from airwake.errors import AirwakeError


class DiscrepancyError(AirwakeError):
    """Bad input to compare/diagnose/add/report: what is wrong, where (file, column, value)."""
