"""Piksi-class RTK receiver: baseline rover-minus-base, fix status, and its SBP frames.

Measured at `rate_hz` (default 10 Hz) per epoch:
- fix mode from `fix_schedule` (times at which the mode changes) plus optional random
  RTK dropouts (fixed -> float for `dropout_duration_s`, Poisson at
  `dropout_rate_per_s`); SBP codes 1 SPP, 2 DGNSS, 3 float RTK, 4 fixed RTK;
- baseline NED (rover antenna - base antenna, m): truth + a Gauss-Markov error whose
  size depends on the mode (cm when fixed); absent (NaN, no MSG_BASELINE_NED) in SPP;
- rover position (lat, lon, height): truth + the same error in RTK modes, the SPP error
  (metres) otherwise;
- velocity NED: truth + white noise; satellites in use: a slowly varying integer.

Stream: per epoch, MSG_GPS_TIME, MSG_POS_LLH, MSG_BASELINE_NED (RTK modes only) and
MSG_VEL_NED, framed by the `sbp` package (`msg.to_binary()`), first byte `latency_s`
after the epoch.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from sbp.navigation import MsgBaselineNED, MsgGPSTime, MsgPosLLH, MsgVelNED

from hil_sim.sensors import noise
from hil_sim.sensors.config import (
    check_choice,
    check_finite,
    check_nonnegative,
    check_positive,
)
from hil_sim.sensors.geodesy import DEFAULT_ORIGIN_LLA, ned_to_lla
from hil_sim.sensors.streams import ByteStream, sample_times
from hil_sim.world.kinematics import Trajectory

FIX_MODE_CODES = {"spp": 1, "dgnss": 2, "float": 3, "fixed": 4}
SECONDS_PER_WEEK = 604800
Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class RtkConfig:
    """Piksi model. Accuracy defaults: Piksi Multi datasheet (docs/sensors.md)."""

    rate_hz: float = 10.0
    sender_id: int = 0x2A1B
    fix_schedule: tuple[tuple[float, str], ...] = ((0.0, "fixed"),)
    dropout_rate_per_s: float = 0.0
    dropout_duration_s: float = 5.0
    fixed_sigma_m: Vec3 = (0.010, 0.010, 0.015)
    fixed_tau_s: float = 2.0
    float_sigma_m: Vec3 = (0.15, 0.15, 0.30)
    float_tau_s: float = 30.0
    dgnss_sigma_m: Vec3 = (0.5, 0.5, 1.0)
    dgnss_tau_s: float = 30.0
    spp_sigma_m: Vec3 = (1.5, 1.5, 3.0)
    spp_tau_s: float = 60.0
    velocity_sigma_m_s: Vec3 = (0.02, 0.02, 0.04)
    n_sats_mean: float = 14.0
    origin_lla: Vec3 = DEFAULT_ORIGIN_LLA
    gps_week: int = 2000
    gps_tow_at_t0_s: float = 345600.0
    phase_s: float = 0.0
    latency_s: float = 0.03
    baud: int = 115200

    def __post_init__(self) -> None:
        check_positive("rate_hz", self.rate_hz)
        if not 0 <= self.sender_id <= 0xFFFF:
            raise ValueError(f"sender_id = {self.sender_id!r}: must fit in a u16")
        if not self.fix_schedule:
            raise ValueError("fix_schedule = (): needs at least one (t_s, mode) entry")
        last = -np.inf
        for t, mode in self.fix_schedule:
            check_choice("fix_schedule mode", mode, tuple(FIX_MODE_CODES))
            if not t >= last:
                raise ValueError(f"fix_schedule = {self.fix_schedule!r}: times must increase")
            last = t
        check_nonnegative("dropout_rate_per_s", self.dropout_rate_per_s)
        check_positive("dropout_duration_s", self.dropout_duration_s)
        for name in ("fixed", "float", "dgnss", "spp"):
            for v in getattr(self, f"{name}_sigma_m"):
                check_nonnegative(f"{name}_sigma_m", v)
            check_positive(f"{name}_tau_s", getattr(self, f"{name}_tau_s"))
        for v in self.velocity_sigma_m_s:
            check_nonnegative("velocity_sigma_m_s", v)
        check_positive("n_sats_mean", self.n_sats_mean)
        check_finite("origin_lla", self.origin_lla)
        check_nonnegative("gps_tow_at_t0_s", self.gps_tow_at_t0_s)
        check_nonnegative("latency_s", self.latency_s)
        check_positive("baud", self.baud)


@dataclass(frozen=True, eq=False)
class RtkSamples:
    """K epochs. `t_s` (K,) simulation time; `gps_week` (K,), `tow_ms` (K,),
    `ns_residual` (K,) GPS time; `fix_mode` (K,) SBP codes; `baseline_ned_m` (K, 3)
    (NaN in SPP); `lla` (K, 3) lat deg / lon deg / height m; `vel_ned_m_s` (K, 3);
    `n_sats` (K,); `h_accuracy_m`, `v_accuracy_m` (K,) reported 1-sigma accuracies."""

    t_s: np.ndarray
    gps_week: np.ndarray
    tow_ms: np.ndarray
    ns_residual: np.ndarray
    fix_mode: np.ndarray
    baseline_ned_m: np.ndarray
    lla: np.ndarray
    vel_ned_m_s: np.ndarray
    n_sats: np.ndarray
    h_accuracy_m: np.ndarray
    v_accuracy_m: np.ndarray

    def __len__(self) -> int:
        return self.t_s.size


class RtkReceiver:
    """One Piksi. `measure(rover, base)` for the rover's RTK solution;
    `measure_standalone(traj)` for a receiver without corrections (the base's own SPP)."""

    def __init__(self, config: RtkConfig | None = None, *, rng: np.random.Generator) -> None:
        self.config = config or RtkConfig()
        self.rng = rng

    def fix_modes(self, t_s: np.ndarray) -> np.ndarray:
        """SBP fix-mode code at each time: the schedule, degraded by random dropouts."""
        c = self.config
        times = np.array([t for t, _ in c.fix_schedule])
        codes = np.array([FIX_MODE_CODES[m] for _, m in c.fix_schedule])
        idx = np.searchsorted(times, t_s, side="right") - 1
        mode = np.where(idx >= 0, codes[np.clip(idx, 0, None)], FIX_MODE_CODES["spp"])
        if c.dropout_rate_per_s > 0 and t_s.size:
            span = float(t_s[-1] - t_s[0])
            n_events = self.rng.poisson(c.dropout_rate_per_s * span)
            starts = t_s[0] + self.rng.uniform(0.0, span, n_events)
            lost = np.zeros(t_s.size, dtype=bool)
            for s in starts:
                lost |= (t_s >= s) & (t_s < s + c.dropout_duration_s)
            mode = np.where(lost & (mode == FIX_MODE_CODES["fixed"]), FIX_MODE_CODES["float"],
                            mode)
        return mode.astype(np.int64)

    def measure(self, rover: Trajectory, base: Trajectory | None) -> RtkSamples:
        """Epochs within the rover trajectory's span (rover and base share times)."""
        c = self.config
        t = sample_times(rover.t_s[0], rover.t_s[-1], c.rate_hz, c.phase_s)
        truth = rover.at(t)
        mode = self.fix_modes(t)
        if base is None:
            mode = np.minimum(mode, FIX_MODE_CODES["spp"])
            baseline_truth = np.full((t.size, 3), np.nan)
        else:
            baseline_truth = truth.pos_ned_m - base.at(t).pos_ned_m

        sigma = np.zeros((t.size, 3))
        err = np.zeros((t.size, 3))
        for name, code in FIX_MODE_CODES.items():
            sel = mode == code
            s = np.asarray(getattr(c, f"{name}_sigma_m"))
            # Each mode's error is its own process over the whole flight, used where
            # that mode is active (a mode change is a jump, as on the real receiver).
            process = noise.gauss_markov(t, s, getattr(c, f"{name}_tau_s"), self.rng)
            err[sel] = process[sel]
            sigma[sel] = s
        rtk = mode >= FIX_MODE_CODES["dgnss"]
        baseline = np.where(rtk[:, None], baseline_truth + err, np.nan)
        lla = ned_to_lla(truth.pos_ned_m + err, c.origin_lla)
        vel = truth.vel_ned_m_s + noise.white(
            t, np.asarray(c.velocity_sigma_m_s) * np.sqrt(1.0 / c.rate_hz), self.rng)
        sats = np.clip(np.round(c.n_sats_mean + noise.gauss_markov(t, 1.5, 60.0, self.rng,
                                                                       width=1)[:, 0]), 4, 30)
        week, tow_ms, ns_res = self._gps_time(t)
        return RtkSamples(
            t_s=t,
            gps_week=week,
            tow_ms=tow_ms,
            ns_residual=ns_res,
            fix_mode=mode,
            baseline_ned_m=baseline,
            lla=lla,
            vel_ned_m_s=vel,
            n_sats=sats.astype(np.int64),
            h_accuracy_m=np.hypot(sigma[:, 0], sigma[:, 1]),
            v_accuracy_m=sigma[:, 2],
        )

    def measure_standalone(self, trajectory: Trajectory) -> RtkSamples:
        """A receiver with no base: SPP at best (the base Piksi's own position)."""
        return self.measure(trajectory, None)

    def _gps_time(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        c = self.config
        total_s = c.gps_tow_at_t0_s + t
        weeks = np.floor(total_s / SECONDS_PER_WEEK)
        tow_s = total_s - weeks * SECONDS_PER_WEEK
        tow_ms = np.floor(tow_s * 1000.0 + 1e-6)
        ns_residual = np.round((tow_s * 1000.0 - tow_ms) * 1e6)
        return ((c.gps_week + weeks).astype(np.int64), tow_ms.astype(np.int64),
                ns_residual.astype(np.int64))

    def stream(self, samples: RtkSamples) -> ByteStream:
        """SBP frames per epoch (one chunk per epoch)."""
        c = self.config
        sender = c.sender_id
        chunks: list[bytes] = []
        vel_h_acc = _mm_u16(float(np.hypot(*c.velocity_sigma_m_s[:2])))
        vel_v_acc = _mm_u16(c.velocity_sigma_m_s[2])
        for i in range(len(samples)):
            tow = int(samples.tow_ms[i])
            mode = int(samples.fix_mode[i])
            sats = int(samples.n_sats[i])
            h_acc = _mm_u16(samples.h_accuracy_m[i])
            v_acc = _mm_u16(samples.v_accuracy_m[i])
            parts = [
                MsgGPSTime(sender=sender, wn=int(samples.gps_week[i]) % 65536, tow=tow,
                           ns_residual=int(samples.ns_residual[i]), flags=1).to_binary(),
                MsgPosLLH(sender=sender, tow=tow, lat=float(samples.lla[i, 0]),
                          lon=float(samples.lla[i, 1]), height=float(samples.lla[i, 2]),
                          h_accuracy=h_acc, v_accuracy=v_acc, n_sats=sats,
                          flags=mode).to_binary(),
            ]
            if mode >= FIX_MODE_CODES["dgnss"]:
                n, e, d = (int(round(v * 1000.0)) for v in samples.baseline_ned_m[i])
                parts.append(MsgBaselineNED(sender=sender, tow=tow, n=n, e=e, d=d,
                                            h_accuracy=h_acc, v_accuracy=v_acc, n_sats=sats,
                                            flags=mode).to_binary())
            vn, ve, vd = (int(round(v * 1000.0)) for v in samples.vel_ned_m_s[i])
            parts.append(MsgVelNED(sender=sender, tow=tow, n=vn, e=ve, d=vd,
                                   h_accuracy=vel_h_acc, v_accuracy=vel_v_acc, n_sats=sats,
                                   flags=1).to_binary())
            chunks.append(b"".join(parts))
        return ByteStream.from_chunks(samples.t_s + c.latency_s, chunks, c.baud)


def _mm_u16(value_m: float) -> int:
    return int(min(max(round(value_m * 1000.0), 0), 0xFFFF))
