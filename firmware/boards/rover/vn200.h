/* VectorNav VN-200 binary output packet parser, byte at a time.
 *
 * Packet: 0xFA sync | group byte | one u16 LE field mask per group present (group
 * order) | the fields in group then bit order, little-endian | CRC-16/XMODEM over every
 * byte after the sync, appended big-endian (so the CRC over group..CRC is 0).
 * Field sizes: the full tables of groups 1-7 (Common, Time, IMU, GNSS, Attitude, INS,
 * GNSS2) as VectorNav's programming library lists them, so fields we do not use are
 * skipped. Not supported (the packet is rejected and counted in bad_headers): the
 * variable-length GNSS SatInfo/RawMeas fields (group 4/7 bits 14-15), the extension
 * bits (group byte bit 7, mask bit 15) and empty masks.
 *
 * Decoded (present bits say which arrived in this packet):
 *   Common (1): TimeStartup b0, YawPitchRoll b3, AngularRate b5, Position b6,
 *               Velocity b7, Accel b8, InsStatus b12
 *   Time (2) TimeStartup b0; IMU (3) Accel b9, AngularRate b10; Attitude (5)
 *   YawPitchRoll b1; INS (6) InsStatus b0, PosLla b1, VelNed b4.
 * Our rover/base configuration (Binary Output 1, 150 Hz): group 0x01, mask 0x11E9,
 * 82-byte payload, 88-byte packet.
 *
 * After a bad CRC or an impossible header the parser drops the sync byte and rescans
 * the bytes it already holds for the next 0xFA, so a frame hidden in a corrupt one's
 * span is not lost.
 */
#ifndef AW_VN200_H
#define AW_VN200_H

#include <stddef.h>
#include <stdint.h>

#define VN200_SYNC 0xFAu
#define VN200_MAX_PACKET 512u
/* Our configuration's packet (group 1, mask 0x11E9): 82-byte payload + sync, group,
 * mask and CRC. */
#define VN200_PACKET_BYTES 88u
/* Binary Output 1's latency from the IMU sample instant its values describe to the
 * packet's first byte on the wire (the VN200 as we configure and model it:
 * docs/sensors.md). */
#define VN200_OUTPUT_LATENCY_US 500u
#define VN200_GROUPS 7

/* vn200_ins_t.present */
#define VN200_HAVE_TIME_STARTUP 0x01u
#define VN200_HAVE_YPR 0x02u
#define VN200_HAVE_ANGULAR_RATE 0x04u
#define VN200_HAVE_POSITION 0x08u
#define VN200_HAVE_VELOCITY 0x10u
#define VN200_HAVE_ACCEL 0x20u
#define VN200_HAVE_INS_STATUS 0x40u

typedef struct {
    uint64_t time_startup_ns;
    double lla[3];                 /* latitude deg, longitude deg, altitude m */
    float ypr_deg[3];              /* yaw, pitch, roll */
    float angular_rate_rad_s[3];   /* body */
    float vel_ned_m_s[3];
    float accel_m_s2[3];           /* body, includes gravity (z ~ -9.8 at rest) */
    uint16_t ins_status;
    uint8_t group;                 /* group byte of the packet */
    uint8_t present;               /* VN200_HAVE_* */
} vn200_ins_t;

typedef void (*vn200_handler_t)(void *ctx, const vn200_ins_t *ins);

typedef struct {
    vn200_handler_t handler;
    void *ctx;
    size_t n;
    uint32_t packets;      /* valid packets delivered */
    uint32_t crc_errors;
    uint32_t bad_headers;  /* unsupported/invalid group byte or mask */
    uint32_t oversize;     /* header asked for more than VN200_MAX_PACKET */
    uint32_t bytes_dropped; /* bytes skipped while hunting for a sync */
    uint16_t later_syncs; /* sync bytes buffered after the front one */
    uint8_t buf[VN200_MAX_PACKET];
} vn200_parser_t;

/* Size in bytes of field `bit` of group `group` (1..7); 0 when unknown/variable. */
unsigned vn200_field_size(unsigned group, unsigned bit);

void vn200_parser_init(vn200_parser_t *p, vn200_handler_t handler, void *ctx);
/* Feed received bytes; the handler runs once per valid packet, in order. */
void vn200_parser_feed(vn200_parser_t *p, const uint8_t *data, size_t len);

#endif
