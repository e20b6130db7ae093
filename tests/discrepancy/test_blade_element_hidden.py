"""The hidden-effect acceptance on the independent blade-element truth (issue 20): a
sensor-side hidden effect on top of a helicopter the host model does not describe,
analysed with the model the documented sequence gives (docs/calibration.md: Table 5.1
calibrated on the still-air flight, then the effect `diagnose` names there added).

On this truth every channel sits far above its noise floor before any hidden effect (the
model's own gap), so the effect-truth tests' ">= 60 % on every affected channel" has no
room. What must hold: the workflow names the effect first, adding it cuts the channel it
acts on most, and on the same flight without the hidden effect (the control) the effect
explains far less (the airframe's servos lag too: measured 5 % against 30 %). Of the
sensor-side effects the blade-element truth takes (docs/truth-world.md):

- input time skew (a 40 ms lag of the commands): servo lag, the catalogue's nearest, is
  named first; adding it cuts az by ~60 %;
- the IMU lever arm is not testable so: the airframe has an IMU offset of its own
  (0.06, 0.015, 0.07 m), which `diagnose` already names first on the still-air flight;
- vibration rectification (a rotor-speed-squared az offset) is not named first: an az
  offset is what a CG offset also explains on this airframe (`cg_offset` first, az
  0.97 -> 0.20; `accel_bias` 4th).
"""

import numpy as np
import pytest
from airwake.calibrate import calibrate
from airwake.discrepancy.add import add_effect
from airwake.discrepancy.diagnose import diagnose

from .flights import analysed, fly

SCENARIO, EXPECTED = "input_time_skew", "servo_lag"
MIN_CUT = 0.35  # on the channel the effect acts on most
MAX_WORSE = 1.1


@pytest.fixture(scope="module")
def documented_model():
    """Table 5.1, `airwake calibrate`'s defaults on the compact still-air flight (12
    windows of it: the suite's time), then the effect diagnose ranks first there added
    (the demo's discrepancy step)."""
    cal = fly("calibration", blade_element=True)
    model = calibrate(cal, model="table51", max_windows=12).model
    first = diagnose(model, cal, sindy=False, refine_top=3).top(1)[0]
    return add_effect(model, first, cal).model


def rms(an) -> np.ndarray:
    return np.sqrt(np.mean(an.residual_band[an.mask] ** 2, 0))


@pytest.mark.slow
def test_diagnose_names_a_hidden_input_skew_on_the_blade_element_truth(documented_model):
    ft = fly(SCENARIO, blade_element=True)
    before_an = analysed(documented_model, ft)
    d = diagnose(documented_model, ft, sindy=False, refine_top=3, analysis=before_an)
    assert d.top(1) == [EXPECTED], f"ranked {d.top(5)}"
    assert d.result(EXPECTED).significant
    before = rms(before_an)
    after = rms(analysed(add_effect(documented_model, EXPECTED, ft,
                                    analysis=before_an).model, ft))
    ratio = after / before
    assert ratio.min() <= 1 - MIN_CUT, f"after/before {np.round(ratio, 3)}"
    assert ratio.max() <= MAX_WORSE, f"after/before {np.round(ratio, 3)}"
    # the control: the same flight and seed without the skew; the blade-element servos
    # are a lag of their own, so servo lag may explain something there, not as much
    control = diagnose(documented_model, fly(SCENARIO, blade_element=True, hidden=False),
                       sindy=False, refine_top=3)
    assert control.result(EXPECTED).explained < 0.5 * d.result(EXPECTED).explained, (
        control.top(5), control.result(EXPECTED).explained, d.result(EXPECTED).explained)
