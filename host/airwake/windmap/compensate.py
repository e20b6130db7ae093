"""Motion compensation of a carried anemometer (reference §3.4): the sensor equation
inverted with the tracked pose.

The anemometer measures the air velocity relative to itself in its own axes
(`hil_sim.sensors.anemometer`):

    w_meas = M^T R^T (w(p_s) - v_s),   p_s = p + R r,   v_s = v + R (omega x r)

with R the attitude (body -> NED, roll/pitch/yaw), p and v the tracked reference point's
position and velocity (NED), omega its body rates, r the lever arm from the reference
point to the anemometer's sensing volume (body axes) and M the anemometer's axes relative
to the body's (anemometer -> body; identity when the marker is mounted with the
anemometer's axes). Inverted:

    w(p_s) = R (M w_meas + omega x r) + v

Pose sources (columns of the table, docs/flight-table.md "Anemometer pose"):
- "marker": the tracked marker (pose EKF) — `marker_pos_n/e/d_m`,
  `marker_vel_n/e/d_m_s`, `marker_roll/pitch/yaw_rad`, `marker_p/q/r_rad_s`;
- "truth": a simulated table's truth pose of the carrier — `truth_pos_n/e/d_m`,
  `truth_vel_u/v/w_m_s` (body axes), `truth_roll/pitch/yaw_rad`, `truth_p/q/r_rad_s`.
The lever arm r comes from the table's metadata `anemometer_lever_arm_m` and M from
`anemometer_mount_quat_wxyz` (w, x, y, z; anemometer -> body), or are given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from airwake.windmap.errors import WindMapError

ANEMOMETER = ("anemo_u_m_s", "anemo_v_m_s", "anemo_w_m_s")
POSE_SOURCES = {
    "marker": {"pos": ("marker_pos_n_m", "marker_pos_e_m", "marker_pos_d_m"),
               "vel": ("marker_vel_n_m_s", "marker_vel_e_m_s", "marker_vel_d_m_s"),
               "vel_frame": "ned",
               "att": ("marker_roll_rad", "marker_pitch_rad", "marker_yaw_rad"),
               "rates": ("marker_p_rad_s", "marker_q_rad_s", "marker_r_rad_s")},
    "truth": {"pos": ("truth_pos_n_m", "truth_pos_e_m", "truth_pos_d_m"),
              "vel": ("truth_vel_u_m_s", "truth_vel_v_m_s", "truth_vel_w_m_s"),
              "vel_frame": "body",
              "att": ("truth_roll_rad", "truth_pitch_rad", "truth_yaw_rad"),
              "rates": ("truth_p_rad_s", "truth_q_rad_s", "truth_r_rad_s")},
}


@dataclass
class CompensatedSamples:
    """n samples: t (n,), pos (n, 3) sensor position NED, wind (n, 3) air velocity NED;
    pose ("marker" or "truth"), lever_arm_m (3,), dt (s) the median sample spacing."""

    t: np.ndarray
    pos: np.ndarray
    wind: np.ndarray
    pose: str
    lever_arm_m: np.ndarray
    dt: float
    mount_quat_wxyz: np.ndarray | None = None


def _columns(cols) -> list[str]:
    return [c for group in ("pos", "vel", "att", "rates") for c in cols[group]]


def pose_source(df, pose: str = "auto") -> str:
    """The pose source to use: `pose` checked, or the first complete one ("auto")."""
    names = list(POSE_SOURCES) if pose == "auto" else [pose]
    if pose != "auto" and pose not in POSE_SOURCES:
        raise WindMapError(f"--pose {pose!r}: expected auto, {', '.join(POSE_SOURCES)}")
    have = set(df.columns)
    for name in names:
        if set(_columns(POSE_SOURCES[name])) <= have:
            return name
    lack = {n: [c for c in _columns(POSE_SOURCES[n]) if c not in have] for n in names}
    text = "; ".join(f"{n} pose lacks {', '.join(m)}" for n, m in lack.items())
    raise WindMapError(f"the table has no anemometer pose ({text})")


def check_anemometer(df) -> None:
    missing = [c for c in ANEMOMETER if c not in df.columns]
    if missing:
        raise WindMapError(f"the table has no anemometer wind (missing {', '.join(missing)})")


def mount_matrix(quat_wxyz) -> np.ndarray:
    """M (3, 3), anemometer -> body, of a unit quaternion (w, x, y, z)."""
    q = np.asarray(quat_wxyz, dtype=float).reshape(-1)
    if q.shape != (4,) or not np.all(np.isfinite(q)) or abs(np.linalg.norm(q) - 1.0) > 1e-3:
        raise WindMapError(f"anemometer mount {quat_wxyz!r}: expected a unit quaternion "
                           "w,x,y,z (anemometer -> body axes)")
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def compensate(df, metadata: dict | None = None, *, pose: str = "auto",
               lever_arm_m=None, mount_quat_wxyz=None) -> CompensatedSamples:
    """The table's anemometer samples in the site NED frame (module docstring). Rows with
    `anemo_valid` 0 (no anemometer sample there) are left out, and with the marker pose
    rows with `marker_valid` 0 (docs/flight-table.md)."""
    from airwake.record.flight_builder import euler_to_dcm

    check_anemometer(df)
    if "t_s" not in df.columns:
        raise WindMapError("the table has no time column t_s")
    source = pose_source(df, pose)
    cols = POSE_SOURCES[source]
    meta = metadata or {}
    if lever_arm_m is None:
        lever_arm_m = meta.get("anemometer_lever_arm_m", (0.0, 0.0, 0.0))
    r = np.asarray(lever_arm_m, dtype=float).reshape(-1)
    if r.shape != (3,) or not np.all(np.isfinite(r)):
        raise WindMapError(f"anemometer lever arm {lever_arm_m!r}: expected three finite "
                           "numbers (m, body axes)")
    if mount_quat_wxyz is None:
        mount_quat_wxyz = meta.get("anemometer_mount_quat_wxyz", (1.0, 0.0, 0.0, 0.0))
    m = mount_matrix(mount_quat_wxyz)
    keep = np.ones(len(df), bool)
    if "anemo_valid" in df.columns:
        keep = np.asarray(df["anemo_valid"], float) > 0.5
    if not keep.any():
        raise WindMapError("the table has no valid anemometer sample (anemo_valid is 0)")
    if source == "marker" and "marker_valid" in df.columns:
        # dead reckoning (the marker out of the tracker's view) or an unconfirmed slot
        # re-acquisition: metres off within seconds, not a pose to map with
        keep &= np.asarray(df["marker_valid"], float) > 0.5
        if not keep.any():
            raise WindMapError("no row has both an anemometer sample and a valid marker "
                               "pose (marker_valid is 0 wherever anemo_valid is 1)")

    def block(names):
        return np.column_stack([np.asarray(df[c], float)[keep] for c in names])

    t = np.asarray(df["t_s"], float)[keep]
    w_meas = block(ANEMOMETER)
    p = block(cols["pos"])
    v = block(cols["vel"])
    att = block(cols["att"])
    omega = block(cols["rates"])
    bad = ~np.all(np.isfinite(np.column_stack([w_meas, p, v, att, omega])), axis=1)
    if bad.all():
        raise WindMapError("no row has a finite anemometer sample and pose")
    if bad.any():
        t, w_meas, p, v, att, omega = (a[~bad] for a in (t, w_meas, p, v, att, omega))
    rot = euler_to_dcm(att[:, 0], att[:, 1], att[:, 2])  # body -> NED
    if cols["vel_frame"] == "body":
        v = np.einsum("nij,nj->ni", rot, v)
    # p_s = p + R r ;  w(p_s) = R (M w_meas + omega x r) + v        (§3.4, inverted)
    pos = p + np.einsum("nij,j->ni", rot, r)
    wind = np.einsum("nij,nj->ni", rot, w_meas @ m.T + np.cross(omega, r)) + v
    dt = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    return CompensatedSamples(t, pos, wind, source, r, dt,
                              np.asarray(mount_quat_wxyz, dtype=float).reshape(4))
