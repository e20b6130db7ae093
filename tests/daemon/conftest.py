"""Fixtures of the daemon tests (helpers: daemon_harness.py)."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture
def run_dir(tmp_path) -> Path:
    """A directory for the fake boards' pty symlinks, the recording and the status."""
    d = tmp_path / "run"
    d.mkdir()
    return d
