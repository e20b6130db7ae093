"""The INS velocity error, measured on the flight itself against the GNSS receiver's
Doppler velocity.

The wind is the air velocity over the ground, so the INS velocity error goes one to one
into the mean-flow estimate; its size is the floor of the wind's uncertainty. Instead of
a number (a datasheet's, or the simulator's), it is measured on every flight that carries
the receiver's velocity (`gnss_vel_*` in the flight table, from the rover's `rtk_vel`):

1. the INS velocity moved to the GNSS antenna, v_ant = v_ins + R(att) (omega x r_ant),
   with r_ant the antenna's place from the rotor hub (the flight's `builder` metadata;
   the host takes the INS to be at the hub, as its model does);
2. the GNSS latency: the delay tau in [MIN_LAG_S, MAX_LAG_S] (negative: the INS's
   solution is the later one) that minimises the mean square of
   v_gnss(t) - v_ant(t - tau), both less their 2 s moving means (the slow INS error
   left out, the manoeuvres align them) (a receiver's velocity arrives 50-150 ms late);
3. the difference averaged over AVERAGE_S (the INS error is slow, the Doppler noise
   white), its mean square per axis less the averaged Doppler noise (the receiver's own
   reported accuracy, over the independent samples in the window), floored at 0:

       std_ins^2 = mean over axes of [ mean_t (d_avg^2) - acc_axis^2 / n_window ].

Without a valid GNSS velocity for at least MIN_SECONDS (indoors) the user's value is
needed; `airwake wind estimate` falls back to the VN-200 datasheet's 0.05 m/s and says so
(`ins_velocity_std_source`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# VN-200 datasheet: velocity accuracy 0.05 m/s (1 sigma): the fallback when the flight
# carries no GNSS velocity to measure the error against
DATASHEET_VELOCITY_STD_M_S = 0.05
AVERAGE_S = 1.0
MAX_LAG_S = 0.5
MIN_LAG_S = -0.2  # the INS's own solution may be the later one
LAG_STEP_S = 0.01
LAG_HIGHPASS_S = 2.0
MIN_SECONDS = 10.0
GNSS_COLUMNS = ("gnss_vel_n_m_s", "gnss_vel_e_m_s", "gnss_vel_d_m_s")


@dataclass
class InsVelocityError:
    std_m_s: float
    source: str  # "gnss" (measured), "user", "datasheet"
    detail: dict

    def to_dict(self) -> dict:
        return {"ins_velocity_std_m_s": self.std_m_s, "ins_velocity_std_source": self.source,
                "ins_velocity_error": self.detail}


def ins_velocity_error(df, metadata: dict | None = None,
                       user_std: float | None = None) -> InsVelocityError:
    """The flight's INS velocity error (module docstring): the user's value when given,
    else measured against the GNSS velocity, else the datasheet's with the reason."""
    if user_std is not None:
        return InsVelocityError(float(user_std), "user", {})
    measured = measure_against_gnss(df, metadata or {})
    if isinstance(measured, str):
        return InsVelocityError(DATASHEET_VELOCITY_STD_M_S, "datasheet",
                                {"why": measured,
                                 "advice": "give --ins-velocity-std (the INS's reported "
                                           "velocity uncertainty) for a flight without GNSS"})
    return InsVelocityError(measured["std_m_s"], "gnss", measured)


def measure_against_gnss(df, metadata: dict) -> dict | str:
    """{std_m_s, per-axis std, lag_s, seconds, ...} or why it cannot be measured."""
    if not all(c in df.columns for c in GNSS_COLUMNS):
        return "the flight has no GNSS velocity (gnss_vel_* columns)"
    t = df["t_s"].to_numpy(dtype=float)
    valid = df["gnss_vel_valid"].to_numpy(dtype=float) > 0.5 if "gnss_vel_valid" in \
        df.columns else np.ones(t.size, bool)
    dt = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    seconds = float(valid.sum() * dt)
    if seconds < MIN_SECONDS:
        return (f"the flight has {seconds:.1f} s of valid GNSS velocity "
                f"(at least {MIN_SECONDS:g} s needed)")
    gnss = df[list(GNSS_COLUMNS)].to_numpy(dtype=float)
    ant = _ins_at_antenna(df, metadata)
    lag, ms = _best_lag(t, gnss, ant, valid)
    ins_lagged = np.column_stack([np.interp(t - lag, t, ant[:, i]) for i in range(3)])
    diff = np.where(valid[:, None], gnss - ins_lagged, np.nan)
    width = max(int(round(AVERAGE_S / dt)), 1)
    avg = _moving_mean(diff, width)
    ok = np.all(np.isfinite(avg), axis=1)
    if ok.sum() * dt < MIN_SECONDS:
        return "too few whole averaging windows of valid GNSS velocity"
    # the Doppler noise left in a window's mean: its reported accuracy over the window's
    # independent receiver samples (the receiver's own rate, from its value changes)
    rate = _receiver_rate_hz(t[valid], gnss[valid])
    n_window = max(rate * AVERAGE_S, 1.0)
    h_acc = df["gnss_vel_h_acc_m_s"].to_numpy(float)[ok] if "gnss_vel_h_acc_m_s" in \
        df.columns else np.zeros(ok.sum())
    v_acc = df["gnss_vel_v_acc_m_s"].to_numpy(float)[ok] if "gnss_vel_v_acc_m_s" in \
        df.columns else np.zeros(ok.sum())
    noise = np.array([np.mean(h_acc**2) / 2.0, np.mean(h_acc**2) / 2.0,
                      np.mean(v_acc**2)]) / n_window
    var = np.maximum(np.mean(avg[ok] ** 2, axis=0) - noise, 0.0)
    return {"std_m_s": float(np.sqrt(np.mean(var))),
            "std_ned_m_s": np.sqrt(var).round(4).tolist(),
            "mean_ned_m_s": np.mean(avg[ok], axis=0).round(4).tolist(),
            "gnss_lag_s": round(float(lag), 3), "gnss_rate_hz": round(rate, 2),
            "gnss_noise_removed_m_s": np.sqrt(noise).round(4).tolist(),
            "seconds": round(float(ok.sum() * dt), 1), "rms_at_lag_m_s": round(ms, 4)}


def _ins_at_antenna(df, metadata: dict) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    v = df[["vel_n_m_s", "vel_e_m_s", "vel_d_m_s"]].to_numpy(dtype=float)
    builder = metadata.get("builder") or {}
    to_hub = np.asarray(builder.get("rover_antenna_to_hub_frd_m", (0.0, 0.0, 0.0)), float)
    r_ant = -to_hub  # the antenna from the hub, body axes
    if not np.any(r_ant):
        return v
    omega = df[["p_rad_s", "q_rad_s", "r_rad_s"]].to_numpy(dtype=float)
    att = df[["yaw_rad", "pitch_rad", "roll_rad"]].to_numpy(dtype=float)
    return v + Rotation.from_euler("ZYX", att).apply(np.cross(omega, r_ant))


def _best_lag(t, gnss, ant, valid) -> tuple[float, float]:
    """The delay of the GNSS velocity behind the INS's and the RMS difference there: the
    two compared after removing their LAG_HIGHPASS_S moving means (the INS error is slow;
    what aligns them is the manoeuvring), the minimum refined by a parabola."""
    dt = float(np.median(np.diff(t)))
    width = max(int(round(LAG_HIGHPASS_S / dt)), 1)
    g = np.where(valid[:, None], gnss, np.nan)
    g_hp = g - _moving_mean(g, width)
    lags = np.arange(MIN_LAG_S, MAX_LAG_S + 1e-9, LAG_STEP_S)
    cost = np.empty(lags.size)
    for i, lag in enumerate(lags):
        shifted = np.column_stack([np.interp(t - lag, t, ant[:, j]) for j in range(3)])
        d = g_hp - (shifted - _moving_mean(shifted, width))
        cost[i] = np.nanmean(d**2) if np.isfinite(d).any() else np.inf
    k = int(np.argmin(cost))
    lag = float(lags[k])
    if 0 < k < lags.size - 1:
        c0, c1, c2 = cost[k - 1], cost[k], cost[k + 1]
        curve = c0 - 2.0 * c1 + c2
        if curve > 0:
            lag += 0.5 * (c0 - c2) / curve * LAG_STEP_S
    shifted = np.column_stack([np.interp(t - lag, t, ant[:, j]) for j in range(3)])
    return lag, float(np.sqrt(np.mean((gnss[valid] - shifted[valid]) ** 2)))


def _moving_mean(x: np.ndarray, width: int) -> np.ndarray:
    """Centred mean over `width` rows; NaN where the window holds a NaN or leaves the
    flight."""
    n = x.shape[0]
    out = np.full_like(x, np.nan)
    if n < width:
        return out
    finite = np.isfinite(x)
    c = np.cumsum(np.vstack([np.zeros((1, x.shape[1])), np.where(finite, x, 0.0)]), axis=0)
    k = np.cumsum(np.vstack([np.zeros((1, x.shape[1])), finite]), axis=0)
    means = (c[width:] - c[:-width]) / width
    means[(k[width:] - k[:-width]) < width] = np.nan
    half = width // 2
    out[half:half + means.shape[0]] = means
    return out


def _receiver_rate_hz(t: np.ndarray, gnss: np.ndarray) -> float:
    """The receiver's own update rate: how often its (interpolated) velocity changes
    slope, i.e. the number of distinct samples over the span."""
    if t.size < 3:
        return 1.0
    slope = np.diff(gnss, axis=0) / np.diff(t)[:, None]
    kink = np.any(np.abs(np.diff(slope, axis=0)) > 1e-9, axis=1)
    # a receiver sample between two rows bends the line at both: count runs, not rows
    knots = int(np.sum(kink[1:] & ~kink[:-1]) + kink[0])
    return float(max(knots, 1) / max(t[-1] - t[0], 1e-9))
