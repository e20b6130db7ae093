"""A small VN-200 binary output packet builder (the shared VN200 contract).

Packet: 0xFA | group byte | u16 LE field mask per group present | fields in group then
bit order, little-endian | CRC-16/XMODEM (VectorNav's CRC-16-CCITT, init 0, poly
0x1021) over everything after the sync, appended big-endian. Field sizes as listed by
VectorNav's programming library (groups 1-7; 0 = variable length or unassigned).
"""

from __future__ import annotations

import struct

SYNC = 0xFA
FIELD_SIZES = {
    1: [8, 8, 8, 12, 16, 12, 24, 12, 12, 24, 20, 28, 2, 4, 8],  # Common
    2: [8, 8, 8, 2, 8, 8, 8, 4, 4, 1, 0, 0, 0, 0, 0],  # Time
    3: [2, 12, 12, 12, 4, 4, 16, 12, 12, 12, 12, 2, 40, 0, 0],  # IMU
    4: [8, 8, 2, 1, 1, 24, 24, 12, 12, 12, 4, 4, 2, 28, 0, 0],  # GNSS (14, 15 variable)
    5: [2, 12, 16, 36, 12, 12, 12, 12, 12, 12, 28, 24, 12, 0, 0],  # Attitude
    6: [2, 24, 24, 12, 12, 12, 12, 12, 12, 4, 4, 68, 64, 0, 0],  # INS
    7: [8, 8, 2, 1, 1, 24, 24, 12, 12, 12, 4, 4, 2, 28, 0, 0],  # GNSS2
}

# The fields the firmware decodes: (group, bit) -> (name, struct format)
DECODED = {
    (1, 0): ("time_startup_ns", "<Q"),
    (2, 0): ("time_startup_ns", "<Q"),
    (1, 3): ("ypr_deg", "<3f"),
    (5, 1): ("ypr_deg", "<3f"),
    (1, 5): ("angular_rate_rad_s", "<3f"),
    (3, 10): ("angular_rate_rad_s", "<3f"),
    (1, 6): ("lla", "<3d"),
    (6, 1): ("lla", "<3d"),
    (1, 7): ("vel_ned_m_s", "<3f"),
    (6, 4): ("vel_ned_m_s", "<3f"),
    (1, 8): ("accel_m_s2", "<3f"),
    (3, 9): ("accel_m_s2", "<3f"),
    (1, 12): ("ins_status", "<H"),
    (6, 0): ("ins_status", "<H"),
}

# Our rover/base configuration: Binary Output 1, group 1, mask 0x11E9.
ROVER_MASK = 0x11E9


def crc16_xmodem(data: bytes, crc: int = 0) -> int:
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else crc << 1
            crc &= 0xFFFF
    return crc


def build_packet(fields: dict[tuple[int, int], bytes]) -> bytes:
    """fields: (group 1..7, bit) -> raw little-endian field bytes of the right size."""
    groups = sorted({g for g, _ in fields})
    body = bytearray([sum(1 << (g - 1) for g in groups)])
    for g in groups:
        body += struct.pack("<H", sum(1 << b for gg, b in fields if gg == g))
    for g, b in sorted(fields):
        assert len(fields[(g, b)]) == FIELD_SIZES[g][b], (g, b)
        body += fields[(g, b)]
    return bytes([SYNC]) + bytes(body) + struct.pack(">H", crc16_xmodem(bytes(body)))


def rover_packet(
    time_startup_ns: int,
    ypr_deg,
    angular_rate_rad_s,
    lla,
    vel_ned_m_s,
    accel_m_s2,
    ins_status: int,
) -> bytes:
    """The 88-byte packet of our configuration (mask 0x11E9)."""
    return build_packet(
        {
            (1, 0): struct.pack("<Q", time_startup_ns),
            (1, 3): struct.pack("<3f", *ypr_deg),
            (1, 5): struct.pack("<3f", *angular_rate_rad_s),
            (1, 6): struct.pack("<3d", *lla),
            (1, 7): struct.pack("<3f", *vel_ned_m_s),
            (1, 8): struct.pack("<3f", *accel_m_s2),
            (1, 12): struct.pack("<H", ins_status),
        }
    )
