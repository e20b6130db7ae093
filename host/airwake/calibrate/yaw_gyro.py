"""Is a yaw-rate gyro acting between the rudder channel and the tail servo, and how much of
a fitted model's yaw damping is its?

    found = yaw_gyro(flight_df)                      # dict, or None when the flight cannot say
    aero = aero_yaw_damping(flight_df, found)        # the airframe's own yaw damping
    share = effect_gain(model, found, aero)          # the catalogue's yaw_gyro gain

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
PEDAL = "delta_ped_rad"  # the tail pitch the model reads, the rigging's map of pwm_ch4_us
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


def aero_yaw_damping(df, found: dict | None, cutoff_hz: float | None = 6.0) -> dict | None:
    """The airframe's yaw damping relative to the air, read with the tail pitch the servo
    flies instead of the rudder's: after the wind estimator's front end (`cutoff_hz`
    zero-phase low-pass), the measured yaw acceleration regressed by least squares on

        r_dot = c + B_t theta_servo - N_a r + k_col delta_col + k_v v + k_u u^2 + e,

    theta_servo the rudder's tail pitch (`delta_ped_rad`) plus the servo's pulse less the
    rudder's and the gyro's neutral, times the rigging's tail pitch per us (`delta_ped_rad`
    regressed on `pwm_ch4_us`); the collective's torque, the sideslip's tail and fin force
    and the airspeed's torque change (`advance_torque`) as the other regressors. With the
    gyro's loop out of the input the rate's coefficient is the tail rotor's and the fin's
    damping alone. {"damping_1_s": N_a, "pedal_1_s2": B_t, "explained": R^2, "rows"};
    None when no gyro was found or a column is missing."""
    need = (*COLUMNS, PEDAL, "delta_col_rad", "vel_u_m_s", "vel_v_m_s", "rdot_rad_s2", "t_s")
    if not found or not found["found"] or any(c not in df.columns for c in need):
        return None
    col = {c: np.asarray(df[c], float) for c in need}
    ok = (col["tail_servo_valid"] > 0) & np.all([np.isfinite(v) for v in col.values()], 0)
    if ok.sum() < MIN_ROWS:
        return None
    col = {c: v[ok] for c, v in col.items()}
    us, rad = col["pwm_ch4_us"], col[PEDAL]
    if np.ptp(us) <= 0:
        return None
    per_us = float(np.polyfit(us, rad, 1)[0])
    servo = rad + per_us * (col["tail_servo_pwm_us"] - us - found["neutral_us"])
    sig = {"servo": servo, **{c: col[c] for c in ("r_rad_s", "delta_col_rad", "vel_u_m_s",
                                                    "vel_v_m_s", "rdot_rad_s2")}}
    if cutoff_hz:
        from scipy.signal import butter, sosfiltfilt

        from airwake.estimate.prefilter import FILTER_ORDER

        fs = 1.0 / float(np.median(np.diff(col["t_s"])))
        if cutoff_hz < 0.45 * fs:  # the estimator's front end, as calibrate's residual
            sos = butter(FILTER_ORDER, cutoff_hz, fs=fs, output="sos")
            sig = {k: sosfiltfilt(sos, v) for k, v in sig.items()}
    a = np.column_stack([np.ones_like(servo), sig["servo"], sig["r_rad_s"],
                         sig["delta_col_rad"], sig["vel_v_m_s"], sig["vel_u_m_s"] ** 2])
    y = sig["rdot_rad_s2"]
    coef, *_ = np.linalg.lstsq(a, y, rcond=None)
    var = float(np.var(y))
    explained = 0.0 if var <= 0 else float(1.0 - np.var(y - a @ coef) / var)
    return {"damping_1_s": float(-coef[2]), "pedal_1_s2": float(coef[1]),
            "explained": explained, "rows": int(len(y)), "per_us": per_us}


def effect_gain(model, found: dict | None, aero: dict | None) -> dict | None:
    """The gain of the catalogue's `yaw_gyro` effect for a model fitted with the rudder as
    its tail pitch: the share of the model's yaw damping beyond the airframe's aerodynamic
    damping is the gyro's, which answers the inertial rate. At the model's hover trim,
    N_m = -d r_dot / d r and B_m = d r_dot / d delta_ped; the effect's tail-pitch gain
    g = -(N_m - N_a) / B_m turns N_m's answer to the air's rotation into N_a's. Held
    between the gyro's own gain (its slope times the rigging's tail pitch per us, the
    whole loop) and 0 (a model with no more damping than the airframe's has no gyro share
    to take out). {"model_damping_1_s", "model_pedal_1_s2", "gain_rad_per_rad_s",
    "gyro_gain_rad_per_rad_s"}; None when no gyro, no aerodynamic damping or no trim."""
    if aero is None or not found or not found["found"]:
        return None
    from airwake.heli.trim import trim_hover

    try:
        tr = trim_hover(model)
    except Exception:  # noqa: BLE001 - a model with no hover trim: say nothing
        return None
    x, u = tr.x[None], tr.u[None]
    h = 1e-4
    i_r = list(model.state_names).index("rigid_body.r_rad_s")
    dx, du = x.copy(), u.copy()
    dx[0, i_r] += h
    du[0, 3] += h
    z0 = model.measure(x, u)[0, 5]
    n_m = -float(model.measure(dx, u)[0, 5] - z0) / h
    b_m = float(model.measure(x, du)[0, 5] - z0) / h
    if not (np.isfinite(n_m) and np.isfinite(b_m)) or b_m <= 0:
        return None
    gyro = found["slope_us_per_rad_s"] * aero["per_us"]
    g = max(min(0.0, -(n_m - aero["damping_1_s"]) / b_m), min(gyro, 0.0))
    return {"model_damping_1_s": n_m, "model_pedal_1_s2": b_m, "gain_rad_per_rad_s": g,
            "gyro_gain_rad_per_rad_s": gyro}


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
