"""User-facing anemometer wind-map errors."""

from airwake.errors import AirwakeError


class WindMapError(AirwakeError):
    """Wind-map input that cannot be used (column, option, value named)."""
