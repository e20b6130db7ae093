"""Cross-checks of the firmware algorithm modules (C, via build/native/libawboards.so)
against Python references: peak finder accuracy, slot unwrapping, quaternion
integration vs scipy, VN200 and SBP parsers, PWM capture and rotor speed."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import awboards  # noqa: E402


@pytest.fixture(scope="session")
def lib():
    return awboards.load()
