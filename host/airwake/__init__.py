"""airwake: an instrumented RC helicopter as a flying wind sensor for ship airwake."""

__version__ = "0.1.0"
