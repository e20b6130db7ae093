"""Session fixtures of the discrepancy tests (helpers in flights.py)."""

import pytest

from .flights import fly


@pytest.fixture(scope="session")
def flights():
    return fly


@pytest.fixture(scope="session")
def calibrated():
    """The model the tests analyse with: C's least-squares calibration, started from the
    reference's Table 5.2, on the compact still-air calibration flight (its identifiable
    parameters: inertias, rotor and flybar Lock numbers, flap inertia/stiffness, hub
    height, lag damping, tail rotor, fuselage drag)."""
    from airwake.calibrate import calibrate

    res = calibrate(fly("calibration"), model="table52", method="lsq",
                    params=CALIBRATED_PARAMS, max_nfev=15, max_windows=16)
    return res.model


@pytest.fixture(scope="session")
def baseline(calibrated):
    return calibrated


CALIBRATED_PARAMS = [
    "rigid_body.*", "main_rotor.lock_number", "main_rotor.flap_inertia_kg_m2",
    "main_rotor.flap_stiffness_nm_rad", "main_rotor.hub_height_m",
    "main_rotor.lag_damping_ratio", "flybar.lock_number", "tail_rotor.radius_m",
    "tail_rotor.lift_slope_per_rad", "tail_rotor.arm_m", "tail_rotor.height_m", "fuselage.*",
]
