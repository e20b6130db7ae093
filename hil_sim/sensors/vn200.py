"""VN200-class GNSS/INS: measured values and the real VectorNav binary output packets.

Measured (what the VN200 reports at `rate_hz`, default 150 Hz, Binary Output 1):
- TimeStartup: the device's nanoseconds since power-on (its own clock);
- YawPitchRoll (deg): truth + a Gauss-Markov INS attitude error per angle;
- AngularRate (rad/s, body): truth + the shared IMU error model (`imu`);
- Position (lat deg, lon deg, height m, WGS-84): truth NED + Gauss-Markov GNSS error;
- Velocity (NED m/s): truth + Gauss-Markov error;
- Accel (m/s^2, body): specific force + IMU errors — as the VN200 reports it, gravity
  included: at rest and level z is about -9.8;
- InsStatus (u16): mode 2 (tracking) + GNSS fix bit, constant.

Packet contract (shared with the rover/base firmware parser): sync 0xFA, group byte,
one u16 LE field mask per group present, fields in bit order little-endian, then the
CRC-16 (VectorNav's CRC-16-CCITT: init 0, poly 0x1021, no reflection = CRC-16/XMODEM)
over every byte after the sync, appended big-endian, so the CRC over the whole packet
after the sync (CRC included) is 0. Our configuration is group 1 (Common) only with
mask 0x11E9 = TimeStartup(0) | YawPitchRoll(3) | AngularRate(5) | Position(6) |
Velocity(7) | Accel(8) | InsStatus(12): 82-byte payload, 88-byte packet. Field bits and
sizes follow VectorNav's programming library (`Packet::BinaryGroupLengths`).

`Vn200Parser` is a reference decoder for any group byte / field mask (the full size
tables), resynchronising on 0xFA and counting CRC errors — the model the C parser
follows and the tests use.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from hil_sim.sensors import noise
from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive
from hil_sim.sensors.geodesy import DEFAULT_ORIGIN_LLA, ned_to_lla
from hil_sim.sensors.imu import ImuErrors, ImuNoiseConfig, imu_errors
from hil_sim.sensors.streams import ByteStream, sample_times
from hil_sim.world.kinematics import Trajectory

VN_SYNC = 0xFA
GROUP_COMMON = 0x01

# Field sizes (bytes) per binary group (bit index 0..15 of each group's field mask), from
# VectorNav's programming library (the revision with the GNSS2 group 7; 0 = unassigned or
# variable length: a packet using it cannot be sized and is counted as unsupported).
VN_GROUP_FIELD_SIZES: tuple[tuple[int, ...], ...] = (
    (8, 8, 8, 12, 16, 12, 24, 12, 12, 24, 20, 28, 2, 4, 8, 0),   # 1 Common
    (8, 8, 8, 2, 8, 8, 8, 4, 4, 1, 0, 0, 0, 0, 0, 0),            # 2 Time
    (2, 12, 12, 12, 4, 4, 16, 12, 12, 12, 12, 2, 40, 0, 0, 0),   # 3 IMU
    (8, 8, 2, 1, 1, 24, 24, 12, 12, 12, 4, 4, 2, 28, 0, 0),      # 4 GNSS1
    (2, 12, 16, 36, 12, 12, 12, 12, 12, 12, 28, 24, 12, 0, 0, 0),  # 5 Attitude
    (2, 24, 24, 12, 12, 12, 12, 12, 12, 4, 4, 68, 64, 0, 0, 0),  # 6 INS
    (8, 8, 2, 1, 1, 24, 24, 12, 12, 12, 4, 4, 2, 28, 0, 0),      # 7 GNSS2
)

# Common-group fields we emit (bit -> name).
COMMON_TIME_STARTUP = 0
COMMON_YAW_PITCH_ROLL = 3
COMMON_ANGULAR_RATE = 5
COMMON_POSITION = 6
COMMON_VELOCITY = 7
COMMON_ACCEL = 8
COMMON_INS_STATUS = 12
ROVER_COMMON_MASK = 0x11E9

# InsStatus bits (VN-200 user manual): mode in bits 0-1 (2 = tracking within spec),
# GNSS fix bit 2, error bits 3-6 (time, IMU, mag/pressure, GNSS).
INS_MODE_TRACKING = 2
INS_GNSS_FIX = 1 << 2

_PACKET_DTYPE = np.dtype(
    [
        ("sync", "u1"),
        ("group", "u1"),
        ("mask", "<u2"),
        ("time_startup_ns", "<u8"),
        ("ypr_deg", "<f4", (3,)),
        ("rates_rad_s", "<f4", (3,)),
        ("lla", "<f8", (3,)),
        ("vel_ned_m_s", "<f4", (3,)),
        ("accel_m_s2", "<f4", (3,)),
        ("ins_status", "<u2"),
        ("crc", ">u2"),
    ]
)
PACKET_SIZE = _PACKET_DTYPE.itemsize  # 88

Vec3 = tuple[float, float, float]


# ---------------------------------------------------------------------------
# CRC
# ---------------------------------------------------------------------------


def _crc_table() -> np.ndarray:
    table = np.zeros(256, dtype=np.uint16)
    for i in range(256):
        c = i << 8
        for _ in range(8):
            c = ((c << 1) ^ 0x1021) if c & 0x8000 else (c << 1)
        table[i] = c & 0xFFFF
    return table


_CRC_TABLE = _crc_table()


def vn_crc16(data: bytes | bytearray | memoryview) -> int:
    """VectorNav CRC-16 (CRC-16/XMODEM: init 0, poly 0x1021, MSB first)."""
    crc = 0
    table = _CRC_TABLE
    for b in bytes(data):
        crc = ((crc << 8) & 0xFFFF) ^ int(table[((crc >> 8) ^ b) & 0xFF])
    return crc


def vn_crc16_bulk(rows: np.ndarray) -> np.ndarray:
    """CRC of every row of a (K, L) uint8 array at once (vectorised over rows)."""
    crc = np.zeros(rows.shape[0], dtype=np.uint16)
    for j in range(rows.shape[1]):
        idx = ((crc >> 8) ^ rows[:, j]).astype(np.uint8)
        crc = (crc << 8) ^ _CRC_TABLE[idx]
    return crc


# ---------------------------------------------------------------------------
# Model
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Vn200Config:
    """VN200 output model. Defaults from the VN-200 datasheet (docs/sensors.md)."""

    rate_hz: float = 150.0
    imu: ImuNoiseConfig = field(default_factory=ImuNoiseConfig)
    attitude_error_deg: Vec3 = (0.1, 0.1, 0.3)  # 1 sigma roll, pitch, yaw
    attitude_error_tau_s: float = 30.0
    position_error_m: Vec3 = (1.77, 1.77, 5.0)  # 1 sigma N, E, D (2.5 m RMS horizontal)
    position_error_tau_s: float = 120.0
    velocity_error_m_s: Vec3 = (0.05, 0.05, 0.05)
    velocity_error_tau_s: float = 5.0
    origin_lla: Vec3 = DEFAULT_ORIGIN_LLA
    startup_offset_s: float = 12.0  # TimeStartup at simulation time 0
    clock_ppm: float = 0.0  # device crystal error
    phase_s: float = 0.0  # first sample instant of the device clock
    latency_s: float = 0.0005  # sample instant -> first byte on the wire
    baud: int = 921600
    ins_status: int = INS_MODE_TRACKING | INS_GNSS_FIX
    # 0: the IMU outputs are the truth at the output instants (an ideal anti-alias);
    # > 0: the IMU samples at this rate (VN-200 data sheet: 800 Hz) and each output is
    # the mean of the samples since the previous output, so vibration above half the
    # output rate folds down as it does in the real device
    imu_sample_rate_hz: float = 0.0
    solution_delay_s: float = 0.0  # attitude / velocity / position of t - delay (INS filter)

    def __post_init__(self) -> None:
        check_positive("rate_hz", self.rate_hz)
        check_nonnegative("imu_sample_rate_hz", self.imu_sample_rate_hz)
        if 0 < self.imu_sample_rate_hz < self.rate_hz:
            raise ValueError(f"imu_sample_rate_hz = {self.imu_sample_rate_hz!r}: must be 0 "
                             f"or >= rate_hz ({self.rate_hz})")
        check_nonnegative("solution_delay_s", self.solution_delay_s)
        for name in ("attitude_error_deg", "position_error_m", "velocity_error_m_s"):
            for v in getattr(self, name):
                check_nonnegative(name, v)
        for name in ("attitude_error_tau_s", "position_error_tau_s", "velocity_error_tau_s"):
            check_positive(name, getattr(self, name))
        check_finite("origin_lla", self.origin_lla)
        check_nonnegative("startup_offset_s", self.startup_offset_s)
        check_nonnegative("latency_s", self.latency_s)
        check_positive("baud", self.baud)
        if not 0 <= self.ins_status <= 0xFFFF:
            raise ValueError(f"ins_status = {self.ins_status!r}: must fit in a u16")
        # 88 bytes * 10 bits at rate_hz must fit the line.
        if PACKET_SIZE * 10 * self.rate_hz > self.baud:
            raise ValueError(
                f"baud = {self.baud}: {PACKET_SIZE}-byte packets at {self.rate_hz} Hz need "
                f">= {int(PACKET_SIZE * 10 * self.rate_hz)} baud"
            )


@dataclass(frozen=True, eq=False)
class Vn200Samples:
    """K VN200 outputs. `t_s` (K,) simulation time of each sample; values as reported:
    `time_startup_ns` (K,) uint64, `ypr_deg` (K, 3) yaw/pitch/roll, `rates_body_rad_s`
    (K, 3), `lla` (K, 3) lat deg / lon deg / height m, `vel_ned_m_s` (K, 3),
    `accel_body_m_s2` (K, 3) (specific force), `ins_status` (K,) uint16;
    `imu_errors` the drawn IMU errors (truth)."""

    t_s: np.ndarray
    time_startup_ns: np.ndarray
    ypr_deg: np.ndarray
    rates_body_rad_s: np.ndarray
    lla: np.ndarray
    vel_ned_m_s: np.ndarray
    accel_body_m_s2: np.ndarray
    ins_status: np.ndarray
    imu_errors: ImuErrors

    def __len__(self) -> int:
        return self.t_s.size


class Vn200:
    """One VN200 (rover or base). `measure` draws a flight's outputs; `stream` encodes them."""

    def __init__(self, config: Vn200Config | None = None, *, rng: np.random.Generator) -> None:
        self.config = config or Vn200Config()
        self.rng = rng

    def sample_times(self, trajectory: Trajectory) -> np.ndarray:
        c = self.config
        return sample_times(trajectory.t_s[0], trajectory.t_s[-1], c.rate_hz, c.phase_s,
                            c.clock_ppm)

    def measure(self, trajectory: Trajectory) -> Vn200Samples:
        """Outputs at the device's sample instants within the trajectory's span."""
        c = self.config
        t = self.sample_times(trajectory)
        truth = trajectory.at(t)
        rates, accel = truth.rates_body_rad_s, truth.specific_force_body_m_s2
        if c.imu_sample_rate_hz > 0:
            rates, accel = _averaged_imu(trajectory, t, c.imu_sample_rate_hz, c.rate_hz)
        if c.solution_delay_s > 0:
            truth = dataclasses.replace(truth, **{
                k: getattr(trajectory.at(t - c.solution_delay_s), k) for k in (
                    "pos_ned_m", "vel_ned_m_s", "quat_wxyz", "euler_rad")})
        errs = imu_errors(t, truth.rotor_azimuth_rad, c.imu, self.rng)

        att_err_deg = noise.gauss_markov(t, c.attitude_error_deg, c.attitude_error_tau_s,
                                         self.rng)
        euler_deg = np.degrees(truth.euler_rad) + att_err_deg
        yaw = (euler_deg[:, 2] + 180.0) % 360.0 - 180.0
        ypr = np.stack([yaw, euler_deg[:, 1], euler_deg[:, 0]], axis=-1)

        pos_err = noise.gauss_markov(t, c.position_error_m, c.position_error_tau_s, self.rng)
        vel_err = noise.gauss_markov(t, c.velocity_error_m_s, c.velocity_error_tau_s, self.rng)
        lla = ned_to_lla(truth.pos_ned_m + pos_err, c.origin_lla)

        device_s = (t / (1.0 + c.clock_ppm * 1e-6)) + c.startup_offset_s
        return Vn200Samples(
            t_s=t,
            time_startup_ns=np.round(device_s * 1e9).astype(np.uint64),
            ypr_deg=ypr,
            rates_body_rad_s=rates + errs.gyro_rad_s,
            lla=lla,
            vel_ned_m_s=truth.vel_ned_m_s + vel_err,
            accel_body_m_s2=accel + errs.accel_m_s2,
            ins_status=np.full(t.size, c.ins_status, dtype=np.uint16),
            imu_errors=errs,
        )

    def stream(self, samples: Vn200Samples) -> ByteStream:
        """The binary packets on the wire, first byte `latency_s` after each sample."""
        packets = encode_vn200_packets(samples)
        return ByteStream.from_fixed_size(samples.t_s + self.config.latency_s, packets,
                                          self.config.baud)


def _averaged_imu(trajectory: Trajectory, t_out: np.ndarray, imu_rate_hz: float,
                  out_rate_hz: float) -> tuple[np.ndarray, np.ndarray]:
    """(rates, specific force) (K, 3) at the output instants t_out: the mean of the IMU's
    samples (at imu_rate_hz, on its own grid) in (previous output, this output]."""
    t0 = trajectory.t_s[0]
    ti = t0 + np.arange(int(np.floor((trajectory.t_s[-1] - t0) * imu_rate_hz)) + 1) / imu_rate_hz
    sampled = trajectory.at(ti)
    out = []
    idx = np.searchsorted(ti, t_out, side="right")  # samples up to and including t_out
    for x in (sampled.rates_body_rad_s, sampled.specific_force_body_m_s2):
        c = np.vstack([np.zeros((1, 3)), np.cumsum(x, axis=0)])
        hi = idx
        lo = np.concatenate([[max(idx[0] - int(round(imu_rate_hz / out_rate_hz)), 0)], idx[:-1]])
        lo = np.minimum(lo, hi - 1)
        lo = np.maximum(lo, 0)
        count = np.maximum(hi - lo, 1)
        out.append((c[hi] - c[lo]) / count[:, None])
    return out[0], out[1]


def encode_vn200_packets(samples: Vn200Samples) -> np.ndarray:
    """(K, 88) uint8: one Binary Output 1 packet (group 1, mask 0x11E9) per sample."""
    k = len(samples)
    rec = np.zeros(k, dtype=_PACKET_DTYPE)
    rec["sync"] = VN_SYNC
    rec["group"] = GROUP_COMMON
    rec["mask"] = ROVER_COMMON_MASK
    rec["time_startup_ns"] = samples.time_startup_ns
    rec["ypr_deg"] = samples.ypr_deg
    rec["rates_rad_s"] = samples.rates_body_rad_s
    rec["lla"] = samples.lla
    rec["vel_ned_m_s"] = samples.vel_ned_m_s
    rec["accel_m_s2"] = samples.accel_body_m_s2
    rec["ins_status"] = samples.ins_status
    rows = rec.view(np.uint8).reshape(k, PACKET_SIZE)
    rec["crc"] = vn_crc16_bulk(rows[:, 1 : PACKET_SIZE - 2])
    return rec.view(np.uint8).reshape(k, PACKET_SIZE).copy()


# ---------------------------------------------------------------------------
# Reference decoder
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Vn200Packet:
    """One decoded binary packet: `group` byte, `masks` {group number 1..6: field mask},
    `fields` {(group number, bit): raw little-endian bytes}."""

    group: int
    masks: dict[int, int]
    fields: dict[tuple[int, int], bytes]

    def common(self) -> dict[str, object]:
        """The common-group fields we use, decoded (absent ones left out)."""
        out: dict[str, object] = {}
        f = self.fields
        if (1, COMMON_TIME_STARTUP) in f:
            out["time_startup_ns"] = int(np.frombuffer(f[(1, COMMON_TIME_STARTUP)], "<u8")[0])
        for bit, name, dt in (
            (COMMON_YAW_PITCH_ROLL, "ypr_deg", "<f4"),
            (COMMON_ANGULAR_RATE, "rates_body_rad_s", "<f4"),
            (COMMON_POSITION, "lla", "<f8"),
            (COMMON_VELOCITY, "vel_ned_m_s", "<f4"),
            (COMMON_ACCEL, "accel_body_m_s2", "<f4"),
        ):
            if (1, bit) in f:
                out[name] = np.frombuffer(f[(1, bit)], dt).astype(float)
        if (1, COMMON_INS_STATUS) in f:
            out["ins_status"] = int(np.frombuffer(f[(1, COMMON_INS_STATUS)], "<u2")[0])
        return out


def packet_length(group: int, masks: list[int]) -> int | None:
    """Total packet length for a group byte and its masks; None if a field is unknown."""
    payload = 0
    groups = [g for g in range(8) if group >> g & 1]
    for g, mask in zip(groups, masks, strict=True):
        if g >= len(VN_GROUP_FIELD_SIZES) or mask >> 15 & 1:
            return None  # unknown group, or extension flag (sizes not tabulated)
        for bit in range(16):
            if mask >> bit & 1:
                size = VN_GROUP_FIELD_SIZES[g][bit]
                if size == 0:
                    return None
                payload += size
    return 2 + 2 * len(groups) + payload + 2


class Vn200Parser:
    """Streaming decoder: feed bytes, get packets; resyncs on 0xFA after any corruption.

    Counters: `packets`, `crc_errors` (a full-length candidate failed its CRC),
    `unsupported` (group/mask naming fields we cannot size), `bytes_skipped`.
    """

    def __init__(self) -> None:
        self._buf = bytearray()
        self.packets = 0
        self.crc_errors = 0
        self.unsupported = 0
        self.bytes_skipped = 0

    def feed(self, data: bytes) -> list[Vn200Packet]:
        self._buf += data
        out: list[Vn200Packet] = []
        buf = self._buf
        pos = 0
        while True:
            start = buf.find(bytes([VN_SYNC]), pos)
            if start < 0:
                self.bytes_skipped += len(buf) - pos
                pos = len(buf)
                break
            self.bytes_skipped += start - pos
            pos = start
            if len(buf) - pos < 2:
                break
            group = buf[pos + 1]
            n_groups = bin(group).count("1")
            if n_groups == 0:
                self.unsupported += 1
                self.bytes_skipped += 1
                pos += 1
                continue
            if len(buf) - pos < 2 + 2 * n_groups:
                break
            masks = [int.from_bytes(buf[pos + 2 + 2 * i : pos + 4 + 2 * i], "little")
                     for i in range(n_groups)]
            length = packet_length(group, masks)
            if length is None:
                self.unsupported += 1
                self.bytes_skipped += 1
                pos += 1
                continue
            if len(buf) - pos < length:
                break
            if vn_crc16(buf[pos + 1 : pos + length]) != 0:
                self.crc_errors += 1
                self.bytes_skipped += 1
                pos += 1
                continue
            out.append(_split_fields(group, masks, bytes(buf[pos + 2 + 2 * n_groups :
                                                             pos + length - 2])))
            self.packets += 1
            pos += length
        del buf[:pos]
        return out


def _split_fields(group: int, masks: list[int], payload: bytes) -> Vn200Packet:
    fields_: dict[tuple[int, int], bytes] = {}
    mask_by_group: dict[int, int] = {}
    offset = 0
    groups = [g for g in range(8) if group >> g & 1]
    for g, mask in zip(groups, masks, strict=True):
        mask_by_group[g + 1] = mask
        for bit in range(16):
            if mask >> bit & 1:
                size = VN_GROUP_FIELD_SIZES[g][bit]
                fields_[(g + 1, bit)] = payload[offset : offset + size]
                offset += size
    return Vn200Packet(group=group, masks=mask_by_group, fields=fields_)
