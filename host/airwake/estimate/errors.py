"""User-facing wind-estimation errors."""

from airwake.errors import AirwakeError


class WindEstimationError(AirwakeError):
    """Wind-estimation input that cannot be used (flight column, option, value named)."""
