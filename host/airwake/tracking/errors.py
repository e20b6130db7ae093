"""User-facing tracking errors."""

from airwake.errors import AirwakeError


class TrackingError(AirwakeError):
    """Tracking input that cannot be used (degenerate geometry, bad shapes; named)."""
