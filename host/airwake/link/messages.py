# ruff: noqa: E501
# generated from protocol/messages by protocol/codegen — do not edit
"""Message definitions of the airwake wire protocol (docs/protocol.md).

generated from protocol/messages by protocol/codegen — do not edit

One record class per message (a NamedTuple whose fields carry units and frame in
their names) and one `MessageInfo` per message with its id, sizes, definition hash,
CRC seed, precompiled structs, field metadata and numpy dtype description.
"""

from __future__ import annotations

from collections.abc import Callable
from struct import Struct
from typing import Any, NamedTuple

SCHEMA_HASH = 0xE6AFF602
HEADER_SIZE = 7
CRC_SIZE = 2
FRAME_OVERHEAD = 9
MAX_PAYLOAD_SIZE = 259
MAX_RAW_FRAME_SIZE = 268
# Longest valid COBS-encoded frame (without delimiters); a longer segment is oversize.
MAX_ENCODED_SIZE = 270
FLAGS_ORIGIN_MASK = 0x07
BOARDS = {0: 'host', 1: 'losa', 2: 'marker', 3: 'rover', 4: 'base'}
BOARD_IDS = {'host': 0, 'losa': 1, 'marker': 2, 'rover': 3, 'base': 4}
HEADER = Struct("<BBBI")
# Records are built with tuple.__new__ on the decode path: the frame struct already
# guarantees the field count, and skipping NamedTuple's Python-level __new__ halves
# the cost per frame.
_new = tuple.__new__


class FieldInfo(NamedTuple):
    name: str
    type: str
    count: int
    unit: str
    description: str
    values: dict[int, str] | None = None
    bits: dict[int, str] | None = None


class MessageInfo(NamedTuple):
    id: int
    name: str
    record: type
    payload_size: int
    def_hash: int
    crc_seed: int
    payload_struct: Struct
    frame_struct: Struct  # header, payload fields and CRC of a whole raw frame
    fields: tuple[FieldInfo, ...]
    rate_hz: dict[str, float]
    to: tuple[str, ...]
    frozen: bool
    description: str
    time: str
    pack: Callable[[Any], bytes]
    unpack: Callable[[bytes], Any]
    from_frame: Callable[[tuple], Any]  # record from frame_struct.unpack values
    dtype_descr: tuple

    @property
    def raw_frame_size(self) -> int:
        return FRAME_OVERHEAD + self.payload_size

    @property
    def wire_max(self) -> int:
        """Longest wire form: leading 0x00, COBS, trailing 0x00."""
        raw = self.raw_frame_size
        return raw + max(1, -(-raw // 254)) + 2


class Heartbeat(NamedTuple):
    """heartbeat (0x01), frozen layout.

    The HELLO: who the board is, which schema it speaks and its link counters. Its
    layout is frozen (never changes), so every receiver decodes it whatever schema
    either side was built from; new counters go into a new message.

    board_time_us: transmit time.
    """

    MSG_ID = 0x01

    board_id: int = 0
    fw_version_major: int = 0
    fw_version_minor: int = 0
    fw_version_patch: int = 0
    schema_hash: int = 0
    uptime_ms: int = 0
    boot_count: int = 0
    reset_cause: int = 0
    frames_sent: int = 0
    bytes_sent: int = 0
    tx_bytes_dropped: int = 0
    rx_frames_ok: int = 0
    rx_crc_error: int = 0
    rx_unknown_id: int = 0
    rx_def_mismatch: int = 0
    rx_cobs_error: int = 0
    rx_oversize: int = 0
    rx_bytes_dropped: int = 0
    buffer_overruns: int = 0
    task_max_us: int = 0


_S_HEARTBEAT = Struct('<BBBBIIIBIIIIIIIIIIII')
_F_HEARTBEAT = Struct('<BBBIBBBBIIIBIIIIIIIIIIIIH')


def _pack_heartbeat(m: Heartbeat) -> bytes:
    return _S_HEARTBEAT.pack(m.board_id, m.fw_version_major, m.fw_version_minor, m.fw_version_patch, m.schema_hash, m.uptime_ms, m.boot_count, m.reset_cause, m.frames_sent, m.bytes_sent, m.tx_bytes_dropped, m.rx_frames_ok, m.rx_crc_error, m.rx_unknown_id, m.rx_def_mismatch, m.rx_cobs_error, m.rx_oversize, m.rx_bytes_dropped, m.buffer_overruns, m.task_max_us)


def _unpack_heartbeat(b: bytes) -> Heartbeat:
    return Heartbeat._make(_S_HEARTBEAT.unpack(b))


def _from_frame_heartbeat(v: tuple) -> Heartbeat:
    return _new(Heartbeat, v[4:-1])


HEARTBEAT = MessageInfo(
    id=0x01,
    name='heartbeat',
    record=Heartbeat,
    payload_size=65,
    def_hash=0x8DE3D5E4,
    crc_seed=0x5807,
    payload_struct=_S_HEARTBEAT,
    frame_struct=_F_HEARTBEAT,
    fields=(
        FieldInfo('board_id', 'u8', 1, 'enum', 'sending board (see Board ids)', values={0: 'host', 1: 'losa', 2: 'marker', 3: 'rover', 4: 'base'}),
        FieldInfo('fw_version_major', 'u8', 1, '1', 'firmware version, major'),
        FieldInfo('fw_version_minor', 'u8', 1, '1', 'firmware version, minor'),
        FieldInfo('fw_version_patch', 'u8', 1, '1', 'firmware version, patch'),
        FieldInfo('schema_hash', 'u32', 1, 'hash', 'whole-schema hash the firmware was generated from (AW_SCHEMA_HASH)'),
        FieldInfo('uptime_ms', 'u32', 1, 'ms', 'time since reset (wraps after 49.7 days); also unwraps the 32-bit frame clock'),
        FieldInfo('boot_count', 'u32', 1, '1', 'resets since the persistent config was written'),
        FieldInfo('reset_cause', 'u8', 1, 'enum', 'why the board last reset', values={0: 'power_on', 1: 'watchdog', 2: 'software', 3: 'brownout', 4: 'pin', 255: 'unknown'}),
        FieldInfo('frames_sent', 'u32', 1, '1', 'frames queued for transmission since reset'),
        FieldInfo('bytes_sent', 'u32', 1, '1', 'bytes queued for transmission since reset'),
        FieldInfo('tx_bytes_dropped', 'u32', 1, '1', 'bytes not sent because the transmit ring buffer was full'),
        FieldInfo('rx_frames_ok', 'u32', 1, '1', 'frames received and decoded'),
        FieldInfo('rx_crc_error', 'u32', 1, '1', 'received frames failing the CRC (corrupt)'),
        FieldInfo('rx_unknown_id', 'u32', 1, '1', 'received frames with a message id this firmware does not know'),
        FieldInfo('rx_def_mismatch', 'u32', 1, '1', 'received intact frames from a different definition of the message'),
        FieldInfo('rx_cobs_error', 'u32', 1, '1', 'received frames that were not valid COBS or too short'),
        FieldInfo('rx_oversize', 'u32', 1, '1', 'received frames longer than the largest message'),
        FieldInfo('rx_bytes_dropped', 'u32', 1, '1', 'received bytes belonging to frames not delivered'),
        FieldInfo('buffer_overruns', 'u32', 1, '1', 'ring-buffer overruns of every buffer on the board (UART rx/tx, samples)'),
        FieldInfo('task_max_us', 'u32', 1, 'us', 'longest board task iteration since the previous heartbeat'),
    ),
    rate_hz={'losa': 1, 'marker': 1, 'rover': 1, 'base': 1},
    to=(),
    frozen=True,
    description='The HELLO: who the board is, which schema it speaks and its link counters. Its layout is frozen (never changes), so every receiver decodes it whatever schema either side was built from; new counters go into a new message.',
    time='transmit time',
    pack=_pack_heartbeat,
    unpack=_unpack_heartbeat,
    from_frame=_from_frame_heartbeat,
    dtype_descr=(('board_id', 'u1'), ('fw_version_major', 'u1'), ('fw_version_minor', 'u1'), ('fw_version_patch', 'u1'), ('schema_hash', '<u4'), ('uptime_ms', '<u4'), ('boot_count', '<u4'), ('reset_cause', 'u1'), ('frames_sent', '<u4'), ('bytes_sent', '<u4'), ('tx_bytes_dropped', '<u4'), ('rx_frames_ok', '<u4'), ('rx_crc_error', '<u4'), ('rx_unknown_id', '<u4'), ('rx_def_mismatch', '<u4'), ('rx_cobs_error', '<u4'), ('rx_oversize', '<u4'), ('rx_bytes_dropped', '<u4'), ('buffer_overruns', '<u4'), ('task_max_us', '<u4'),),
)


class SchemaEntry(NamedTuple):
    """schema_entry (0x02), frozen layout.

    One entry of the sender's schema: the definition hash of one message id it sends or
    receives. Boards send all their entries at boot, then one entry at least every 250
    ms, cycling, so a receiver that joins late learns them within seconds. A receiver
    uses the announced hash to tell an intact frame from a different definition
    (def_mismatch) from a corrupt one (crc_error). Frozen layout.

    board_time_us: transmit time.
    """

    MSG_ID = 0x02

    msg_id: int = 0
    def_hash: int = 0
    entry_index: int = 0
    entry_count: int = 0


_S_SCHEMA_ENTRY = Struct('<BIBB')
_F_SCHEMA_ENTRY = Struct('<BBBIBIBBH')


def _pack_schema_entry(m: SchemaEntry) -> bytes:
    return _S_SCHEMA_ENTRY.pack(m.msg_id, m.def_hash, m.entry_index, m.entry_count)


def _unpack_schema_entry(b: bytes) -> SchemaEntry:
    return SchemaEntry._make(_S_SCHEMA_ENTRY.unpack(b))


def _from_frame_schema_entry(v: tuple) -> SchemaEntry:
    return _new(SchemaEntry, v[4:-1])


SCHEMA_ENTRY = MessageInfo(
    id=0x02,
    name='schema_entry',
    record=SchemaEntry,
    payload_size=7,
    def_hash=0xA4D7A680,
    crc_seed=0x0257,
    payload_struct=_S_SCHEMA_ENTRY,
    frame_struct=_F_SCHEMA_ENTRY,
    fields=(
        FieldInfo('msg_id', 'u8', 1, '1', 'the message id this entry describes'),
        FieldInfo('def_hash', 'u32', 1, 'hash', "the sender's definition hash of that message"),
        FieldInfo('entry_index', 'u8', 1, '1', "index of this entry in the sender's list (0 .. entry_count-1)"),
        FieldInfo('entry_count', 'u8', 1, '1', 'number of entries the sender announces'),
    ),
    rate_hz={'losa': 4, 'marker': 4, 'rover': 4, 'base': 4, 'host': 4},
    to=('losa', 'marker', 'rover', 'base'),
    frozen=True,
    description="One entry of the sender's schema: the definition hash of one message id it sends or receives. Boards send all their entries at boot, then one entry at least every 250 ms, cycling, so a receiver that joins late learns them within seconds. A receiver uses the announced hash to tell an intact frame from a different definition (def_mismatch) from a corrupt one (crc_error). Frozen layout.",
    time='transmit time',
    pack=_pack_schema_entry,
    unpack=_unpack_schema_entry,
    from_frame=_from_frame_schema_entry,
    dtype_descr=(('msg_id', 'u1'), ('def_hash', '<u4'), ('entry_index', 'u1'), ('entry_count', 'u1'),),
)


class TimeSyncRequest(NamedTuple):
    """time_sync_request (0x03).

    Host -> board clock ping (NTP-style). The board answers with time_sync_reply
    carrying its clock at receive and at transmit; the host estimates offset and drift
    of each board clock from the four timestamps.

    board_time_us: zero (host frames carry no board time).
    """

    MSG_ID = 0x03

    request_id: int = 0
    host_time_us: int = 0


_S_TIME_SYNC_REQUEST = Struct('<IQ')
_F_TIME_SYNC_REQUEST = Struct('<BBBIIQH')


def _pack_time_sync_request(m: TimeSyncRequest) -> bytes:
    return _S_TIME_SYNC_REQUEST.pack(m.request_id, m.host_time_us)


def _unpack_time_sync_request(b: bytes) -> TimeSyncRequest:
    return TimeSyncRequest._make(_S_TIME_SYNC_REQUEST.unpack(b))


def _from_frame_time_sync_request(v: tuple) -> TimeSyncRequest:
    return _new(TimeSyncRequest, v[4:-1])


TIME_SYNC_REQUEST = MessageInfo(
    id=0x03,
    name='time_sync_request',
    record=TimeSyncRequest,
    payload_size=12,
    def_hash=0x73556730,
    crc_seed=0x1465,
    payload_struct=_S_TIME_SYNC_REQUEST,
    frame_struct=_F_TIME_SYNC_REQUEST,
    fields=(
        FieldInfo('request_id', 'u32', 1, '1', 'chosen by the host, echoed in the reply'),
        FieldInfo('host_time_us', 'u64', 1, 'us', 'host monotonic clock when the request was written'),
    ),
    rate_hz={'host': 2},
    to=('losa', 'marker', 'rover', 'base'),
    frozen=False,
    description='Host -> board clock ping (NTP-style). The board answers with time_sync_reply carrying its clock at receive and at transmit; the host estimates offset and drift of each board clock from the four timestamps.',
    time='zero (host frames carry no board time)',
    pack=_pack_time_sync_request,
    unpack=_unpack_time_sync_request,
    from_frame=_from_frame_time_sync_request,
    dtype_descr=(('request_id', '<u4'), ('host_time_us', '<u8'),),
)


class TimeSyncReply(NamedTuple):
    """time_sync_reply (0x04).

    Board answer to time_sync_request. offset = ((board_rx - host_tx) + (board_tx -
    host_rx)) / 2 with host_rx the host's clock when the reply arrived. The 64-bit board
    times also let the host unwrap the 32-bit frame clock.

    board_time_us: transmit time (low 32 bits of board_tx_time_us).
    """

    MSG_ID = 0x04

    request_id: int = 0
    host_time_us: int = 0
    board_rx_time_us: int = 0
    board_tx_time_us: int = 0


_S_TIME_SYNC_REPLY = Struct('<IQQQ')
_F_TIME_SYNC_REPLY = Struct('<BBBIIQQQH')


def _pack_time_sync_reply(m: TimeSyncReply) -> bytes:
    return _S_TIME_SYNC_REPLY.pack(m.request_id, m.host_time_us, m.board_rx_time_us, m.board_tx_time_us)


def _unpack_time_sync_reply(b: bytes) -> TimeSyncReply:
    return TimeSyncReply._make(_S_TIME_SYNC_REPLY.unpack(b))


def _from_frame_time_sync_reply(v: tuple) -> TimeSyncReply:
    return _new(TimeSyncReply, v[4:-1])


TIME_SYNC_REPLY = MessageInfo(
    id=0x04,
    name='time_sync_reply',
    record=TimeSyncReply,
    payload_size=28,
    def_hash=0x85D4B8FA,
    crc_seed=0x3D2E,
    payload_struct=_S_TIME_SYNC_REPLY,
    frame_struct=_F_TIME_SYNC_REPLY,
    fields=(
        FieldInfo('request_id', 'u32', 1, '1', 'request_id of the request being answered'),
        FieldInfo('host_time_us', 'u64', 1, 'us', 'host_time_us of the request, echoed'),
        FieldInfo('board_rx_time_us', 'u64', 1, 'us', "board clock when the request's last byte was received"),
        FieldInfo('board_tx_time_us', 'u64', 1, 'us', 'board clock when this reply was queued'),
    ),
    rate_hz={'losa': 2, 'marker': 2, 'rover': 2, 'base': 2},
    to=(),
    frozen=False,
    description="Board answer to time_sync_request. offset = ((board_rx - host_tx) + (board_tx - host_rx)) / 2 with host_rx the host's clock when the reply arrived. The 64-bit board times also let the host unwrap the 32-bit frame clock.",
    time='transmit time (low 32 bits of board_tx_time_us)',
    pack=_pack_time_sync_reply,
    unpack=_unpack_time_sync_reply,
    from_frame=_from_frame_time_sync_reply,
    dtype_descr=(('request_id', '<u4'), ('host_time_us', '<u8'), ('board_rx_time_us', '<u8'), ('board_tx_time_us', '<u8'),),
)


class LogText(NamedTuple):
    """log_text (0x05).

    A short human-readable event from the board (sensor missing, mode change).

    board_time_us: time of the event.
    """

    MSG_ID = 0x05

    level: int = 0
    code: int = 0
    text_utf8: tuple[int, ...] = (0,) * 48


_S_LOG_TEXT = Struct('<BH48B')
_F_LOG_TEXT = Struct('<BBBIBH48BH')


def _pack_log_text(m: LogText) -> bytes:
    return _S_LOG_TEXT.pack(m.level, m.code, *m.text_utf8)


def _unpack_log_text(b: bytes) -> LogText:
    v = _S_LOG_TEXT.unpack(b)
    return LogText(v[0], v[1], v[2:50])


def _from_frame_log_text(v: tuple) -> LogText:
    return _new(LogText, (v[4], v[5], v[6:54]))


LOG_TEXT = MessageInfo(
    id=0x05,
    name='log_text',
    record=LogText,
    payload_size=51,
    def_hash=0x21E4B6F8,
    crc_seed=0x971C,
    payload_struct=_S_LOG_TEXT,
    frame_struct=_F_LOG_TEXT,
    fields=(
        FieldInfo('level', 'u8', 1, 'enum', 'severity', values={0: 'debug', 1: 'info', 2: 'warning', 3: 'error'}),
        FieldInfo('code', 'u16', 1, '1', 'machine-readable event code, board specific'),
        FieldInfo('text_utf8', 'u8', 48, 'text', 'UTF-8 text, zero padded'),
    ),
    rate_hz={'losa': 1, 'marker': 1, 'rover': 1, 'base': 1},
    to=(),
    frozen=False,
    description='A short human-readable event from the board (sensor missing, mode change).',
    time='time of the event',
    pack=_pack_log_text,
    unpack=_unpack_log_text,
    from_frame=_from_frame_log_text,
    dtype_descr=(('level', 'u1'), ('code', '<u2'), ('text_utf8', 'u1', (48,)),),
)


class StampLatency(NamedTuple):
    """stamp_latency (0x06).

    What one message's board_time_us marks and how long after the instant its data
    describe (the sample instant) that is, as far as the sender's firmware knows it:
    fixed parts only (a peer's documented output latency, a packet's time on a UART at
    the configured baud), from the firmware's own constants. The host subtracts it from
    the mapped times when it exports a flight table. A board sends one entry per message
    it describes after each heartbeat, so a receiver that joins late learns them within
    a second.

    board_time_us: transmit time.
    """

    MSG_ID = 0x06

    msg_id: int = 0
    latency_us: int = 0
    stamp_event: int = 0
    entry_index: int = 0
    entry_count: int = 0


_S_STAMP_LATENCY = Struct('<BIBBB')
_F_STAMP_LATENCY = Struct('<BBBIBIBBBH')


def _pack_stamp_latency(m: StampLatency) -> bytes:
    return _S_STAMP_LATENCY.pack(m.msg_id, m.latency_us, m.stamp_event, m.entry_index, m.entry_count)


def _unpack_stamp_latency(b: bytes) -> StampLatency:
    return StampLatency._make(_S_STAMP_LATENCY.unpack(b))


def _from_frame_stamp_latency(v: tuple) -> StampLatency:
    return _new(StampLatency, v[4:-1])


STAMP_LATENCY = MessageInfo(
    id=0x06,
    name='stamp_latency',
    record=StampLatency,
    payload_size=8,
    def_hash=0x9E56D74D,
    crc_seed=0x491B,
    payload_struct=_S_STAMP_LATENCY,
    frame_struct=_F_STAMP_LATENCY,
    fields=(
        FieldInfo('msg_id', 'u8', 1, '1', 'the message id this entry describes'),
        FieldInfo('latency_us', 'u32', 1, 'us', 'board_time_us of that message minus the sample instant of its data'),
        FieldInfo('stamp_event', 'u8', 1, 'enum', 'what board_time_us of that message marks', values={0: 'transmit', 1: 'peer_packet_end', 2: 'rc_frame_start', 3: 'peer_packet_start'}),
        FieldInfo('entry_index', 'u8', 1, '1', "index of this entry in the sender's list (0 .. entry_count-1)"),
        FieldInfo('entry_count', 'u8', 1, '1', 'number of entries the sender declares'),
    ),
    rate_hz={'rover': 1, 'base': 2, 'marker': 1},
    to=(),
    frozen=False,
    description="What one message's board_time_us marks and how long after the instant its data describe (the sample instant) that is, as far as the sender's firmware knows it: fixed parts only (a peer's documented output latency, a packet's time on a UART at the configured baud), from the firmware's own constants. The host subtracts it from the mapped times when it exports a flight table. A board sends one entry per message it describes after each heartbeat, so a receiver that joins late learns them within a second.",
    time='transmit time',
    pack=_pack_stamp_latency,
    unpack=_unpack_stamp_latency,
    from_frame=_from_frame_stamp_latency,
    dtype_descr=(('msg_id', 'u1'), ('latency_us', '<u4'), ('stamp_event', 'u1'), ('entry_index', 'u1'), ('entry_count', 'u1'),),
)


class Imu(NamedTuple):
    """imu (0x10).

    Raw inertial sample of a board's IMU (LOSA and marker: MPU9250-class over SPI; rover
    and base: the VN200's IMU when configured). The origin board is in the frame flags;
    axes are the board's body frame, x forward, y right, z down.

    board_time_us: sample time.
    """

    MSG_ID = 0x10

    gyro_frd_rad_s: tuple[float, float, float] = (0.0,) * 3
    accel_frd_m_s2: tuple[float, float, float] = (0.0,) * 3
    mag_frd_ut: tuple[float, float, float] = (0.0,) * 3
    temperature_c: float = 0.0
    status: int = 0


_S_IMU = Struct('<3f3f3ffB')
_F_IMU = Struct('<BBBI3f3f3ffBH')


def _pack_imu(m: Imu) -> bytes:
    return _S_IMU.pack(*m.gyro_frd_rad_s, *m.accel_frd_m_s2, *m.mag_frd_ut, m.temperature_c, m.status)


def _unpack_imu(b: bytes) -> Imu:
    v = _S_IMU.unpack(b)
    return Imu(v[0:3], v[3:6], v[6:9], v[9], v[10])


def _from_frame_imu(v: tuple) -> Imu:
    return _new(Imu, (v[4:7], v[7:10], v[10:13], v[13], v[14]))


IMU = MessageInfo(
    id=0x10,
    name='imu',
    record=Imu,
    payload_size=41,
    def_hash=0x9ABEA190,
    crc_seed=0x3B2E,
    payload_struct=_S_IMU,
    frame_struct=_F_IMU,
    fields=(
        FieldInfo('gyro_frd_rad_s', 'f32', 3, 'rad/s', 'angular rate, body axes'),
        FieldInfo('accel_frd_m_s2', 'f32', 3, 'm/s^2', 'specific force, body axes (at rest z = -9.81)'),
        FieldInfo('mag_frd_ut', 'f32', 3, 'uT', 'magnetic field, body axes'),
        FieldInfo('temperature_c', 'f32', 1, 'degC', 'IMU die temperature'),
        FieldInfo('status', 'u8', 1, 'bits', 'sample flags', bits={0: 'gyro_saturated', 1: 'accel_saturated', 2: 'mag_valid'}),
    ),
    rate_hz={'losa': 100, 'marker': 120, 'rover': 50, 'base': 50},
    to=(),
    frozen=False,
    description="Raw inertial sample of a board's IMU (LOSA and marker: MPU9250-class over SPI; rover and base: the VN200's IMU when configured). The origin board is in the frame flags; axes are the board's body frame, x forward, y right, z down.",
    time='sample time',
    pack=_pack_imu,
    unpack=_unpack_imu,
    from_frame=_from_frame_imu,
    dtype_descr=(('gyro_frd_rad_s', '<f4', (3,)), ('accel_frd_m_s2', '<f4', (3,)), ('mag_frd_ut', '<f4', (3,)), ('temperature_c', '<f4'), ('status', 'u1'),),
)


class LosaPeaks(NamedTuple):
    """losa_peaks (0x20).

    The LOSA tracker's per-frame result for its four TSL1401 sensors: sub-pixel peak
    position (weighted least-squares line intersection in a +-3 pixel window, §3.3.1.5),
    unwrapped across the three slots (peak_px = pixel on the array + 128 * slot), peak
    intensity, slot index and the exposure the line was taken with.

    board_time_us: middle of the exposure of the line.
    """

    MSG_ID = 0x20

    peak_px: tuple[float, float, float, float] = (0.0,) * 4
    intensity_counts: tuple[int, int, int, int] = (0,) * 4
    slot: tuple[int, int, int, int] = (0,) * 4
    exposure_us: tuple[int, int, int, int] = (0,) * 4
    sensor_flags: tuple[int, int, int, int] = (0,) * 4


_S_LOSA_PEAKS = Struct('<4f4H4b4H4B')
_F_LOSA_PEAKS = Struct('<BBBI4f4H4b4H4BH')


def _pack_losa_peaks(m: LosaPeaks) -> bytes:
    return _S_LOSA_PEAKS.pack(*m.peak_px, *m.intensity_counts, *m.slot, *m.exposure_us, *m.sensor_flags)


def _unpack_losa_peaks(b: bytes) -> LosaPeaks:
    v = _S_LOSA_PEAKS.unpack(b)
    return LosaPeaks(v[0:4], v[4:8], v[8:12], v[12:16], v[16:20])


def _from_frame_losa_peaks(v: tuple) -> LosaPeaks:
    return _new(LosaPeaks, (v[4:8], v[8:12], v[12:16], v[16:20], v[20:24]))


LOSA_PEAKS = MessageInfo(
    id=0x20,
    name='losa_peaks',
    record=LosaPeaks,
    payload_size=40,
    def_hash=0x40424835,
    crc_seed=0x0877,
    payload_struct=_S_LOSA_PEAKS,
    frame_struct=_F_LOSA_PEAKS,
    fields=(
        FieldInfo('peak_px', 'f32', 4, 'px', 'sub-pixel peak position per sensor, unwrapped across slots'),
        FieldInfo('intensity_counts', 'u16', 4, 'counts', 'peak pixel value per sensor (ADC counts)'),
        FieldInfo('slot', 'i8', 4, '1', 'slot the peak is attributed to per sensor: -1, 0 (centre), +1'),
        FieldInfo('exposure_us', 'u16', 4, 'us', 'integration time of the line per sensor'),
        FieldInfo('sensor_flags', 'u8', 4, 'bits', 'per-sensor state', bits={0: 'valid', 1: 'saturated', 2: 'slot_jump', 3: 'exposure_changed'}),
    ),
    rate_hz={'losa': 320},
    to=(),
    frozen=False,
    description="The LOSA tracker's per-frame result for its four TSL1401 sensors: sub-pixel peak position (weighted least-squares line intersection in a +-3 pixel window, §3.3.1.5), unwrapped across the three slots (peak_px = pixel on the array + 128 * slot), peak intensity, slot index and the exposure the line was taken with.",
    time='middle of the exposure of the line',
    pack=_pack_losa_peaks,
    unpack=_unpack_losa_peaks,
    from_frame=_from_frame_losa_peaks,
    dtype_descr=(('peak_px', '<f4', (4,)), ('intensity_counts', '<u2', (4,)), ('slot', 'i1', (4,)), ('exposure_us', '<u2', (4,)), ('sensor_flags', 'u1', (4,)),),
)


class LosaRawLine(NamedTuple):
    """losa_raw_line (0x21).

    One sensor's full 128-pixel line, sent only while requested by losa_raw_request
    (diagnostics, optics calibration). Longer than 254 bytes: its COBS encoding needs a
    0xFF block.

    board_time_us: middle of the exposure of the line.
    """

    MSG_ID = 0x21

    sensor_index: int = 0
    exposure_us: int = 0
    pixels_counts: tuple[int, ...] = (0,) * 128


_S_LOSA_RAW_LINE = Struct('<BH128H')
_F_LOSA_RAW_LINE = Struct('<BBBIBH128HH')


def _pack_losa_raw_line(m: LosaRawLine) -> bytes:
    return _S_LOSA_RAW_LINE.pack(m.sensor_index, m.exposure_us, *m.pixels_counts)


def _unpack_losa_raw_line(b: bytes) -> LosaRawLine:
    v = _S_LOSA_RAW_LINE.unpack(b)
    return LosaRawLine(v[0], v[1], v[2:130])


def _from_frame_losa_raw_line(v: tuple) -> LosaRawLine:
    return _new(LosaRawLine, (v[4], v[5], v[6:134]))


LOSA_RAW_LINE = MessageInfo(
    id=0x21,
    name='losa_raw_line',
    record=LosaRawLine,
    payload_size=259,
    def_hash=0x25A45C47,
    crc_seed=0x79E3,
    payload_struct=_S_LOSA_RAW_LINE,
    frame_struct=_F_LOSA_RAW_LINE,
    fields=(
        FieldInfo('sensor_index', 'u8', 1, '1', 'sensor 0..3'),
        FieldInfo('exposure_us', 'u16', 1, 'us', 'integration time of the line'),
        FieldInfo('pixels_counts', 'u16', 128, 'counts', 'pixel values in array order (ADC counts)'),
    ),
    rate_hz={'losa': 10},
    to=(),
    frozen=False,
    description="One sensor's full 128-pixel line, sent only while requested by losa_raw_request (diagnostics, optics calibration). Longer than 254 bytes: its COBS encoding needs a 0xFF block.",
    time='middle of the exposure of the line',
    pack=_pack_losa_raw_line,
    unpack=_unpack_losa_raw_line,
    from_frame=_from_frame_losa_raw_line,
    dtype_descr=(('sensor_index', 'u1'), ('exposure_us', '<u2'), ('pixels_counts', '<u2', (128,)),),
)


class LosaRawRequest(NamedTuple):
    """losa_raw_request (0x22).

    Host -> LOSA: send raw lines of the selected sensors (count 0 stops).

    board_time_us: zero (host frames carry no board time).
    """

    MSG_ID = 0x22

    sensor_mask: int = 0
    line_count: int = 0
    decimation: int = 0


_S_LOSA_RAW_REQUEST = Struct('<BHB')
_F_LOSA_RAW_REQUEST = Struct('<BBBIBHBH')


def _pack_losa_raw_request(m: LosaRawRequest) -> bytes:
    return _S_LOSA_RAW_REQUEST.pack(m.sensor_mask, m.line_count, m.decimation)


def _unpack_losa_raw_request(b: bytes) -> LosaRawRequest:
    return LosaRawRequest._make(_S_LOSA_RAW_REQUEST.unpack(b))


def _from_frame_losa_raw_request(v: tuple) -> LosaRawRequest:
    return _new(LosaRawRequest, v[4:-1])


LOSA_RAW_REQUEST = MessageInfo(
    id=0x22,
    name='losa_raw_request',
    record=LosaRawRequest,
    payload_size=4,
    def_hash=0x405119AB,
    crc_seed=0x59FA,
    payload_struct=_S_LOSA_RAW_REQUEST,
    frame_struct=_F_LOSA_RAW_REQUEST,
    fields=(
        FieldInfo('sensor_mask', 'u8', 1, 'bits', 'sensors to send, bit i = sensor i', bits={0: 'sensor0', 1: 'sensor1', 2: 'sensor2', 3: 'sensor3'}),
        FieldInfo('line_count', 'u16', 1, '1', 'lines to send per selected sensor; 0 stops, 65535 = until stopped'),
        FieldInfo('decimation', 'u8', 1, '1', 'send every Nth tracker frame (0 and 1: every frame)'),
    ),
    rate_hz={'host': 1},
    to=('losa',),
    frozen=False,
    description='Host -> LOSA: send raw lines of the selected sensors (count 0 stops).',
    time='zero (host frames carry no board time)',
    pack=_pack_losa_raw_request,
    unpack=_unpack_losa_raw_request,
    from_frame=_from_frame_losa_raw_request,
    dtype_descr=(('sensor_mask', 'u1'), ('line_count', '<u2'), ('decimation', 'u1'),),
)


class MarkerAttitude(NamedTuple):
    """marker_attitude (0x30).

    The active marker's state (§3.3.1.4): integrated attitude, the tracked gravity and
    line-of-sight vectors, mode, which LED is lit and how bright, gyro bias estimate.

    board_time_us: time of the IMU sample the attitude was propagated to.
    """

    MSG_ID = 0x30

    quat_init_from_body_wxyz: tuple[float, float, float, float] = (0.0,) * 4
    gravity_frd_unit: tuple[float, float, float] = (0.0,) * 3
    los_frd_unit: tuple[float, float, float] = (0.0,) * 3
    mode: int = 0
    active_led: int = 0
    led_duty_q16: int = 0
    gyro_bias_frd_rad_s: tuple[float, float, float] = (0.0,) * 3
    ir_feedback_age_ms: int = 0


_S_MARKER_ATTITUDE = Struct('<4f3f3fBBH3fH')
_F_MARKER_ATTITUDE = Struct('<BBBI4f3f3fBBH3fHH')


def _pack_marker_attitude(m: MarkerAttitude) -> bytes:
    return _S_MARKER_ATTITUDE.pack(*m.quat_init_from_body_wxyz, *m.gravity_frd_unit, *m.los_frd_unit, m.mode, m.active_led, m.led_duty_q16, *m.gyro_bias_frd_rad_s, m.ir_feedback_age_ms)


def _unpack_marker_attitude(b: bytes) -> MarkerAttitude:
    v = _S_MARKER_ATTITUDE.unpack(b)
    return MarkerAttitude(v[0:4], v[4:7], v[7:10], v[10], v[11], v[12], v[13:16], v[16])


def _from_frame_marker_attitude(v: tuple) -> MarkerAttitude:
    return _new(MarkerAttitude, (v[4:8], v[8:11], v[11:14], v[14], v[15], v[16], v[17:20], v[20]))


MARKER_ATTITUDE = MessageInfo(
    id=0x30,
    name='marker_attitude',
    record=MarkerAttitude,
    payload_size=58,
    def_hash=0x8FA9EE5C,
    crc_seed=0x61F5,
    payload_struct=_S_MARKER_ATTITUDE,
    frame_struct=_F_MARKER_ATTITUDE,
    fields=(
        FieldInfo('quat_init_from_body_wxyz', 'f32', 4, '1', 'unit quaternion rotating body-frame vectors into the frame of the last calibration (w, x, y, z), eq 3.9'),
        FieldInfo('gravity_frd_unit', 'f32', 3, 'unit vector', 'gravity direction in the current body frame'),
        FieldInfo('los_frd_unit', 'f32', 3, 'unit vector', 'line of sight to the tracker in the current body frame'),
        FieldInfo('mode', 'u8', 1, 'enum', 'marker state machine', values={0: 'boot', 1: 'calibrate_still', 2: 'calibrate_leds', 3: 'tracking', 4: 'ir_lost'}),
        FieldInfo('active_led', 'u8', 1, '1', 'LED lit now (0..3), 255 = none'),
        FieldInfo('led_duty_q16', 'u16', 1, '1/65535', 'LED drive duty cycle, 65535 = full'),
        FieldInfo('gyro_bias_frd_rad_s', 'f32', 3, 'rad/s', 'current gyro bias estimate, body axes'),
        FieldInfo('ir_feedback_age_ms', 'u16', 1, 'ms', 'time since the last marker_command with a seen peak (saturates at 65535)'),
    ),
    rate_hz={'marker': 120},
    to=(),
    frozen=False,
    description="The active marker's state (§3.3.1.4): integrated attitude, the tracked gravity and line-of-sight vectors, mode, which LED is lit and how bright, gyro bias estimate.",
    time='time of the IMU sample the attitude was propagated to',
    pack=_pack_marker_attitude,
    unpack=_unpack_marker_attitude,
    from_frame=_from_frame_marker_attitude,
    dtype_descr=(('quat_init_from_body_wxyz', '<f4', (4,)), ('gravity_frd_unit', '<f4', (3,)), ('los_frd_unit', '<f4', (3,)), ('mode', 'u1'), ('active_led', 'u1'), ('led_duty_q16', '<u2'), ('gyro_bias_frd_rad_s', '<f4', (3,)), ('ir_feedback_age_ms', '<u2'),),
)


class MarkerCommand(NamedTuple):
    """marker_command (0x31).

    Host -> marker feedback: the peak intensity the tracker measured for each LED (the
    host attributes a peak to the LED the marker reported lit) and the host's position
    estimate of the marker in the tracker frame.

    board_time_us: zero (host frames carry no board time).
    """

    MSG_ID = 0x31

    led_peak_counts: tuple[int, int, int, int] = (0,) * 4
    full_scale_counts: int = 0
    pos_tracker_m: tuple[float, float, float] = (0.0,) * 3
    pos_valid: int = 0


_S_MARKER_COMMAND = Struct('<4HH3fB')
_F_MARKER_COMMAND = Struct('<BBBI4HH3fBH')


def _pack_marker_command(m: MarkerCommand) -> bytes:
    return _S_MARKER_COMMAND.pack(*m.led_peak_counts, m.full_scale_counts, *m.pos_tracker_m, m.pos_valid)


def _unpack_marker_command(b: bytes) -> MarkerCommand:
    v = _S_MARKER_COMMAND.unpack(b)
    return MarkerCommand(v[0:4], v[4], v[5:8], v[8])


def _from_frame_marker_command(v: tuple) -> MarkerCommand:
    return _new(MarkerCommand, (v[4:8], v[8], v[9:12], v[12]))


MARKER_COMMAND = MessageInfo(
    id=0x31,
    name='marker_command',
    record=MarkerCommand,
    payload_size=23,
    def_hash=0x2BFFD56C,
    crc_seed=0xFE93,
    payload_struct=_S_MARKER_COMMAND,
    frame_struct=_F_MARKER_COMMAND,
    fields=(
        FieldInfo('led_peak_counts', 'u16', 4, 'counts', 'brightest tracker peak seen for each LED (0 = not seen)'),
        FieldInfo('full_scale_counts', 'u16', 1, 'counts', 'tracker ADC full scale (the marker holds its peak at ~20 % of it)'),
        FieldInfo('pos_tracker_m', 'f32', 3, 'm', 'marker position estimate in the tracker frame'),
        FieldInfo('pos_valid', 'u8', 1, '1', '1 when pos_tracker_m is valid'),
    ),
    rate_hz={'host': 60},
    to=('marker',),
    frozen=False,
    description="Host -> marker feedback: the peak intensity the tracker measured for each LED (the host attributes a peak to the LED the marker reported lit) and the host's position estimate of the marker in the tracker frame.",
    time='zero (host frames carry no board time)',
    pack=_pack_marker_command,
    unpack=_unpack_marker_command,
    from_frame=_from_frame_marker_command,
    dtype_descr=(('led_peak_counts', '<u2', (4,)), ('full_scale_counts', '<u2'), ('pos_tracker_m', '<f4', (3,)), ('pos_valid', 'u1'),),
)


class Ins(NamedTuple):
    """ins (0x40).

    VN200-class INS solution as the rover and base read it (VectorNav binary group 1:
    TimeStartup, YawPitchRoll, AngularRate, Position, Velocity, Accel, InsStatus),
    forwarded with the sensor's own units.

    board_time_us: board time when the VN200 packet was parsed (its last byte in);
    stamp_latency says how long after the sample instant.
    """

    MSG_ID = 0x40

    time_startup_ns: int = 0
    ypr_deg: tuple[float, float, float] = (0.0,) * 3
    angular_rate_frd_rad_s: tuple[float, float, float] = (0.0,) * 3
    lat_deg: float = 0.0
    lon_deg: float = 0.0
    alt_m: float = 0.0
    vel_ned_m_s: tuple[float, float, float] = (0.0,) * 3
    accel_frd_m_s2: tuple[float, float, float] = (0.0,) * 3
    ins_status: int = 0


_S_INS = Struct('<Q3f3fddd3f3fH')
_F_INS = Struct('<BBBIQ3f3fddd3f3fHH')


def _pack_ins(m: Ins) -> bytes:
    return _S_INS.pack(m.time_startup_ns, *m.ypr_deg, *m.angular_rate_frd_rad_s, m.lat_deg, m.lon_deg, m.alt_m, *m.vel_ned_m_s, *m.accel_frd_m_s2, m.ins_status)


def _unpack_ins(b: bytes) -> Ins:
    v = _S_INS.unpack(b)
    return Ins(v[0], v[1:4], v[4:7], v[7], v[8], v[9], v[10:13], v[13:16], v[16])


def _from_frame_ins(v: tuple) -> Ins:
    return _new(Ins, (v[4], v[5:8], v[8:11], v[11], v[12], v[13], v[14:17], v[17:20], v[20]))


INS = MessageInfo(
    id=0x40,
    name='ins',
    record=Ins,
    payload_size=82,
    def_hash=0x06B84EBA,
    crc_seed=0x4802,
    payload_struct=_S_INS,
    frame_struct=_F_INS,
    fields=(
        FieldInfo('time_startup_ns', 'u64', 1, 'ns', 'VN200 time since its startup'),
        FieldInfo('ypr_deg', 'f32', 3, 'deg', 'yaw, pitch, roll (3-2-1 Euler angles of body from NED)'),
        FieldInfo('angular_rate_frd_rad_s', 'f32', 3, 'rad/s', 'angular rate, body axes (bias compensated)'),
        FieldInfo('lat_deg', 'f64', 1, 'deg', 'latitude, WGS84'),
        FieldInfo('lon_deg', 'f64', 1, 'deg', 'longitude, WGS84'),
        FieldInfo('alt_m', 'f64', 1, 'm', 'height above the WGS84 ellipsoid'),
        FieldInfo('vel_ned_m_s', 'f32', 3, 'm/s', 'velocity, north east down'),
        FieldInfo('accel_frd_m_s2', 'f32', 3, 'm/s^2', 'acceleration as VN200 reports it, body axes (includes gravity: at rest z = -9.8)'),
        FieldInfo('ins_status', 'u16', 1, 'bits', 'VN200 InsStatus word (bits 0-1 mode: 0 not tracking, 1 aligning, 2 tracking, 3 loss of GNSS)', bits={2: 'gnss_fix', 4: 'imu_error', 5: 'mag_pres_error', 6: 'gnss_error'}),
    ),
    rate_hz={'rover': 150, 'base': 150},
    to=(),
    frozen=False,
    description="VN200-class INS solution as the rover and base read it (VectorNav binary group 1: TimeStartup, YawPitchRoll, AngularRate, Position, Velocity, Accel, InsStatus), forwarded with the sensor's own units.",
    time='board time when the VN200 packet was parsed (its last byte in); stamp_latency says how long after the sample instant',
    pack=_pack_ins,
    unpack=_unpack_ins,
    from_frame=_from_frame_ins,
    dtype_descr=(('time_startup_ns', '<u8'), ('ypr_deg', '<f4', (3,)), ('angular_rate_frd_rad_s', '<f4', (3,)), ('lat_deg', '<f8'), ('lon_deg', '<f8'), ('alt_m', '<f8'), ('vel_ned_m_s', '<f4', (3,)), ('accel_frd_m_s2', '<f4', (3,)), ('ins_status', '<u2'),),
)


class RtkBaseline(NamedTuple):
    """rtk_baseline (0x41).

    Piksi RTK baseline rover minus base, from SBP MSG_BASELINE_NED.

    board_time_us: board time when the SBP frame's first byte arrived.
    """

    MSG_ID = 0x41

    gps_tow_ms: int = 0
    baseline_ned_mm: tuple[int, int, int] = (0,) * 3
    h_accuracy_mm: int = 0
    v_accuracy_mm: int = 0
    num_sats: int = 0
    fix_mode: int = 0


_S_RTK_BASELINE = Struct('<I3iHHBB')
_F_RTK_BASELINE = Struct('<BBBII3iHHBBH')


def _pack_rtk_baseline(m: RtkBaseline) -> bytes:
    return _S_RTK_BASELINE.pack(m.gps_tow_ms, *m.baseline_ned_mm, m.h_accuracy_mm, m.v_accuracy_mm, m.num_sats, m.fix_mode)


def _unpack_rtk_baseline(b: bytes) -> RtkBaseline:
    v = _S_RTK_BASELINE.unpack(b)
    return RtkBaseline(v[0], v[1:4], v[4], v[5], v[6], v[7])


def _from_frame_rtk_baseline(v: tuple) -> RtkBaseline:
    return _new(RtkBaseline, (v[4], v[5:8], v[8], v[9], v[10], v[11]))


RTK_BASELINE = MessageInfo(
    id=0x41,
    name='rtk_baseline',
    record=RtkBaseline,
    payload_size=22,
    def_hash=0xAC79FC26,
    crc_seed=0x505F,
    payload_struct=_S_RTK_BASELINE,
    frame_struct=_F_RTK_BASELINE,
    fields=(
        FieldInfo('gps_tow_ms', 'u32', 1, 'ms', 'GPS time of week of the solution'),
        FieldInfo('baseline_ned_mm', 'i32', 3, 'mm', 'baseline north, east, down'),
        FieldInfo('h_accuracy_mm', 'u16', 1, 'mm', 'horizontal accuracy estimate'),
        FieldInfo('v_accuracy_mm', 'u16', 1, 'mm', 'vertical accuracy estimate'),
        FieldInfo('num_sats', 'u8', 1, '1', 'satellites used'),
        FieldInfo('fix_mode', 'u8', 1, 'enum', 'SBP flags bits 0-2', values={0: 'invalid', 1: 'spp', 2: 'dgnss', 3: 'float_rtk', 4: 'fixed_rtk'}),
    ),
    rate_hz={'rover': 10},
    to=(),
    frozen=False,
    description='Piksi RTK baseline rover minus base, from SBP MSG_BASELINE_NED.',
    time="board time when the SBP frame's first byte arrived",
    pack=_pack_rtk_baseline,
    unpack=_unpack_rtk_baseline,
    from_frame=_from_frame_rtk_baseline,
    dtype_descr=(('gps_tow_ms', '<u4'), ('baseline_ned_mm', '<i4', (3,)), ('h_accuracy_mm', '<u2'), ('v_accuracy_mm', '<u2'), ('num_sats', 'u1'), ('fix_mode', 'u1'),),
)


class RtkPos(NamedTuple):
    """rtk_pos (0x42).

    Piksi geodetic position, from SBP MSG_POS_LLH.

    board_time_us: board time when the SBP frame's first byte arrived.
    """

    MSG_ID = 0x42

    gps_tow_ms: int = 0
    lat_deg: float = 0.0
    lon_deg: float = 0.0
    height_m: float = 0.0
    h_accuracy_mm: int = 0
    v_accuracy_mm: int = 0
    num_sats: int = 0
    fix_mode: int = 0


_S_RTK_POS = Struct('<IdddHHBB')
_F_RTK_POS = Struct('<BBBIIdddHHBBH')


def _pack_rtk_pos(m: RtkPos) -> bytes:
    return _S_RTK_POS.pack(m.gps_tow_ms, m.lat_deg, m.lon_deg, m.height_m, m.h_accuracy_mm, m.v_accuracy_mm, m.num_sats, m.fix_mode)


def _unpack_rtk_pos(b: bytes) -> RtkPos:
    return RtkPos._make(_S_RTK_POS.unpack(b))


def _from_frame_rtk_pos(v: tuple) -> RtkPos:
    return _new(RtkPos, v[4:-1])


RTK_POS = MessageInfo(
    id=0x42,
    name='rtk_pos',
    record=RtkPos,
    payload_size=34,
    def_hash=0x552E6E1D,
    crc_seed=0x3B33,
    payload_struct=_S_RTK_POS,
    frame_struct=_F_RTK_POS,
    fields=(
        FieldInfo('gps_tow_ms', 'u32', 1, 'ms', 'GPS time of week of the solution'),
        FieldInfo('lat_deg', 'f64', 1, 'deg', 'latitude, WGS84'),
        FieldInfo('lon_deg', 'f64', 1, 'deg', 'longitude, WGS84'),
        FieldInfo('height_m', 'f64', 1, 'm', 'height above the WGS84 ellipsoid'),
        FieldInfo('h_accuracy_mm', 'u16', 1, 'mm', 'horizontal accuracy estimate'),
        FieldInfo('v_accuracy_mm', 'u16', 1, 'mm', 'vertical accuracy estimate'),
        FieldInfo('num_sats', 'u8', 1, '1', 'satellites used'),
        FieldInfo('fix_mode', 'u8', 1, 'enum', 'SBP flags bits 0-2', values={0: 'invalid', 1: 'spp', 2: 'dgnss', 3: 'float_rtk', 4: 'fixed_rtk', 5: 'dead_reckoning', 6: 'sbas'}),
    ),
    rate_hz={'rover': 10, 'base': 1},
    to=(),
    frozen=False,
    description='Piksi geodetic position, from SBP MSG_POS_LLH.',
    time="board time when the SBP frame's first byte arrived",
    pack=_pack_rtk_pos,
    unpack=_unpack_rtk_pos,
    from_frame=_from_frame_rtk_pos,
    dtype_descr=(('gps_tow_ms', '<u4'), ('lat_deg', '<f8'), ('lon_deg', '<f8'), ('height_m', '<f8'), ('h_accuracy_mm', '<u2'), ('v_accuracy_mm', '<u2'), ('num_sats', 'u1'), ('fix_mode', 'u1'),),
)


class RtkVel(NamedTuple):
    """rtk_vel (0x43).

    Piksi velocity, from SBP MSG_VEL_NED.

    board_time_us: board time when the SBP frame's first byte arrived.
    """

    MSG_ID = 0x43

    gps_tow_ms: int = 0
    vel_ned_mm_s: tuple[int, int, int] = (0,) * 3
    h_accuracy_mm_s: int = 0
    v_accuracy_mm_s: int = 0
    num_sats: int = 0
    fix_mode: int = 0


_S_RTK_VEL = Struct('<I3iHHBB')
_F_RTK_VEL = Struct('<BBBII3iHHBBH')


def _pack_rtk_vel(m: RtkVel) -> bytes:
    return _S_RTK_VEL.pack(m.gps_tow_ms, *m.vel_ned_mm_s, m.h_accuracy_mm_s, m.v_accuracy_mm_s, m.num_sats, m.fix_mode)


def _unpack_rtk_vel(b: bytes) -> RtkVel:
    v = _S_RTK_VEL.unpack(b)
    return RtkVel(v[0], v[1:4], v[4], v[5], v[6], v[7])


def _from_frame_rtk_vel(v: tuple) -> RtkVel:
    return _new(RtkVel, (v[4], v[5:8], v[8], v[9], v[10], v[11]))


RTK_VEL = MessageInfo(
    id=0x43,
    name='rtk_vel',
    record=RtkVel,
    payload_size=22,
    def_hash=0xAB0D5924,
    crc_seed=0xF229,
    payload_struct=_S_RTK_VEL,
    frame_struct=_F_RTK_VEL,
    fields=(
        FieldInfo('gps_tow_ms', 'u32', 1, 'ms', 'GPS time of week of the solution'),
        FieldInfo('vel_ned_mm_s', 'i32', 3, 'mm/s', 'velocity north, east, down'),
        FieldInfo('h_accuracy_mm_s', 'u16', 1, 'mm/s', 'horizontal velocity accuracy estimate'),
        FieldInfo('v_accuracy_mm_s', 'u16', 1, 'mm/s', 'vertical velocity accuracy estimate'),
        FieldInfo('num_sats', 'u8', 1, '1', 'satellites used'),
        FieldInfo('fix_mode', 'u8', 1, 'enum', 'SBP flags bits 0-2', values={0: 'invalid', 1: 'measured_doppler', 2: 'computed_doppler', 3: 'dead_reckoning'}),
    ),
    rate_hz={'rover': 10},
    to=(),
    frozen=False,
    description='Piksi velocity, from SBP MSG_VEL_NED.',
    time="board time when the SBP frame's first byte arrived",
    pack=_pack_rtk_vel,
    unpack=_unpack_rtk_vel,
    from_frame=_from_frame_rtk_vel,
    dtype_descr=(('gps_tow_ms', '<u4'), ('vel_ned_mm_s', '<i4', (3,)), ('h_accuracy_mm_s', '<u2'), ('v_accuracy_mm_s', '<u2'), ('num_sats', 'u1'), ('fix_mode', 'u1'),),
)


class GpsTime(NamedTuple):
    """gps_time (0x44).

    Piksi GPS time, from SBP MSG_GPS_TIME: ties board clocks to GPS time.

    board_time_us: board time when the SBP frame's first byte arrived.
    """

    MSG_ID = 0x44

    gps_week: int = 0
    gps_tow_ms: int = 0
    ns_residual_ns: int = 0
    time_source: int = 0


_S_GPS_TIME = Struct('<HIiB')
_F_GPS_TIME = Struct('<BBBIHIiBH')


def _pack_gps_time(m: GpsTime) -> bytes:
    return _S_GPS_TIME.pack(m.gps_week, m.gps_tow_ms, m.ns_residual_ns, m.time_source)


def _unpack_gps_time(b: bytes) -> GpsTime:
    return GpsTime._make(_S_GPS_TIME.unpack(b))


def _from_frame_gps_time(v: tuple) -> GpsTime:
    return _new(GpsTime, v[4:-1])


GPS_TIME = MessageInfo(
    id=0x44,
    name='gps_time',
    record=GpsTime,
    payload_size=11,
    def_hash=0x8FD60FB1,
    crc_seed=0x8067,
    payload_struct=_S_GPS_TIME,
    frame_struct=_F_GPS_TIME,
    fields=(
        FieldInfo('gps_week', 'u16', 1, '1', 'GPS week number'),
        FieldInfo('gps_tow_ms', 'u32', 1, 'ms', 'GPS time of week'),
        FieldInfo('ns_residual_ns', 'i32', 1, 'ns', 'nanosecond residual of the time of week (-500000 .. 500000)'),
        FieldInfo('time_source', 'u8', 1, 'enum', 'SBP flags bits 0-2', values={0: 'none', 1: 'gnss', 2: 'propagated'}),
    ),
    rate_hz={'rover': 10, 'base': 1},
    to=(),
    frozen=False,
    description='Piksi GPS time, from SBP MSG_GPS_TIME: ties board clocks to GPS time.',
    time="board time when the SBP frame's first byte arrived",
    pack=_pack_gps_time,
    unpack=_unpack_gps_time,
    from_frame=_from_frame_gps_time,
    dtype_descr=(('gps_week', '<u2'), ('gps_tow_ms', '<u4'), ('ns_residual_ns', '<i4'), ('time_source', 'u1'),),
)


class RtkStatus(NamedTuple):
    """rtk_status (0x45).

    Health of a board's Piksi link: the SBP parser's counters and the last fix (the
    base's Piksi runs in base mode and sends corrections to the rover by radio).

    board_time_us: transmit time.
    """

    MSG_ID = 0x45

    sbp_frames_ok: int = 0
    sbp_crc_errors: int = 0
    sbp_unhandled: int = 0
    last_frame_age_ms: int = 0
    num_sats: int = 0
    fix_mode: int = 0


_S_RTK_STATUS = Struct('<IIIHBB')
_F_RTK_STATUS = Struct('<BBBIIIIHBBH')


def _pack_rtk_status(m: RtkStatus) -> bytes:
    return _S_RTK_STATUS.pack(m.sbp_frames_ok, m.sbp_crc_errors, m.sbp_unhandled, m.last_frame_age_ms, m.num_sats, m.fix_mode)


def _unpack_rtk_status(b: bytes) -> RtkStatus:
    return RtkStatus._make(_S_RTK_STATUS.unpack(b))


def _from_frame_rtk_status(v: tuple) -> RtkStatus:
    return _new(RtkStatus, v[4:-1])


RTK_STATUS = MessageInfo(
    id=0x45,
    name='rtk_status',
    record=RtkStatus,
    payload_size=16,
    def_hash=0x2F8BD6D0,
    crc_seed=0xF95B,
    payload_struct=_S_RTK_STATUS,
    frame_struct=_F_RTK_STATUS,
    fields=(
        FieldInfo('sbp_frames_ok', 'u32', 1, '1', 'SBP frames with a good CRC'),
        FieldInfo('sbp_crc_errors', 'u32', 1, '1', 'SBP frames with a bad CRC'),
        FieldInfo('sbp_unhandled', 'u32', 1, '1', 'SBP frames of message types the board does not decode'),
        FieldInfo('last_frame_age_ms', 'u16', 1, 'ms', 'time since the last good SBP frame (saturates at 65535)'),
        FieldInfo('num_sats', 'u8', 1, '1', 'satellites in the last solution'),
        FieldInfo('fix_mode', 'u8', 1, 'enum', 'fix mode of the last position solution', values={0: 'invalid', 1: 'spp', 2: 'dgnss', 3: 'float_rtk', 4: 'fixed_rtk', 5: 'dead_reckoning', 6: 'sbas'}),
    ),
    rate_hz={'rover': 1, 'base': 1},
    to=(),
    frozen=False,
    description="Health of a board's Piksi link: the SBP parser's counters and the last fix (the base's Piksi runs in base mode and sends corrections to the rover by radio).",
    time='transmit time',
    pack=_pack_rtk_status,
    unpack=_unpack_rtk_status,
    from_frame=_from_frame_rtk_status,
    dtype_descr=(('sbp_frames_ok', '<u4'), ('sbp_crc_errors', '<u4'), ('sbp_unhandled', '<u4'), ('last_frame_age_ms', '<u2'), ('num_sats', 'u1'), ('fix_mode', 'u1'),),
)


class RotorSpeed(NamedTuple):
    """rotor_speed (0x46).

    Main-rotor speed from the IR reflection interval of the two blades (TSMP6000, §5.2):
    omega = pi / interval.

    board_time_us: time of the last accepted pulse.
    """

    MSG_ID = 0x46

    rotor_speed_rad_s: float = 0.0
    pulse_interval_us: int = 0
    pulse_count: int = 0
    rejected_pulses: int = 0


_S_ROTOR_SPEED = Struct('<fIIH')
_F_ROTOR_SPEED = Struct('<BBBIfIIHH')


def _pack_rotor_speed(m: RotorSpeed) -> bytes:
    return _S_ROTOR_SPEED.pack(m.rotor_speed_rad_s, m.pulse_interval_us, m.pulse_count, m.rejected_pulses)


def _unpack_rotor_speed(b: bytes) -> RotorSpeed:
    return RotorSpeed._make(_S_ROTOR_SPEED.unpack(b))


def _from_frame_rotor_speed(v: tuple) -> RotorSpeed:
    return _new(RotorSpeed, v[4:-1])


ROTOR_SPEED = MessageInfo(
    id=0x46,
    name='rotor_speed',
    record=RotorSpeed,
    payload_size=14,
    def_hash=0x49A50297,
    crc_seed=0x4B32,
    payload_struct=_S_ROTOR_SPEED,
    frame_struct=_F_ROTOR_SPEED,
    fields=(
        FieldInfo('rotor_speed_rad_s', 'f32', 1, 'rad/s', 'main rotor speed (0 when stopped or no pulses)'),
        FieldInfo('pulse_interval_us', 'u32', 1, 'us', 'last accepted interval between blade reflections'),
        FieldInfo('pulse_count', 'u32', 1, '1', 'accepted pulses since reset'),
        FieldInfo('rejected_pulses', 'u16', 1, '1', 'pulses rejected as glitches or missed-pulse intervals since reset (wraps)'),
    ),
    rate_hz={'rover': 150},
    to=(),
    frozen=False,
    description='Main-rotor speed from the IR reflection interval of the two blades (TSMP6000, §5.2): omega = pi / interval.',
    time='time of the last accepted pulse',
    pack=_pack_rotor_speed,
    unpack=_unpack_rotor_speed,
    from_frame=_from_frame_rotor_speed,
    dtype_descr=(('rotor_speed_rad_s', '<f4'), ('pulse_interval_us', '<u4'), ('pulse_count', '<u4'), ('rejected_pulses', '<u2'),),
)


class TailServo(NamedTuple):
    """tail_servo (0x47).

    Tail-servo command pulse width from the heading-hold gyro, captured on the rover.

    board_time_us: falling edge of the last accepted pulse.
    """

    MSG_ID = 0x47

    pulse_width_us: int = 0
    valid: int = 0
    glitch_count: int = 0


_S_TAIL_SERVO = Struct('<HBH')
_F_TAIL_SERVO = Struct('<BBBIHBHH')


def _pack_tail_servo(m: TailServo) -> bytes:
    return _S_TAIL_SERVO.pack(m.pulse_width_us, m.valid, m.glitch_count)


def _unpack_tail_servo(b: bytes) -> TailServo:
    return TailServo._make(_S_TAIL_SERVO.unpack(b))


def _from_frame_tail_servo(v: tuple) -> TailServo:
    return _new(TailServo, v[4:-1])


TAIL_SERVO = MessageInfo(
    id=0x47,
    name='tail_servo',
    record=TailServo,
    payload_size=5,
    def_hash=0x2A97FA41,
    crc_seed=0xD0D6,
    payload_struct=_S_TAIL_SERVO,
    frame_struct=_F_TAIL_SERVO,
    fields=(
        FieldInfo('pulse_width_us', 'u16', 1, 'us', 'pulse width (valid range 1000-2000)'),
        FieldInfo('valid', 'u8', 1, '1', '1 when a valid pulse was seen within the last 100 ms'),
        FieldInfo('glitch_count', 'u16', 1, '1', 'rejected pulses since reset (wraps)'),
    ),
    rate_hz={'rover': 50},
    to=(),
    frozen=False,
    description='Tail-servo command pulse width from the heading-hold gyro, captured on the rover.',
    time='falling edge of the last accepted pulse',
    pack=_pack_tail_servo,
    unpack=_unpack_tail_servo,
    from_frame=_from_frame_tail_servo,
    dtype_descr=(('pulse_width_us', '<u2'), ('valid', 'u1'), ('glitch_count', '<u2'),),
)


class PilotInputs(NamedTuple):
    """pilot_inputs (0x50).

    The pilot's five RC channels measured on the base from the RC receiver's PWM outputs
    (1 aileron/lateral cyclic, 2 elevator/longitudinal cyclic, 3 collective, 4
    rudder/tail pitch, 5 aux/gyro gain).

    board_time_us: rising edge of the first pulse of this RC frame (the frame's start);
    sent when the frame is complete.
    """

    MSG_ID = 0x50

    pwm_us: tuple[int, int, int, int, int] = (0,) * 5
    valid_mask: int = 0
    glitch_count: tuple[int, int, int, int, int] = (0,) * 5


_S_PILOT_INPUTS = Struct('<5HB5H')
_F_PILOT_INPUTS = Struct('<BBBI5HB5HH')


def _pack_pilot_inputs(m: PilotInputs) -> bytes:
    return _S_PILOT_INPUTS.pack(*m.pwm_us, m.valid_mask, *m.glitch_count)


def _unpack_pilot_inputs(b: bytes) -> PilotInputs:
    v = _S_PILOT_INPUTS.unpack(b)
    return PilotInputs(v[0:5], v[5], v[6:11])


def _from_frame_pilot_inputs(v: tuple) -> PilotInputs:
    return _new(PilotInputs, (v[4:9], v[9], v[10:15]))


PILOT_INPUTS = MessageInfo(
    id=0x50,
    name='pilot_inputs',
    record=PilotInputs,
    payload_size=21,
    def_hash=0xAF7789F4,
    crc_seed=0x2683,
    payload_struct=_S_PILOT_INPUTS,
    frame_struct=_F_PILOT_INPUTS,
    fields=(
        FieldInfo('pwm_us', 'u16', 5, 'us', 'pulse width per channel 1..5 (1000-2000 when valid)'),
        FieldInfo('valid_mask', 'u8', 1, 'bits', 'bit i set when channel i+1 is valid', bits={0: 'ch1', 1: 'ch2', 2: 'ch3', 3: 'ch4', 4: 'ch5'}),
        FieldInfo('glitch_count', 'u16', 5, '1', 'rejected pulses per channel since reset (wraps)'),
    ),
    rate_hz={'base': 50},
    to=(),
    frozen=False,
    description="The pilot's five RC channels measured on the base from the RC receiver's PWM outputs (1 aileron/lateral cyclic, 2 elevator/longitudinal cyclic, 3 collective, 4 rudder/tail pitch, 5 aux/gyro gain).",
    time="rising edge of the first pulse of this RC frame (the frame's start); sent when the frame is complete",
    pack=_pack_pilot_inputs,
    unpack=_unpack_pilot_inputs,
    from_frame=_from_frame_pilot_inputs,
    dtype_descr=(('pwm_us', '<u2', (5,)), ('valid_mask', 'u1'), ('glitch_count', '<u2', (5,)),),
)


class Anemometer(NamedTuple):
    """anemometer (0x60).

    Sonic anemometer sample (Young 81000-class) in the instrument's own frame, forwarded
    by the marker board that rides with it during wind mapping (§3.4).

    board_time_us: board time when the sample's first byte arrived.
    """

    MSG_ID = 0x60

    wind_uvw_inst_m_s: tuple[float, float, float] = (0.0,) * 3
    sonic_temp_c: float = 0.0
    status: int = 0


_S_ANEMOMETER = Struct('<3ffB')
_F_ANEMOMETER = Struct('<BBBI3ffBH')


def _pack_anemometer(m: Anemometer) -> bytes:
    return _S_ANEMOMETER.pack(*m.wind_uvw_inst_m_s, m.sonic_temp_c, m.status)


def _unpack_anemometer(b: bytes) -> Anemometer:
    v = _S_ANEMOMETER.unpack(b)
    return Anemometer(v[0:3], v[3], v[4])


def _from_frame_anemometer(v: tuple) -> Anemometer:
    return _new(Anemometer, (v[4:7], v[7], v[8]))


ANEMOMETER = MessageInfo(
    id=0x60,
    name='anemometer',
    record=Anemometer,
    payload_size=17,
    def_hash=0xC95D0D8C,
    crc_seed=0xC4D1,
    payload_struct=_S_ANEMOMETER,
    frame_struct=_F_ANEMOMETER,
    fields=(
        FieldInfo('wind_uvw_inst_m_s', 'f32', 3, 'm/s', "wind u, v, w in the instrument frame, x, y, z down (Young's W, positive up, negated)"),
        FieldInfo('sonic_temp_c', 'f32', 1, 'degC', 'sonic temperature'),
        FieldInfo('status', 'u8', 1, '1', 'instrument status code (0 = ok)'),
    ),
    rate_hz={'marker': 100},
    to=(),
    frozen=False,
    description="Sonic anemometer sample (Young 81000-class) in the instrument's own frame, forwarded by the marker board that rides with it during wind mapping (§3.4).",
    time="board time when the sample's first byte arrived",
    pack=_pack_anemometer,
    unpack=_unpack_anemometer,
    from_frame=_from_frame_anemometer,
    dtype_descr=(('wind_uvw_inst_m_s', '<f4', (3,)), ('sonic_temp_c', '<f4'), ('status', 'u1'),),
)


MESSAGES: tuple[MessageInfo, ...] = (HEARTBEAT, SCHEMA_ENTRY, TIME_SYNC_REQUEST, TIME_SYNC_REPLY, LOG_TEXT, STAMP_LATENCY, IMU, LOSA_PEAKS, LOSA_RAW_LINE, LOSA_RAW_REQUEST, MARKER_ATTITUDE, MARKER_COMMAND, INS, RTK_BASELINE, RTK_POS, RTK_VEL, GPS_TIME, RTK_STATUS, ROTOR_SPEED, TAIL_SERVO, PILOT_INPUTS, ANEMOMETER)
BY_ID: dict[int, MessageInfo] = {m.id: m for m in MESSAGES}
BY_NAME: dict[str, MessageInfo] = {m.name: m for m in MESSAGES}
BY_RECORD: dict[type, MessageInfo] = {m.record: m for m in MESSAGES}
