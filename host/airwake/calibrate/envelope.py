"""The calibration envelope: which air velocities and rotation rates the calibration flight
covered, and so which wind components the fitted model can be trusted for.

    env = flight_envelope(data, model)       # from the calibration's FlightData (still air)
    trust = wind_trust(env)                  # per wind component: trusted?, range, why
    inside = envelope_fraction(env, air_velocity_body_m_s)   # (3,) share of samples inside

The wind reaches the model only as air velocity relative to the airframe (eq 5.3 wind
minus the body's own velocity) and rotation relative to it (wind rotation minus the body
rates). In still air the calibration flight's air velocity is minus its own velocity, so
the fitted model's speed-dependent terms — fuselage and empennage drag, blow-back, tail
rotor inflow — are identified over the velocities flown and extrapolated beyond them. A
mean-flow component is reported trusted when the flight spanned at least
`MIN_SPAN_M_S` along that body axis; the wind estimator checks each sample's air velocity
against the flown range (percentiles 1-99) and says how much of the flight lies outside.
Rotation components are identified through the body rates the chirps and bursts excite.
"""

from __future__ import annotations

import numpy as np

PERCENTILES = (1.0, 99.0)
MIN_SPAN_M_S = 2.0  # e.g. -1 ... +1 m/s along the axis
MIN_RATE_SPAN_RAD_S = 0.2
AXES = ("x", "y", "z")
VELOCITY_STATES = ("vel_u_m_s", "vel_v_m_s", "vel_w_m_s")
RATE_STATES = ("p_rad_s", "q_rad_s", "r_rad_s")


def _ranges(a: np.ndarray) -> list:
    lo, hi = np.percentile(a, PERCENTILES, axis=0)
    return [[float(x), float(y)] for x, y in zip(lo, hi, strict=True)]


def flight_envelope(data, model) -> dict:
    """Air velocity (body axes, = -body velocity in still air) and body-rate ranges of a
    calibration flight (`airwake.calibrate.residuals.FlightData`)."""
    vel = np.column_stack([data.x[:, model.state_index(s)] for s in VELOCITY_STATES])
    rates = np.column_stack([data.x[:, model.state_index(s)] for s in RATE_STATES])
    return {
        "air_velocity_body_m_s": dict(zip(AXES, _ranges(-vel), strict=True)),
        "body_rates_rad_s": dict(zip(AXES, _ranges(rates), strict=True)),
        "percentiles": list(PERCENTILES),
        "samples": int(data.t.size),
        "duration_s": float(data.t[-1] - data.t[0]) if data.t.size else 0.0,
    }


def wind_trust(env: dict) -> dict:
    """Per wind component (vx ... wz): {"trusted": bool, "range": [lo, hi], "why": str}."""
    out = {}
    for axis in AXES:
        lo, hi = env["air_velocity_body_m_s"][axis]
        ok = hi - lo >= MIN_SPAN_M_S
        why = (f"air velocity {lo:+.2f} ... {hi:+.2f} m/s flown along body {axis}: the "
               "speed-dependent terms are identified in that range" if ok else
               f"only {lo:+.2f} ... {hi:+.2f} m/s flown along body {axis} (less than "
               f"{MIN_SPAN_M_S:g} m/s of span): the drag and blow-back terms along this axis "
               "were not exercised; winds along it rest on the starting values")
        out[f"v{axis}"] = {"trusted": bool(ok), "range": [lo, hi], "why": why}
    for axis in AXES:
        lo, hi = env["body_rates_rad_s"][axis]
        ok = hi - lo >= MIN_RATE_SPAN_RAD_S
        why = (f"body rates {lo:+.2f} ... {hi:+.2f} rad/s about {axis}: the rotor's "
               "aerodynamic response to rotation is identified" if ok else
               f"body rates only {lo:+.2f} ... {hi:+.2f} rad/s about {axis}: the rotor's "
               "response to rotation about this axis was not exercised")
        out[f"w{axis}"] = {"trusted": bool(ok), "range": [lo, hi], "why": why}
    return out


def envelope_fraction(env: dict, air_velocity_body_m_s: np.ndarray) -> np.ndarray:
    """(3,) share of the rows of `air_velocity_body_m_s` (N, 3) inside the calibrated
    air-velocity range of each body axis (a small margin of 10 % of the span allowed)."""
    a = np.atleast_2d(np.asarray(air_velocity_body_m_s, dtype=float))
    out = np.empty(3)
    for j, axis in enumerate(AXES):
        lo, hi = env["air_velocity_body_m_s"][axis]
        margin = 0.1 * (hi - lo)
        out[j] = float(np.mean((a[:, j] >= lo - margin) & (a[:, j] <= hi + margin))) if len(
            a) else float("nan")
    return out
