"""Errors the `airwake` command reports to the user as one clear line.

Every area raises a subclass of `AirwakeError` for bad input (file, field, value
named in the message); the CLI prints it and exits with status 2. Anything else
escaping to the CLI is a bug and keeps its traceback.
"""


class AirwakeError(Exception):
    """A user-facing error: the message names what is wrong and where."""
