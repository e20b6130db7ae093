"""User-facing campaign errors."""

from airwake.errors import AirwakeError


class CampaignError(AirwakeError):
    """A campaign file or run that cannot go on (file, key and value named)."""
