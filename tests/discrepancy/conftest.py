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
    parameters: inertias (the mass is weighed, not flown: freed, it trades against the
    fuselage's vertical drag area at rho = -0.995 and a 0.2 % error is 0.017 m/s^2 in az,
    1.5x the floor), rotor and flybar Lock numbers, tail rotor, fuselage drag, and
    the blade profile drag delta_0: Table 5.2's printed 0.0702 is ten times the plausible
    value the truth helicopter flies with, so a model calibrated without it reaches the
    noise floor nowhere). Not freed: the hub height, flap inertia/stiffness, lag damping
    and delta_2, which a hover flight does not separate from the others: freeing them
    leaves compensating errors (hub height 0.156 m for 0.205, delta_2 7.3 for 0.0046)
    that fit the hover but miss by 2-3x the noise floor in az once the aircraft moves."""
    from airwake.calibrate import calibrate

    res = calibrate(fly("calibration"), model="table52", method="lsq",
                    params=CALIBRATED_PARAMS, max_nfev=30, max_windows=16)
    return res.model


@pytest.fixture(scope="session")
def baseline(calibrated):
    return calibrated


CALIBRATED_PARAMS = [
    "rigid_body.I*", "main_rotor.lock_number", "main_rotor.drag_delta0", "flybar.lock_number",
    "tail_rotor.radius_m", "tail_rotor.lift_slope_per_rad", "tail_rotor.arm_m",
    "tail_rotor.height_m", "fuselage.*",
]
