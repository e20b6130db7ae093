"""The pilot: a scripted flight plan flown by a stabilising closed-loop controller.

Script (`[[pilot.segments]]` in a scenario), each segment one table with a `type`:

    hover   duration_s                       hold the current target
    goto    duration_s, position_m, yaw_deg? minimum-jerk move of the target
    path    waypoints_m, speed_m_s, accel_m_s2?, yaw_deg?   minimum-jerk legs through the
            waypoints, each sized so its peak speed and acceleration (default 1.5 m/s^2)
            stay within the limits
    sweep   a_m, b_m, passes, speed_m_s, accel_m_s2?   back and forth between a and b
    chirp   duration_s, channel, amplitude_deg, f0_hz, f1_hz   hold + frequency sweep on
            one input channel (col, lat, lon, ped), "oscillatory tilting at varying
            frequency" (reference §5.3)
    burst   duration_s, channels, amplitude_deg, hold_s        hold + random doublets
            (manoeuvre bursts) on the listed channels

Positions are in the script's `frame`: "ned" (inertial, D = 0 at the ground / hall floor
/ sea) or "ship" (the ship's heading frame riding with the ship-frame origin at the
hangar step: x bow, y starboard, z down from deck level; the pilot holds station in it
and ignores the deck's roll and pitch). The excitation of chirp and burst segments is
added to the controller's command (the stabiliser still holds the aircraft, so below its
bandwidth it partly cancels the excitation — as a real pilot's stabilising hand does).

Controller: the pilot acts on the RC frame grid (knots t_k, 50 Hz); at t_k it sees the
true state and decides the command for t_{k+1}; between knots the command is linear
(first-order hold), so the RC receiver, which samples at the knots, records exactly what
the servos are sent. The gain is a discrete LQR on the truth model linearised at the
initial trim, discretised exactly for that first-order hold with the one-frame decision
delay (augmented state [x, u_k] -> decision u_{k+1}), plus integral action on the
position and yaw errors (in the reference-heading frame) so wind and trim changes leave
no steady offset. Weights: `PilotGains`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg

from hil_sim.sensors.config import (
    check_choice,
    check_finite,
    check_nonnegative,
    check_positive,
    config_from_dict,
)

CHANNELS = ("col", "lat", "lon", "ped")  # order of the model's inputs
SEGMENT_TYPES = ("hover", "goto", "path", "sweep", "chirp", "burst")
POINTS = ("cg", "hub")
Vec3 = tuple[float, float, float]
# Command limits (rad): the RC set-up's end points (docs/sensors.md): col -3..+12 deg,
# cyclic +-8 deg, tail +-20 deg.
COMMAND_MIN = np.radians([-3.0, -8.0, -8.0, -20.0])
COMMAND_MAX = np.radians([12.0, 8.0, 8.0, 20.0])


# ---------------------------------------------------------------------------
# Settings
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Segment:
    """One script segment (see module docstring); unused keys keep their defaults."""

    type: str
    duration_s: float = 0.0
    position_m: Vec3 | None = None
    yaw_deg: float | None = None
    waypoints_m: tuple[Vec3, ...] = ()
    speed_m_s: float = 1.0
    accel_m_s2: float = 1.5
    a_m: Vec3 | None = None
    b_m: Vec3 | None = None
    passes: int = 2
    channel: str = "lat"
    channels: tuple[str, ...] = ("col", "lat", "lon", "ped")
    amplitude_deg: float = 1.0
    f0_hz: float = 0.2
    f1_hz: float = 3.0
    hold_s: float = 0.6

    def __post_init__(self) -> None:
        check_choice("type", self.type, SEGMENT_TYPES)
        check_nonnegative("duration_s", self.duration_s)
        check_positive("speed_m_s", self.speed_m_s)
        check_positive("accel_m_s2", self.accel_m_s2)
        check_choice("channel", self.channel, CHANNELS)
        for c in self.channels:
            check_choice("channels", c, CHANNELS)
        check_nonnegative("amplitude_deg", self.amplitude_deg)
        if self.amplitude_deg > 10.0:
            raise ValueError(f"amplitude_deg = {self.amplitude_deg!r}: must be <= 10")
        check_positive("f0_hz", self.f0_hz)
        check_positive("f1_hz", self.f1_hz)
        check_positive("hold_s", self.hold_s)
        if self.yaw_deg is not None:
            check_finite("yaw_deg", self.yaw_deg)
        need = {
            "hover": ("duration_s",), "chirp": ("duration_s",), "burst": ("duration_s",),
            "goto": ("duration_s", "position_m"), "path": ("waypoints_m",),
            "sweep": ("a_m", "b_m"),
        }[self.type]
        for key in need:
            value = getattr(self, key)
            if value is None or (key == "duration_s" and value <= 0) or (
                    key == "waypoints_m" and not value):
                raise ValueError(f"{key} = {value!r}: a '{self.type}' segment needs it "
                                 "(a positive duration / a position)")
        if not (isinstance(self.passes, int) and self.passes >= 1):
            raise ValueError(f"passes = {self.passes!r}: must be an integer >= 1")


@dataclass(frozen=True)
class PilotGains:
    """LQR weights as "acceptable deviations" (Bryson's rule: weight = 1 / value^2)."""

    position_m: float = 0.4
    velocity_m_s: float = 0.6
    attitude_deg: float = 6.0
    rate_deg_s: float = 40.0
    yaw_deg: float = 5.0
    integral_m_s: float = 2.0  # integrated position error (m s) that costs as much
    input_deg: float = 3.0
    input_step_deg: float = 0.5  # change of command per RC frame
    integral_limit_m_s: float = 5.0

    def __post_init__(self) -> None:
        for f in ("position_m", "velocity_m_s", "attitude_deg", "rate_deg_s", "yaw_deg",
                  "integral_m_s", "input_deg", "input_step_deg", "integral_limit_m_s"):
            check_positive(f, getattr(self, f))


@dataclass(frozen=True)
class CrossoverConfig:
    """The crossover pilot's human parameters (crossover_pilot.py); defaults mid-range of McRuer &
    Krendel 1974 for a practised RC pilot watching from ~10 m."""

    reaction_delay_s: float = 0.22
    neuromuscular_lag_s: float = 0.10
    attitude_crossover_rad_s: float = 3.5
    yaw_crossover_rad_s: float = 2.0
    heave_crossover_rad_s: float = 1.2
    position_crossover_rad_s: float = 0.8
    max_lead_s: float = 1.0
    max_bank_deg: float = 20.0
    trim_time_s: float = 2.0
    position_noise_m: float = 0.08
    velocity_noise_m_s: float = 0.10
    attitude_noise_deg: float = 0.7
    rate_noise_deg_s: float = 3.0
    heading_noise_deg: float = 1.5
    remnant_tau_s: float = 0.4

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            check_positive(name, value)


@dataclass(frozen=True)
class PilotConfig:
    """The `[pilot]` table: frame, start, heading, gains and the segments."""

    frame: str = "ned"
    start_m: Vec3 = (0.0, 0.0, -2.5)
    yaw_deg: float | None = None  # None: 0 in "ned", the ship's heading in "ship"
    # the point the script's positions are for: the CG, or the rotor hub (what a wind map
    # bins: a plan for a layer above the deck flies the hub through it)
    point: str = "cg"
    gains: PilotGains = field(default_factory=PilotGains)
    crossover: CrossoverConfig = field(default_factory=CrossoverConfig)
    segments: tuple[Segment, ...] = (Segment("hover", duration_s=1.0),)

    def __post_init__(self) -> None:
        check_choice("frame", self.frame, ("ned", "ship"))
        check_choice("point", self.point, POINTS)
        check_finite("start_m", self.start_m)
        if self.yaw_deg is not None:
            check_finite("yaw_deg", self.yaw_deg)
        if not self.segments:
            raise ValueError("segments = []: the script needs at least one segment")


def pilot_from_dict(table: Mapping[str, Any] | None, where: str = "pilot") -> PilotConfig:
    """`[pilot]` table (with `[[pilot.segments]]`) -> PilotConfig, errors naming the key."""
    if table is None:
        return PilotConfig()
    if not isinstance(table, Mapping):
        raise ValueError(f"{where}: expected a table, got {table!r}")
    table = dict(table)
    segs = table.pop("segments", None)
    cfg = config_from_dict(PilotConfig, table, where)
    if segs is None:
        return cfg
    if not isinstance(segs, list) or not segs:
        raise ValueError(f"{where}.segments: expected a non-empty list of tables")
    out = []
    for i, s in enumerate(segs):
        here = f"{where}.segments[{i}]"
        if not isinstance(s, Mapping) or "type" not in s:
            raise ValueError(f"{here}: expected a table with a 'type' "
                             f"(one of {', '.join(SEGMENT_TYPES)})")
        if s["type"] not in SEGMENT_TYPES:
            raise ValueError(f"{here}.type = {s['type']!r}: must be one of "
                             f"{', '.join(SEGMENT_TYPES)}")
        out.append(config_from_dict(Segment, s, here))
    return PilotConfig(frame=cfg.frame, start_m=cfg.start_m, yaw_deg=cfg.yaw_deg,
                       point=cfg.point, gains=cfg.gains, crossover=cfg.crossover,
                       segments=tuple(out))


def cg_script(cfg: PilotConfig, hub_offset_body_m) -> PilotConfig:
    """The script for the CG, which the pilot flies: a script for the hub (`point =
    "hub"`) moved down by the hub's height above the CG at level attitude (`hub_offset_body_m`
    in body axes, z down). Only the vertical part: a layer above the deck is about height,
    and the hub's few centimetres ahead of or beside the CG turn with the heading. A CG
    script is returned as it is."""
    if cfg.point == "cg":
        return cfg
    off = np.asarray(hub_offset_body_m, dtype=float)
    dz = -float(off[2])  # the hub is -off_z above the CG: the CG flies that much lower (+z)

    def lower(v):
        return None if v is None else (v[0], v[1], v[2] + dz)

    segs = tuple(dataclasses.replace(
        s, position_m=lower(s.position_m), a_m=lower(s.a_m), b_m=lower(s.b_m),
        waypoints_m=tuple(lower(w) for w in s.waypoints_m)) for s in cfg.segments)
    return dataclasses.replace(cfg, point="cg", start_m=lower(cfg.start_m), segments=segs)


# ---------------------------------------------------------------------------
# Reference (flight plan sampled on the knot grid)
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Reference:
    """The flight plan on the pilot's knots: `t_s` (K,), target position and velocity in
    the script frame `pos_m`, `vel_m_s` (K, 3), `yaw_rad` (K,) relative to the frame's
    heading, and the open-loop excitation `excitation_rad` (K, 4) [col, lat, lon, ped]."""

    t_s: np.ndarray
    pos_m: np.ndarray
    vel_m_s: np.ndarray
    yaw_rad: np.ndarray
    excitation_rad: np.ndarray


def _min_jerk(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 and ds/dtau on [0, 1]."""
    t = np.clip(tau, 0.0, 1.0)
    return t**3 * (10 - 15 * t + 6 * t * t), 30 * t * t * (1 - t) ** 2


def script_duration(cfg: PilotConfig) -> float:
    """Total duration of the script, s (path/sweep legs from their speeds)."""
    return sum(d for _, _, d in _legs(cfg))


def _leg_time(a: np.ndarray, b: np.ndarray, speed: float, accel: float) -> float:
    # a minimum-jerk leg of length L over T peaks at 1.875 L/T in speed and 5.774 L/T^2
    # in acceleration: size it so neither exceeds the segment's limits
    length = float(np.linalg.norm(b - a))
    return max(1.875 * length / speed, math.sqrt(5.774 * length / accel), 1.0)


def _legs(cfg: PilotConfig):
    """(segment, [(start, end) target moves], duration) per segment, in order."""
    here = np.asarray(cfg.start_m, dtype=float)
    out = []
    for seg in cfg.segments:
        moves = []
        if seg.type == "goto":
            end = np.asarray(seg.position_m, dtype=float)
            moves.append((here, end, seg.duration_s))
            here = end
            dur = seg.duration_s
        elif seg.type in ("path", "sweep"):
            if seg.type == "path":
                points = [np.asarray(p, dtype=float) for p in seg.waypoints_m]
            else:
                a, b = np.asarray(seg.a_m, dtype=float), np.asarray(seg.b_m, dtype=float)
                points = [a] + [b if i % 2 == 0 else a for i in range(seg.passes)]
            dur = 0.0
            for p in points:
                if np.linalg.norm(p - here) > 1e-9:
                    leg = _leg_time(here, p, seg.speed_m_s, seg.accel_m_s2)
                    moves.append((here, p, leg))
                    dur += leg
                    here = p
            dur = max(dur, seg.duration_s)
        else:
            dur = seg.duration_s
        out.append((seg, moves, dur))
    return out


def build_reference(cfg: PilotConfig, t_s: np.ndarray, rng: np.random.Generator) -> Reference:
    """Sample the script at the knot times `t_s` (K,). After the script ends the last
    target is held. `rng` draws the burst doublets (same seed, same flight)."""
    t = np.asarray(t_s, dtype=float)
    k = t.size
    pos = np.broadcast_to(np.asarray(cfg.start_m, dtype=float), (k, 3)).copy()
    vel = np.zeros((k, 3))
    yaw = np.zeros(k)
    exc = np.zeros((k, 4))
    t0 = 0.0
    yaw_now = 0.0
    end_pos = np.asarray(cfg.start_m, dtype=float)
    for seg, moves, dur in _legs(cfg):
        sel = t >= t0
        if seg.yaw_deg is not None:
            yaw_now = math.radians(seg.yaw_deg)
        yaw[sel] = yaw_now
        tm = t0
        for a, b, d in moves:
            tau = (t - tm) / d
            s, ds = _min_jerk(tau)
            m = t >= tm
            pos[m] = a + np.outer(s[m], b - a)
            vel[m] = np.outer(ds[m] / d, b - a)
            end_pos = b
            tm += d
        if not moves:
            pos[sel] = end_pos
            vel[sel] = 0.0
        inside = (t >= t0) & (t < t0 + dur)
        if seg.type == "chirp" and np.any(inside):
            # linear frequency sweep f0 -> f1 with a 1 s cosine taper at both ends
            tt = t[inside] - t0
            phase = 2 * np.pi * (seg.f0_hz * tt + 0.5 * (seg.f1_hz - seg.f0_hz) * tt**2 / dur)
            taper = np.minimum(1.0, np.minimum(tt, dur - tt) / 1.0)
            taper = 0.5 - 0.5 * np.cos(np.pi * np.clip(taper, 0.0, 1.0))
            exc[inside, CHANNELS.index(seg.channel)] += (
                math.radians(seg.amplitude_deg) * taper * np.sin(phase))
        elif seg.type == "burst" and np.any(inside):
            tt = t[inside] - t0
            for ch in seg.channels:
                j = CHANNELS.index(ch)
                edges = [0.0]
                while edges[-1] < dur:
                    edges.append(edges[-1] + seg.hold_s * rng.uniform(0.5, 1.5))
                levels = rng.choice([-1.0, 0.0, 1.0], size=len(edges)) * rng.uniform(
                    0.3, 1.0, size=len(edges))
                idx = np.searchsorted(edges, tt, side="right") - 1
                exc[inside, j] += math.radians(seg.amplitude_deg) * levels[idx]
        t0 += dur
    return Reference(t, pos, vel, yaw, exc)


# ---------------------------------------------------------------------------
# Controller
# ---------------------------------------------------------------------------


def foh_discretize(a: np.ndarray, b: np.ndarray, dt: float) -> tuple[np.ndarray, ...]:
    """x_{k+1} = Phi x_k + G0 u_k + G1 u_{k+1} for u linear between the knots."""
    n, m = b.shape
    big = np.zeros((n + 2 * m, n + 2 * m))
    big[:n, :n] = a * dt
    big[:n, n:n + m] = b * dt
    big[n:n + m, n + m:] = np.eye(m)
    e = scipy.linalg.expm(big)
    phi = e[:n, :n]
    gamma_a = e[:n, n:n + m]  # response to u_k held
    gamma_b = e[:n, n + m:]  # response to the ramp (u_{k+1} - u_k)
    return phi, gamma_a - gamma_b, gamma_b


def wrap_pi(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


class HeldCommands:
    """The pilot's decided commands on the RC frame grid and their first-order hold.

    Knots: 0, t_0 .. t_{K-1}, t_{K-1} + dt; the commands at 0 and t_0 are the trim, the
    command decided at knot k is for knot k + 1 (one frame of decision delay)."""

    def _start_hold(self, reference: Reference, u0: np.ndarray, dt: float) -> None:
        k = reference.t_s.size
        self.knots_t = np.concatenate([[0.0], reference.t_s, [reference.t_s[-1] + dt]])
        self.knots_u = np.empty((k + 2, 4))
        self.knots_u[:2] = u0
        self.filled = 1  # knots_u[: filled + 1] are decided
        self._knots_list = self.knots_t.tolist()
        self._cursor = 0
        self.saturated = 0

    def _decide(self, k: int, v: np.ndarray) -> np.ndarray:
        """Clip the command decided at knot k to the RC end points and hold it for k + 1."""
        clipped = np.clip(v, COMMAND_MIN, COMMAND_MAX)
        self.saturated += int(np.any(clipped != v))
        self.knots_u[k + 2] = clipped
        self.filled = k + 2
        return clipped

    def command(self, t_s: float) -> np.ndarray:
        """First-order hold between decided knots (trim before the first knot; the last
        decided value held beyond). Cheapest for increasing times (a moving cursor)."""
        kt = self._knots_list
        i = self._cursor
        while i + 1 < len(kt) and kt[i + 1] <= t_s:
            i += 1
        while i > 0 and kt[i] > t_s:
            i -= 1
        self._cursor = i
        if t_s < kt[0]:
            return self.knots_u[0].copy()
        if i >= self.filled:
            return self.knots_u[self.filled].copy()
        f = (t_s - kt[i]) / (kt[i + 1] - kt[i])
        return self.knots_u[i] + f * (self.knots_u[i + 1] - self.knots_u[i])


class Pilot(HeldCommands):
    """Closed-loop pilot for one flight (module docstring).

    `pilot.update(k, x, pos_ned, vel_ned, yaw_frame)` at knot k with the true state;
    `pilot.command(t)` is the first-order-hold command (4,) at any time.
    """

    def __init__(self, a: np.ndarray, b: np.ndarray, trim, reference: Reference,
                 gains: PilotGains, *, body_slice: slice) -> None:
        """`a` (S, S), `b` (S, 4): the truth linearised at `trim` (trim.x (S,), trim.u (4,)),
        its body states [position, body velocity, Euler angles, rates] at `body_slice`."""
        self.trim = trim
        self.ref = reference
        self.gains = gains
        self.body = body_slice
        self.dt = float(np.median(np.diff(reference.t_s))) if reference.t_s.size > 1 else 0.02
        n = a.shape[0]
        b0 = self.body.start
        # integral states: d xi/dt = [pos_n, pos_e, pos_d, yaw] errors
        ni = 4
        aa = np.zeros((n + ni, n + ni))
        aa[:n, :n] = a
        for i, s in enumerate((0, 1, 2, 8)):
            aa[n + i, b0 + s] = 1.0
        bb = np.vstack([b, np.zeros((ni, 4))])
        phi, g0, g1 = foh_discretize(aa, bb, self.dt)
        nz = n + ni
        # augmented z = [x, xi, u_k]; decision v = u_{k+1}
        az = np.zeros((nz + 4, nz + 4))
        az[:nz, :nz] = phi
        az[:nz, nz:] = g0
        bz = np.vstack([g1, np.eye(4)])
        q = np.zeros(nz + 4)
        g = gains
        body_w = {0: g.position_m, 1: g.position_m, 2: g.position_m,
                  3: g.velocity_m_s, 4: g.velocity_m_s, 5: g.velocity_m_s,
                  6: math.radians(g.attitude_deg), 7: math.radians(g.attitude_deg),
                  8: math.radians(g.yaw_deg), 9: math.radians(g.rate_deg_s),
                  10: math.radians(g.rate_deg_s), 11: math.radians(g.rate_deg_s)}
        for s, v in body_w.items():
            q[b0 + s] = 1.0 / v**2
        q[n:n + 3] = 1.0 / g.integral_m_s**2
        q[n + 3] = 1.0 / (g.integral_m_s * math.radians(g.yaw_deg) / g.position_m) ** 2
        r_abs = 1.0 / math.radians(g.input_deg) ** 2
        r_step = 1.0 / math.radians(g.input_step_deg) ** 2
        # cost on |v - u_k|^2 (command steps) expands into Q_uu, R and a cross term S
        qm = np.diag(q)
        qm[nz:, nz:] += r_step * np.eye(4)
        rm = (r_abs + r_step) * np.eye(4)
        sm = np.zeros((nz + 4, 4))
        sm[nz:, :] = -r_step * np.eye(4)
        p = scipy.linalg.solve_discrete_are(az, bz, qm, rm, s=sm)
        self.gain = np.linalg.solve(rm + bz.T @ p @ bz, bz.T @ p @ az + sm.T)
        closed = az - bz @ self.gain
        self.closed_loop_radius = float(np.max(np.abs(np.linalg.eigvals(closed))))
        self.n_states = n
        self._start_hold(reference, trim.u, self.dt)
        self.integral = np.zeros(4)

    def update(self, k: int, x: np.ndarray, pos_frame_m: np.ndarray, vel_frame_body_m_s:
               np.ndarray, yaw_frame_rad: float) -> np.ndarray:
        """At knot k (time reference.t_s[k]) decide the command for knot k+1.

        `pos_frame_m` (3,): CG position in the script frame; `vel_frame_body_m_s` (3,): the
        reference velocity expressed in body axes; `yaw_frame_rad`: heading relative to
        the frame's. Returns the decided command (4,)."""
        ref = self.ref
        b = self.body.start
        psi_r = ref.yaw_rad[k]
        c, s = math.cos(psi_r), math.sin(psi_r)
        rot = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])  # frame -> heading
        e = x - self.trim.x
        e[b:b + 3] = rot @ (pos_frame_m - ref.pos_m[k])
        e[b + 3:b + 6] = x[b + 3:b + 6] - vel_frame_body_m_s
        e[b + 8] = wrap_pi(yaw_frame_rad - psi_r)
        err = np.concatenate([e[b:b + 3], [e[b + 8]]])
        self.integral = np.clip(self.integral + self.dt * err, -self.gains.integral_limit_m_s,
                                self.gains.integral_limit_m_s)
        z = np.concatenate([e, self.integral, self.knots_u[k + 1] - self.trim.u])
        v = self.trim.u - self.gain @ z + ref.excitation_rad[min(k + 1, ref.t_s.size - 1)]
        return self._decide(k, v)
