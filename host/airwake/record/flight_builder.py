"""The flight-table builder: per-message tables on the host timeline -> one flight table.

    streams = {"rover/ins": MessageTable(t_s, ins_rows), "base/pilot_inputs": ..., ...}
    built = build_flight_table(streams, FlightBuildConfig(ned_origin_lla=(lat, lon, 0.0)))
    write_flight_table(built.df, "flight.parquet", {**built.metadata, "source": "recorder"})

Input: `MessageTable(t_s, data)` per "<board>/<message>" key, `t_s` (N,) seconds on the
host timeline and `data` (N,) a numpy structured array holding (at least) the message's
payload fields by their protocol names — exactly the rows `decode_capture` gives, or
rows a simulator fills (`message_table(name, t_s, **fields)` builds them). Nothing here
knows about recordings: `airwake export` and `airwake sim table` call the same builder.

Output (docs/flight-table.md): one row per rover INS sample (150 Hz), columns

- `t_s`; INS `roll/pitch/yaw_rad` (from `ypr_deg`, yaw wrapped to (-pi, pi]),
  `p/q/r_rad_s`, `vel_n/e/d_m_s` and body `vel_u/v/w_m_s = R(roll, pitch, yaw)^T v_ned`,
  `pos_n/e/d_m` about `ned_origin_lla`, `acc_x/y/z_m_s2` = the VN200 accel (specific
  force, body, at rest z = -g), `pdot/qdot/rdot_rad_s2` = `smooth_derivative` of p, q, r;
- `pwm_ch1..5_us` interpolated from base `pilot_inputs` and `delta_*_rad` through the
  rigging (`record.rigging`); `tail_servo_pwm_us` from rover `tail_servo`;
- `rotor_speed_rad_s` from rover `rotor_speed`;
- RTK: `rel_pos_n/e/d_m` (rover - base antenna), `rtk_fix` (0 none, 1 SPP/DGNSS, 2 float,
  3 fixed) and `height_agl_m` = hub above the deck; the receiver's Doppler velocity
  (rover `rtk_vel`, at its antenna) `gnss_vel_n/e/d_m_s` with its reported accuracy
  `gnss_vel_h_acc_m_s`, `gnss_vel_v_acc_m_s` and `gnss_vel_valid` (what the wind
  estimator measures the INS velocity error against, `airwake.estimate.ins_error`):

      height = h_base_antenna_above_deck - baseline_d - (R(att) r_antenna->hub)_d

  (+inf where there is no float or fixed RTK baseline); indoors without RTK, when
  `tracker_height_above_ground_m` is configured, the hub's height above the floor from
  the tracked marker, `tracker_d + tracker_height_above_ground_m - marker_pos_d_m -
  (R(att) r_marker->hub)_d`, where `marker_valid` (+inf elsewhere: metadata
  `height_source`);
- ship (base INS): `ship_pos_n/e/d_m`, `ship_roll/pitch/yaw_rad`, `ship_speed_m_s`,
  `ship_vel_n/e/d_m_s`; with the RTK baseline and the base antenna's place on the ship
  (`base_antenna_ship_xy_m`) the hub in the ship frame, `hub_ship_x/y/z_m` = R_ship^T
  (baseline + R(att) r_antenna->hub) + (x_b, y_b, -h_b), and `hub_ship_valid` where both
  the baseline and the base INS really had samples;
- tracker (LOSA peaks triangulated): `tracker_pos_x/y/z_m`;
- anemometer (marker): `anemo_u/v/w_m_s`, `anemo_temp_c`;
- marker pose (`record.marker_pose`, when the marker IMU, marker attitude and LOSA peaks
  are all there): the pose EKF + RTS smoother's `marker_pos_n/e/d_m`,
  `marker_vel_n/e/d_m_s`, `marker_roll/pitch/yaw_rad`, `marker_p/q/r_rad_s` in NED
  through `tracker_placement`, and `marker_valid`; metadata `marker_pose` says what was
  done or why not.

Missing data: the loader rejects NaN, so the table keeps only rows where every
**required** stream (INS, pilot inputs, rotor speed) has samples on both sides no further
apart than its gap limit; rows outside are dropped and the kept span and dropped spans go
into the metadata (`trimmed`, `gaps`). A required stream missing entirely leaves its
columns out (named in `missing_streams`; the default loader then refuses the table).
Optional streams never remove rows: their columns are interpolated with the edge values
held and a `<name>_valid` column (1.0 / 0.0) marks where the stream really was.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from airwake.errors import AirwakeError
from airwake.record.differentiate import (
    DERIVATIVE_POLYORDER,
    DERIVATIVE_WINDOW_S,
    smooth_derivative,
)
from airwake.record.geodesy import lla_to_ned
from airwake.record.marker_pose import (
    TrackerPlacement,
    marker_pose_columns,
    missing_marker_streams,
)
from airwake.record.rigging import BLADE_PITCH_COLUMNS, DEFAULT_RIGGING, PwmRigging

# Stream keys the builder reads.
ROVER_INS = "rover/ins"
BASE_INS = "base/ins"
PILOT_INPUTS = "base/pilot_inputs"
ROTOR_SPEED = "rover/rotor_speed"
TAIL_SERVO = "rover/tail_servo"
RTK_BASELINE = "rover/rtk_baseline"
RTK_VEL = "rover/rtk_vel"
LOSA_PEAKS = "losa/losa_peaks"
ANEMOMETER = "marker/anemometer"
MARKER_IMU = "marker/imu"
REQUIRED_STREAMS = (ROVER_INS, PILOT_INPUTS, ROTOR_SPEED)
# Largest spacing between two samples that a row may be interpolated across, per stream
# (about 5 nominal periods; the RTK at 10 Hz may skip an epoch or two).
DEFAULT_MAX_GAP_S = {
    ROVER_INS: 0.05, BASE_INS: 0.05, PILOT_INPUTS: 0.1, ROTOR_SPEED: 0.05, TAIL_SERVO: 0.1,
    RTK_BASELINE: 0.5, RTK_VEL: 0.5, LOSA_PEAKS: 0.05, ANEMOMETER: 0.1,
}
# SBP fix modes (rtk_baseline.fix_mode) -> the flight table's rtk_fix.
RTK_FIX_FROM_SBP = {0: 0, 1: 1, 2: 1, 3: 2, 4: 3}


class FlightBuildError(AirwakeError):
    """The streams cannot make a flight table (which stream and why is named)."""


@dataclass(frozen=True, eq=False)
class MessageTable:
    """One stream: host times `t_s` (N,) s and rows `data` (N,) with payload fields."""

    t_s: np.ndarray
    data: np.ndarray

    def __post_init__(self) -> None:
        if len(self.t_s) != len(self.data):
            raise FlightBuildError(f"message table: {len(self.t_s)} times for "
                                   f"{len(self.data)} rows")

    def __len__(self) -> int:
        return len(self.t_s)


# rtk_vel.fix_mode (SBP MSG_VEL_NED flags bits 0-2): a measured or computed Doppler
# velocity; 0 invalid and 3 dead reckoning are not measurements
GNSS_VELOCITY_MODES = (1, 2)


def gnss_velocity_columns(table: MessageTable | None, t: np.ndarray, max_gap_s: float) -> dict:
    """The GNSS receiver's velocity at the rows `t` (module docstring); {} without it."""
    if table is None or not len(table):
        return {}
    mode = np.asarray(table.data["fix_mode"], dtype=np.int64) & 0x7
    tv, rows = _sorted_unique(table, np.isin(mode, GNSS_VELOCITY_MODES))
    if not tv.size:
        return {}
    vel = np.asarray(rows["vel_ned_mm_s"], dtype=float) * 1e-3
    v = interp_columns(tv, vel, t)
    return {"gnss_vel_n_m_s": v[:, 0], "gnss_vel_e_m_s": v[:, 1], "gnss_vel_d_m_s": v[:, 2],
            "gnss_vel_h_acc_m_s": np.interp(t, tv, np.asarray(rows["h_accuracy_mm_s"],
                                                              dtype=float) * 1e-3),
            "gnss_vel_v_acc_m_s": np.interp(t, tv, np.asarray(rows["v_accuracy_mm_s"],
                                                              dtype=float) * 1e-3),
            "gnss_vel_valid": coverage(tv, t, max_gap_s).astype(float)}


def message_table(name: str, t_s: np.ndarray, **fields) -> MessageTable:
    """Rows of message `name` (protocol field names) at host times `t_s`.

    Fields not given are zero; arrays broadcast to (N,) or (N, count).
    """
    from airwake.link.batch import table_dtype
    from airwake.link.messages import BY_NAME

    info = BY_NAME.get(name)
    if info is None:
        raise FlightBuildError(f"message_table: unknown message '{name}'")
    t = np.asarray(t_s, dtype=float)
    rows = np.zeros(t.size, dtype=table_dtype(info))
    for key, value in fields.items():
        if key not in rows.dtype.names:
            raise FlightBuildError(f"message_table: '{name}' has no field '{key}'; fields are "
                                   f"{[f.name for f in info.fields]}")
        rows[key] = value
    return MessageTable(t, rows)


@dataclass(frozen=True)
class FlightBuildConfig:
    """What the streams do not say: frames, lever arms, rigging, filter settings."""

    ned_origin_lla: tuple[float, float, float] | None = None  # None: first rover INS fix, h 0
    base_antenna_height_above_deck_m: float = 0.0
    # base antenna on the ship: x forward of the hangar step, y starboard (ship frame, m)
    base_antenna_ship_xy_m: tuple[float, float] | None = None
    rover_antenna_to_hub_frd_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    tracker_height_above_ground_m: float | None = None  # indoors: height from the tracker
    tracker_placement: TrackerPlacement = TrackerPlacement()  # LOSA tracker in NED
    # indoors: marker centre -> rotor hub, helicopter body axes FRD (the hub's height from
    # the tracked marker's)
    marker_to_hub_frd_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rigging: PwmRigging = DEFAULT_RIGGING
    derivative_window_s: float = DERIVATIVE_WINDOW_S
    derivative_polyorder: int = DERIVATIVE_POLYORDER
    max_gap_s: Mapping[str, float] = field(default_factory=lambda: dict(DEFAULT_MAX_GAP_S))

    def to_dict(self) -> dict:
        return {
            "ned_origin_lla": None if self.ned_origin_lla is None else list(self.ned_origin_lla),
            "base_antenna_height_above_deck_m": self.base_antenna_height_above_deck_m,
            "base_antenna_ship_xy_m": None if self.base_antenna_ship_xy_m is None else list(
                self.base_antenna_ship_xy_m),
            "rover_antenna_to_hub_frd_m": list(self.rover_antenna_to_hub_frd_m),
            "tracker_height_above_ground_m": self.tracker_height_above_ground_m,
            "tracker_placement": self.tracker_placement.to_dict(),
            "marker_to_hub_frd_m": list(self.marker_to_hub_frd_m),
            "rigging": self.rigging.to_dict(),
            "derivative": {"method": "savitzky-golay", "window_s": self.derivative_window_s,
                           "polyorder": self.derivative_polyorder},
            "max_gap_s": dict(self.max_gap_s),
        }


@dataclass
class BuiltFlight:
    """The table and the metadata to write beside it."""

    df: pd.DataFrame
    metadata: dict


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------


def euler_to_dcm(roll: np.ndarray, pitch: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """(N, 3, 3) body -> NED, R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cy, sy = np.cos(yaw), np.sin(yaw)
    r = np.empty(np.shape(roll) + (3, 3))
    r[..., 0, 0] = cp * cy
    r[..., 0, 1] = sr * sp * cy - cr * sy
    r[..., 0, 2] = cr * sp * cy + sr * sy
    r[..., 1, 0] = cp * sy
    r[..., 1, 1] = sr * sp * sy + cr * cy
    r[..., 1, 2] = cr * sp * sy - sr * cy
    r[..., 2, 0] = -sp
    r[..., 2, 1] = sr * cp
    r[..., 2, 2] = cr * cp
    return r


def wrap_pi(a: np.ndarray) -> np.ndarray:
    """Angles into (-pi, pi]."""
    return np.pi - np.mod(np.pi - np.asarray(a, dtype=float), 2 * np.pi)


def _sorted_unique(table: MessageTable, keep: np.ndarray | None = None) -> tuple[np.ndarray,
                                                                                  np.ndarray]:
    t = np.asarray(table.t_s, dtype=float)
    rows = table.data
    ok = np.isfinite(t)
    if keep is not None:
        ok &= keep
    t, rows = t[ok], rows[ok]
    order = np.argsort(t, kind="stable")
    t, rows = t[order], rows[order]
    if t.size:
        first = np.concatenate([[True], np.diff(t) > 0])
        t, rows = t[first], rows[first]
    return t, rows


def coverage(t_src: np.ndarray, t_rows: np.ndarray, max_gap_s: float) -> np.ndarray:
    """(M,) bool: t_rows inside [t_src[0], t_src[-1]] with neighbours <= max_gap_s apart."""
    if t_src.size == 0:
        return np.zeros(t_rows.size, dtype=bool)
    if t_src.size == 1:
        return np.abs(t_rows - t_src[0]) <= 1e-9
    i = np.searchsorted(t_src, t_rows, side="right")
    inside = (i > 0) & (i < t_src.size) | (t_rows == t_src[-1])
    lo = t_src[np.clip(i - 1, 0, t_src.size - 1)]
    hi = t_src[np.clip(i, 0, t_src.size - 1)]
    return inside & (hi - lo <= max_gap_s)


def interp_columns(t_src: np.ndarray, values: np.ndarray, t_rows: np.ndarray) -> np.ndarray:
    """Linear interpolation of (N,) or (N, C) values at t_rows, edge values held."""
    v = np.asarray(values, dtype=float)
    if v.ndim == 1:
        return np.interp(t_rows, t_src, v)
    return np.stack([np.interp(t_rows, t_src, v[:, j]) for j in range(v.shape[1])], axis=-1)


def hold_previous(t_src: np.ndarray, values: np.ndarray, t_rows: np.ndarray) -> np.ndarray:
    """Zero-order hold (the last sample at or before each row; the first before that)."""
    i = np.clip(np.searchsorted(t_src, t_rows, side="right") - 1, 0, t_src.size - 1)
    return np.asarray(values)[i]


def _spans(t: np.ndarray, mask: np.ndarray) -> list[list[float]]:
    """[start, end] host times of runs of True in mask."""
    if not mask.any():
        return []
    m = mask.astype(np.int8)
    d = np.diff(np.concatenate([[0], m, [0]]))
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1
    return [[float(t[a]), float(t[b])] for a, b in zip(starts, ends, strict=True)]


def marker_pose_step(streams: Mapping[str, MessageTable], t_rows: np.ndarray,
                     cfg: FlightBuildConfig, meta: dict) -> dict[str, np.ndarray]:
    """The `marker_*` columns at t_rows when the streams allow; `meta["marker_pose"]`
    records the track or, as one line, why there is none."""
    from airwake.tracking.errors import TrackingError

    missing = missing_marker_streams(streams)
    if missing:
        meta["marker_pose"] = {"reason": f"no marker pose: the recording lacks "
                                         f"{', '.join(missing)}"}
        return {}
    try:
        cols, info = marker_pose_columns(streams, t_rows, cfg.tracker_placement)
    except TrackingError as e:
        meta["marker_pose"] = {"reason": f"no marker pose: {e}"}
        return {}
    meta["marker_pose"] = info
    return cols


def anemometer_columns(streams: Mapping[str, MessageTable], t_rows: np.ndarray,
                       max_gap_s: float) -> dict[str, np.ndarray]:
    """`anemo_u/v/w_m_s`, `anemo_temp_c`, `anemo_valid` at t_rows (status-0 samples)."""
    an = streams.get(ANEMOMETER)
    if an is None or len(an) == 0:
        return {}
    ta, arow = _sorted_unique(an, np.asarray(an.data["status"]) == 0)
    if ta.size == 0:
        return {}
    wind = interp_columns(ta, np.asarray(arow["wind_uvw_inst_m_s"], dtype=float), t_rows)
    return {"anemo_u_m_s": wind[:, 0], "anemo_v_m_s": wind[:, 1], "anemo_w_m_s": wind[:, 2],
            "anemo_temp_c": np.interp(t_rows, ta, np.asarray(arow["sonic_temp_c"], dtype=float)),
            "anemo_valid": coverage(ta, t_rows, max_gap_s).astype(float)}


def build_marker_table(streams: Mapping[str, MessageTable],
                       config: FlightBuildConfig | None = None) -> BuiltFlight:
    """A table without a helicopter (a hand-carried anemometer, docs/wind-map.md): one
    row per marker IMU sample from the marker's calibration on, the `marker_*` pose and
    the `anemo_*` columns. Missing marker or LOSA streams raise one line naming them."""
    cfg = config or FlightBuildConfig()
    missing = missing_marker_streams(streams)
    if missing:
        raise FlightBuildError(f"no marker pose: the streams lack {', '.join(missing)} "
                               f"(streams given: {sorted(streams) or 'none'})")
    gap = dict(DEFAULT_MAX_GAP_S)
    gap.update(cfg.max_gap_s)
    meta: dict = {"frame": "ned", "table": "marker",
                  "streams": {k: len(v) for k, v in sorted(streams.items())},
                  "builder": cfg.to_dict()}
    t_imu, _ = _sorted_unique(streams[MARKER_IMU])
    probe = marker_pose_step(streams, t_imu, cfg, meta)
    if not probe:
        raise FlightBuildError(meta["marker_pose"]["reason"])
    info = meta["marker_pose"]
    t = t_imu[(t_imu >= info["track_start_s"]) & (t_imu <= info["track_end_s"])]
    cols: dict[str, np.ndarray] = {"t_s": t}
    cols.update({k: v[np.searchsorted(t_imu, t)] for k, v in probe.items()})
    cols.update(anemometer_columns(streams, t, gap[ANEMOMETER]))
    df = pd.DataFrame({k: np.asarray(v, dtype=float) for k, v in cols.items()})
    dt = np.diff(t)
    meta.update({"trimmed": {"start_s": float(t[0]), "end_s": float(t[-1]),
                             "rows_dropped_head": 0, "rows_dropped_tail": 0},
                 "gaps": [], "rows_dropped_in_gaps": 0,
                 "missing_streams": [] if "anemo_u_m_s" in cols else [ANEMOMETER],
                 "rate_hz": float(1.0 / np.median(dt)) if dt.size else math.nan})
    return BuiltFlight(df, meta)


# ---------------------------------------------------------------------------
# the builder
# ---------------------------------------------------------------------------


def build_flight_table(streams: Mapping[str, MessageTable],
                       config: FlightBuildConfig | None = None) -> BuiltFlight:
    """Flight table (DataFrame) + metadata from per-message tables (see module doc)."""
    cfg = config or FlightBuildConfig()
    ins = streams.get(ROVER_INS)
    if ins is None or len(ins) == 0:
        raise FlightBuildError(f"no '{ROVER_INS}' samples: the flight table has one row per "
                               f"rover INS sample (streams given: {sorted(streams)})")
    t, rows = _sorted_unique(ins)
    if t.size < 2:
        raise FlightBuildError(f"'{ROVER_INS}' has {t.size} usable sample(s); need at least 2")
    gap = dict(DEFAULT_MAX_GAP_S)
    gap.update(cfg.max_gap_s)
    cols: dict[str, np.ndarray] = {"t_s": t}
    meta: dict = {"frame": "ned", "streams": {k: len(v) for k, v in sorted(streams.items())},
                  "builder": cfg.to_dict()}
    missing = [k for k in REQUIRED_STREAMS if k not in streams or len(streams[k]) == 0]

    # -- INS: attitude, rates, velocity, position, specific force ------------
    ypr = np.radians(np.asarray(rows["ypr_deg"], dtype=float))
    yaw, pitch, roll = wrap_pi(ypr[:, 0]), ypr[:, 1], ypr[:, 2]
    rates = np.asarray(rows["angular_rate_frd_rad_s"], dtype=float)
    vel_ned = np.asarray(rows["vel_ned_m_s"], dtype=float)
    dcm = euler_to_dcm(roll, pitch, yaw)
    vel_body = np.einsum("nji,nj->ni", dcm, vel_ned)  # R^T v
    lla = np.stack([rows["lat_deg"], rows["lon_deg"], rows["alt_m"]], axis=-1).astype(float)
    origin = cfg.ned_origin_lla
    if origin is None:
        origin = (float(lla[0, 0]), float(lla[0, 1]), 0.0)
    pos = lla_to_ned(lla, origin)
    accel = np.asarray(rows["accel_frd_m_s2"], dtype=float)
    rate_dot = smooth_derivative(t, rates, cfg.derivative_window_s, cfg.derivative_polyorder)
    cols.update({
        "pos_n_m": pos[:, 0], "pos_e_m": pos[:, 1], "pos_d_m": pos[:, 2],
        "vel_u_m_s": vel_body[:, 0], "vel_v_m_s": vel_body[:, 1], "vel_w_m_s": vel_body[:, 2],
        "roll_rad": roll, "pitch_rad": pitch, "yaw_rad": yaw,
        "p_rad_s": rates[:, 0], "q_rad_s": rates[:, 1], "r_rad_s": rates[:, 2],
        "acc_x_m_s2": accel[:, 0], "acc_y_m_s2": accel[:, 1], "acc_z_m_s2": accel[:, 2],
        "pdot_rad_s2": rate_dot[:, 0], "qdot_rad_s2": rate_dot[:, 1],
        "rdot_rad_s2": rate_dot[:, 2],
        "vel_n_m_s": vel_ned[:, 0], "vel_e_m_s": vel_ned[:, 1], "vel_d_m_s": vel_ned[:, 2],
        "ins_mode": (np.asarray(rows["ins_status"]) & 0x3).astype(float),
    })
    meta["ned_origin_lla"] = [float(x) for x in origin]
    keep = np.ones(t.size, dtype=bool)  # INS rows are the rows

    # -- required: pilot inputs, rotor speed ---------------------------------
    pi = streams.get(PILOT_INPUTS)
    if pi is not None and len(pi):
        mask = (np.asarray(pi.data["valid_mask"]) & 0x0F) == 0x0F  # channels 1..4 valid
        tp, prow = _sorted_unique(pi, mask)
        cov = coverage(tp, t, gap[PILOT_INPUTS])
        if tp.size:
            pwm = interp_columns(tp, np.asarray(prow["pwm_us"], dtype=float), t)
            for c in range(5):
                cols[f"pwm_ch{c + 1}_us"] = pwm[:, c]
            pitch_cmd = cfg.rigging.pwm_to_blade_pitch(pwm)
            for j, name in enumerate(BLADE_PITCH_COLUMNS):
                cols[name] = pitch_cmd[:, j]
        keep = keep & cov
    rs = streams.get(ROTOR_SPEED)
    if rs is not None and len(rs):
        tr, rrow = _sorted_unique(rs)
        keep = keep & coverage(tr, t, gap[ROTOR_SPEED])
        if tr.size:
            cols["rotor_speed_rad_s"] = np.interp(t, tr, np.asarray(rrow["rotor_speed_rad_s"],
                                                                    dtype=float))

    # -- optional streams -----------------------------------------------------
    ts = streams.get(TAIL_SERVO)
    if ts is not None and len(ts):
        tt, trow = _sorted_unique(ts, np.asarray(ts.data["valid"]) == 1)
        if tt.size:
            cols["tail_servo_pwm_us"] = np.interp(t, tt, np.asarray(trow["pulse_width_us"],
                                                                    dtype=float))
            cols["tail_servo_valid"] = coverage(tt, t, gap[TAIL_SERVO]).astype(float)

    height = np.full(t.size, np.inf)
    height_source = "none"
    hub_from_base = None
    bl = streams.get(RTK_BASELINE)
    if bl is not None and len(bl):
        tb_all, brow_all = _sorted_unique(bl)
        sbp_mode = np.asarray(brow_all["fix_mode"], dtype=np.int64)
        lookup = np.zeros(256, dtype=np.int64)
        for sbp, fix_code in RTK_FIX_FROM_SBP.items():
            lookup[sbp] = fix_code
        fix_all = lookup[np.clip(sbp_mode, 0, 255)]
        has_baseline = (sbp_mode >= 2) & (sbp_mode <= 4)  # SBP dgnss, float, fixed RTK
        tb = tb_all[has_baseline]
        base_ned = np.asarray(brow_all["baseline_ned_mm"], dtype=float)[has_baseline] * 1e-3
        if tb.size:
            rel = interp_columns(tb, base_ned, t)
            rel_ok = coverage(tb, t, gap[RTK_BASELINE])
            cols.update({"rel_pos_n_m": rel[:, 0], "rel_pos_e_m": rel[:, 1],
                         "rel_pos_d_m": rel[:, 2]})
            lever = np.einsum("nij,j->ni", dcm, np.asarray(cfg.rover_antenna_to_hub_frd_m,
                                                          dtype=float))
            h = cfg.base_antenna_height_above_deck_m - rel[:, 2] - lever[:, 2]
            height_source = "rtk_baseline"
            hub_from_base = rel + lever  # base antenna -> rotor hub, NED
            hub_ok = rel_ok
        fix = hold_previous(tb_all, fix_all, t) if tb_all.size else np.zeros(t.size)
        fix = np.where(coverage(tb_all, t, gap[RTK_BASELINE]), fix, 0)
        cols["rtk_fix"] = fix.astype(float)
        if height_source == "rtk_baseline":
            # a DGNSS baseline is metres off vertically: the height is known only with a
            # carrier-phase (float or fixed RTK) solution
            height = np.where(rel_ok & (fix >= 2), h, np.inf)

    cols.update(gnss_velocity_columns(streams.get(RTK_VEL), t, gap[RTK_VEL]))

    lp = streams.get(LOSA_PEAKS)
    if lp is not None and len(lp):
        from airwake.tracking.losa import SENSOR_FLAG_VALID, triangulate

        tl, lrow = _sorted_unique(lp)
        valid = (np.asarray(lrow["sensor_flags"]) & SENSOR_FLAG_VALID) != 0
        p_t, ok = triangulate(lrow["peak_px"], lrow["slot"], valid)
        tl, p_t = tl[ok], p_t[ok]
        if tl.size:
            tp_rows = interp_columns(tl, p_t, t)
            tracker_ok = coverage(tl, t, gap[LOSA_PEAKS])
            cols.update({"tracker_pos_x_m": tp_rows[:, 0], "tracker_pos_y_m": tp_rows[:, 1],
                         "tracker_pos_z_m": tp_rows[:, 2],
                         "tracker_valid": tracker_ok.astype(float)})
    cols.update(marker_pose_step(streams, t, cfg, meta))
    if (cfg.tracker_height_above_ground_m is not None and height_source == "none"
            and "marker_valid" in cols):
        # indoors: the hub's height from the tracked marker's where its pose is LOSA-aided
        # (a raw triangulation can be metres off on a wrong slot; the INS height is metres
        # off without RTK), unknown (+inf) elsewhere
        ground_d = (cfg.tracker_placement.position_ned_m[2]
                    + cfg.tracker_height_above_ground_m)
        to_hub = np.einsum("nij,j->ni", dcm, np.asarray(cfg.marker_to_hub_frd_m, float))
        height = np.where(cols["marker_valid"] > 0.5,
                          ground_d - cols["marker_pos_d_m"] - to_hub[:, 2], np.inf)
        height_source = "tracked_marker"
    cols["height_agl_m"] = height
    meta["height_source"] = height_source

    bi = streams.get(BASE_INS)
    if bi is not None and len(bi):
        tsh, srow = _sorted_unique(bi)
        if tsh.size:
            s_ypr = np.radians(np.asarray(srow["ypr_deg"], dtype=float))
            s_lla = np.stack([srow["lat_deg"], srow["lon_deg"], srow["alt_m"]],
                             axis=-1).astype(float)
            s_pos = interp_columns(tsh, lla_to_ned(s_lla, origin), t)
            s_vel = np.asarray(srow["vel_ned_m_s"], dtype=float)
            cols.update({
                "ship_pos_n_m": s_pos[:, 0], "ship_pos_e_m": s_pos[:, 1],
                "ship_pos_d_m": s_pos[:, 2],
                "ship_roll_rad": np.interp(t, tsh, s_ypr[:, 2]),
                "ship_pitch_rad": np.interp(t, tsh, s_ypr[:, 1]),
                "ship_yaw_rad": wrap_pi(np.interp(t, tsh, np.unwrap(s_ypr[:, 0]))),
                "ship_speed_m_s": np.interp(t, tsh, np.hypot(s_vel[:, 0], s_vel[:, 1])),
                "ship_vel_n_m_s": np.interp(t, tsh, s_vel[:, 0]),
                "ship_vel_e_m_s": np.interp(t, tsh, s_vel[:, 1]),
                "ship_vel_d_m_s": np.interp(t, tsh, s_vel[:, 2]),
                "ship_valid": coverage(tsh, t, gap[BASE_INS]).astype(float),
            })
            if hub_from_base is not None and cfg.base_antenna_ship_xy_m is not None:
                # the hub in the ship frame (x bow, y starboard, z down from the deck, origin
                # at the hangar step): the baseline rotated by the ship's attitude, plus the
                # base antenna's place on the ship
                ship_dcm = euler_to_dcm(cols["ship_roll_rad"], cols["ship_pitch_rad"],
                                        cols["ship_yaw_rad"])
                hub = np.einsum("nji,nj->ni", ship_dcm, hub_from_base)
                xb, yb = (float(v) for v in cfg.base_antenna_ship_xy_m)
                cols.update({"hub_ship_x_m": hub[:, 0] + xb, "hub_ship_y_m": hub[:, 1] + yb,
                             "hub_ship_z_m": hub[:, 2] - cfg.base_antenna_height_above_deck_m,
                             "hub_ship_valid": (hub_ok & (cols["ship_valid"] > 0.5))
                             .astype(float)})

    cols.update(anemometer_columns(streams, t, gap[ANEMOMETER]))

    # -- trim to the rows every required stream covers ------------------------
    if not keep.any():
        raise FlightBuildError(
            "no rover INS sample is covered by every required stream "
            f"({', '.join(k for k in REQUIRED_STREAMS if k in streams)}): the streams do "
            "not overlap in host time")
    first, last = int(np.argmax(keep)), int(keep.size - 1 - np.argmax(keep[::-1]))
    meta["trimmed"] = {"start_s": float(t[first]), "end_s": float(t[last]),
                       "rows_dropped_head": first, "rows_dropped_tail": int(keep.size - 1 - last),
                       "ins_start_s": float(t[0]), "ins_end_s": float(t[-1])}
    inner = ~keep
    inner[:first] = False
    inner[last + 1:] = False
    meta["gaps"] = _spans(t, inner)
    meta["rows_dropped_in_gaps"] = int(inner.sum())
    meta["missing_streams"] = missing
    df = pd.DataFrame({k: np.asarray(v, dtype=float)[keep] for k, v in cols.items()})
    dt = np.diff(df["t_s"].to_numpy())
    meta["rate_hz"] = float(1.0 / np.median(dt)) if dt.size else math.nan
    return BuiltFlight(df, meta)
