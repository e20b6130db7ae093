"""One-line physical reasons, generated from the data, for a candidate's fit.

Each reason names the channels the candidate explains (share of their residual variance),
the fitted parameter values, and the physical variable its signature follows, measured
on this flight (binned means or a correlation), e.g.
"az residual -0.52 m/s² at z < 1 R, -0.08 at 1-2 R, +0.00 above 3 R — grows as (R/4z)²
near the ground (strength 0.97): ground effect".
"""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.data import CHANNEL_LABELS, CHANNEL_UNITS
from airwake.heli.context import MEAS_CHANNELS


def _channels(res, threshold: float = 0.15) -> str:
    parts = [f"{CHANNEL_LABELS[c]} {100 * v:.0f} %" for c, v in
             zip(MEAS_CHANNELS, res.explained_channels, strict=True) if v >= threshold]
    if not parts:
        j = int(np.argmax(res.explained_channels))
        parts = [f"{CHANNEL_LABELS[MEAS_CHANNELS[j]]} {100 * res.explained_channels[j]:.0f} %"]
    return "explains " + ", ".join(parts)


def _binned(an, values, bins, labels, channel: int) -> str:
    r = an.residual_band[:, channel]
    m = an.mask & np.isfinite(values)
    out = []
    for (lo, hi), lab in zip(bins, labels, strict=True):
        sel = m & (values >= lo) & (values < hi)
        if sel.sum() >= 20:
            out.append(f"{r[sel].mean():+.2f} {lab}")
    unit = CHANNEL_UNITS[MEAS_CHANNELS[channel]]
    return f"{CHANNEL_LABELS[MEAS_CHANNELS[channel]]} residual " + ", ".join(out) + f" ({unit})"


def _corr(a, b, mask) -> float:
    a, b = a[mask], b[mask]
    if a.std() == 0 or b.std() == 0:
        return 0.0
    return float(np.corrcoef(a, b)[0, 1])


def _main_channel(res) -> int:
    return int(np.argmax(res.explained_channels))


def reason_for(an, res) -> str:
    fn = _REASONS.get(res.name)
    head = _channels(res)
    try:
        body = fn(an, res) if fn else ""
    except Exception as exc:  # noqa: BLE001 — a reason must never break the diagnosis
        body = f"(no reason: {type(exc).__name__})"
    return f"{body}; {head}" if body else head


def _radius(an) -> float:
    return float(an.model["main_rotor"].parameters()["radius_m"])


def _ground_effect(an, res):
    zr = an.flight.column("height_agl_m") / _radius(an)
    text = _binned(an, zr, [(0, 1), (1, 2), (3, np.inf)], ["at z < 1 R", "at 1-2 R",
                                                           "above 3 R"], 2)
    return f"{text} — grows as (R/4z)² near the ground (strength " \
           f"{res.params.get('strength', 0):.2f}): ground effect"


def _lever(an, res):
    p = res.params
    return (f"ax, ay, az residuals ∝ ω̇×r + ω×(ω×r) with r ≈ ({p.get('x_m', 0):.3f}, "
            f"{p.get('y_m', 0):.3f}, {p.get('z_m', 0):.3f}) m (the angular channels only "
            "through the IMU point's velocity the INS reports): IMU lever arm")


def _servo(an, res):
    from airwake.record.differentiate import smooth_derivative

    fl = an.flight
    j = _main_channel(res)
    rates = smooth_derivative(fl.t, np.column_stack([fl.column(c) for c in (
        "delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad")]))
    rb = an.band(rates)
    corr = max(abs(_corr(an.residual_band[:, j], rb[:, k], an.mask)) for k in range(4))
    p = res.params
    return (f"{CHANNEL_LABELS[MEAS_CHANNELS[j]]} residual follows the input rates "
            f"(|corr| {corr:.2f} with dδ/dt), as -τ dδ/dt: τ ≈ "
            f"{1000 * p.get('tau_swash_s', 0):.0f} ms swashplate, "
            f"{1000 * p.get('tau_tail_s', 0):.0f} ms tail: servo lag")


def _droop(an, res):
    fl = an.flight
    om = fl.column("rotor_speed_rad_s")
    nominal = float(an.model["main_rotor"].parameters()["nominal_speed_rad_s"])
    j = _main_channel(res)
    c = _corr(an.residual_band[:, j], an.band(om - nominal), an.mask)
    lo, hi = np.percentile(om[an.mask], [2, 98])
    return (f"{CHANNEL_LABELS[MEAS_CHANNELS[j]]} residual ∝ (Ω_meas − Ω*) (corr {c:+.2f}; Ω "
            f"{lo:.0f}-{hi:.0f} rad/s vs Ω* {nominal:.1f}), gain "
            f"{res.params.get('tachometer_gain', 0):.2f}: rotor-speed droop")


def _inflow(an, res):
    from airwake.record.differentiate import smooth_derivative

    fl = an.flight
    rate = an.band(smooth_derivative(fl.t, fl.column("delta_col_rad")))
    c = _corr(an.residual_band[:, 2], rate, an.mask)
    return (f"az residual in phase with the collective rate (corr {c:+.2f}), a thrust "
            f"overshoot decaying with τ ≈ {1000 * res.params.get('tau_s', 0):.0f} ms: "
            "inflow dynamics")


def _recirc(an, res):
    fl = an.flight
    zr = fl.column("height_agl_m") / _radius(an)
    speed = np.hypot(fl.column("vel_u_m_s"), fl.column("vel_v_m_s"))
    low = zr < 1.5
    vals = np.where(low, speed, np.nan)
    text = _binned(an, vals, [(0, 0.5), (1, 2.5), (2.5, 4.5), (4.5, np.inf)],
                   ["hovering low", "at 1-2.5 m/s low", "at 2.5-4.5 m/s low", "faster"], 2)
    p = res.params
    return (f"{text} — a thrust loss near the ground peaking at "
            f"{p.get('peak_airspeed_m_s', 0):.1f} m/s, none in hover (inflow +"
            f"{100 * p.get('inflow_increase', 0):.0f} %): wake recirculation")


def _bias(an, res):
    p = res.params
    return (f"constant offsets ({p.get('bx_m_s2', 0):+.3f}, {p.get('by_m_s2', 0):+.3f}, "
            f"{p.get('bz_m_s2', 0):+.3f}) m/s² in ax, ay, az that no regime explains: "
            "accelerometer bias")


def _misalign(an, res):
    p = res.params
    return (f"a residual ∝ the specific force rotated by ({1000 * p.get('ex_rad', 0):+.1f}, "
            f"{1000 * p.get('ey_rad', 0):+.1f}, {1000 * p.get('ez_rad', 0):+.1f}) mrad: "
            "accelerometer misalignment")


def _cg(an, res):
    p = res.params
    return (f"moment residuals ∝ rotor force: CG at ({100 * p.get('x_m', 0):+.1f}, "
            f"{100 * p.get('y_m', 0):+.1f}, {100 * p.get('z_m', 0):+.1f}) cm, mass "
            f"{p.get('mass_error_kg', 0):+.2f} kg: mass / CG offset")


def _drag(an, res):
    fl = an.flight
    u = fl.column("vel_u_m_s")
    c = _corr(an.residual_band[:, 0], an.band(u * np.abs(u)), an.mask)
    p = res.params
    return (f"ax residual ∝ u|u| (corr {c:+.2f}): extra drag areas ({p.get('dcx_m2', 0):+.3f}, "
            f"{p.get('dcy_m2', 0):+.3f}, {p.get('dcz_m2', 0):+.3f}) m²: fuselage drag error")


def _advance(an, res):
    from airwake.discrepancy.candidates import air_velocity_uv

    u, v = air_velocity_uv(an.flight, an.wind)
    c = max(abs(_corr(an.residual_band[:, j], an.band(w), an.mask)) for j in (3, 4)
            for w in (u, v))
    p = res.params
    return (f"roll/pitch residuals follow the airspeed across the disc (|corr| {c:.2f} with "
            f"u or v): cyclic per advance ratio k = ({p.get('k_cx', 0):+.2f}, "
            f"{p.get('k_cy', 0):+.2f}; {p.get('k_sx', 0):+.2f}, {p.get('k_sy', 0):+.2f}) rad: "
            "the rotor's blow-back / inflow roll differ from the model's")


def _torque(an, res):
    from airwake.discrepancy.candidates import air_velocity_uv

    u, v = air_velocity_uv(an.flight, an.wind)
    c = _corr(an.residual_band[:, 5], an.band(u * u + v * v), an.mask)
    return (f"yaw residual follows the airspeed squared (corr {c:+.2f}): the rotor torque "
            f"falls with airspeed by k_q = {res.params.get('k_q', 0):+.2f} of itself at the "
            "hover induced velocity beyond the model's")


_REASONS = {
    "advance_cyclic": _advance, "advance_torque": _torque,
    "ground_effect": _ground_effect, "imu_lever_arm": _lever, "servo_lag": _servo,
    "rotor_droop": _droop, "dynamic_inflow": _inflow, "wake_recirculation": _recirc,
    "accel_bias": _bias, "accel_misalignment": _misalign, "cg_offset": _cg,
    "fuselage_drag_error": _drag,
}
