"""User-facing calibration errors."""

from airwake.errors import AirwakeError


class CalibrationError(AirwakeError):
    """Calibration input that cannot be used (flight column, parameter name, value named)."""
