"""Is a yaw-rate gyro acting between the rudder channel and the tail servo?

    found = yaw_gyro(flight_df)      # dict, or None when the flight cannot say

Every RC helicopter flies with a yaw gyro between the receiver's rudder channel and the
tail servo; in rate ("normal") mode it sends the servo the rudder minus a gain times the
yaw rate, so the tail pitch the rotor flies is not the rudder's. The host's model reads
the rudder channel (`delta_ped_rad`) as the tail pitch and has no gyro: a calibration
then takes the gyro's rate feedback into the model's own yaw damping, which grows with
the square of the tail-rotor arm — on the blade-element airframe the fit put the tail and
fin arms at their 3 m bound (0.83 m on the airframe) and the inertias an order of
magnitude high, and the model's yaw-acceleration answer to the wind's rotation ω_z 3-4x
the airframe's (docs/calibration.md, "What the fit bends on this airframe").

The rover captures the tail servo's pulses (`tail_servo_pwm_us`, valid where
`tail_servo_valid`), so the flight says whether a gyro acts: the servo pulse less the
rudder pulse, regressed on the measured yaw rate by least squares with an intercept,

    servo_us - rudder_us = neutral_us + slope_us_per_rad_s * r + e

is the gyro's neutral offset and its rate gain (negative: it opposes the rate). A gyro is
reported when the rate explains at least `MIN_EXPLAINED` of the difference's variance —
half: then the difference is mostly the gyro's feedback, not pulse jitter or a heading-
hold integral — and the flight holds at least `MIN_ROWS` valid rows with the yaw rate
moving (its std at least `MIN_RATE_STD_RAD_S`, 0.5 deg/s; a flight held at a constant
rate cannot show a rate gain).
"""

from __future__ import annotations

import numpy as np

COLUMNS = ("tail_servo_pwm_us", "tail_servo_valid", "pwm_ch4_us", "r_rad_s")
MIN_EXPLAINED = 0.5  # share of the (servo - rudder) variance the yaw rate explains
MIN_ROWS = 100
MIN_RATE_STD_RAD_S = np.radians(0.5)


def yaw_gyro(df) -> dict | None:
    """The yaw gyro's rate feedback as the flight shows it (module doc): {"found": bool,
    "slope_us_per_rad_s", "neutral_us", "explained" (R^2), "rows"}; None when the flight
    has no tail-servo capture, too few valid rows or a yaw rate that does not move."""
    if any(c not in df.columns for c in COLUMNS):
        return None
    servo = np.asarray(df["tail_servo_pwm_us"], float)
    rudder = np.asarray(df["pwm_ch4_us"], float)
    r = np.asarray(df["r_rad_s"], float)
    ok = (np.asarray(df["tail_servo_valid"], float) > 0) & np.isfinite(servo) & \
        np.isfinite(rudder) & np.isfinite(r)
    if ok.sum() < MIN_ROWS or np.std(r[ok]) < MIN_RATE_STD_RAD_S:
        return None
    d, x = servo[ok] - rudder[ok], r[ok]
    a = np.column_stack([np.ones_like(x), x])
    (neutral, slope), *_ = np.linalg.lstsq(a, d, rcond=None)
    var = float(np.var(d))
    explained = 0.0 if var <= 0 else float(1.0 - np.var(d - a @ [neutral, slope]) / var)
    return {"found": explained >= MIN_EXPLAINED, "slope_us_per_rad_s": float(slope),
            "neutral_us": float(neutral), "explained": explained, "rows": int(ok.sum())}


def note(found: dict | None) -> str | None:
    """The calibration report's line for a gyro the model does not hold, else None."""
    if not found or not found["found"]:
        return None
    return (f"yaw gyro: the tail-servo pulses differ from the rudder's by "
            f"{found['slope_us_per_rad_s']:+.1f} us per rad/s of yaw rate (the rate explains "
            f"{100 * found['explained']:.0f} % of the difference): a rate gyro acts between "
            "them, and the model reads the rudder as the tail pitch, so the fit takes the "
            "gyro's damping into the tail (a tail or fin arm at its bound, large inertias; "
            "docs/calibration.md)")
