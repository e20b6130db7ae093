/* Swift Binary Protocol (Piksi RTK) frame parser, byte at a time.
 *
 * Frame: 0x55 | msg_type u16 | sender u16 | length u8 | payload | CRC-16/XMODEM over
 * msg_type..payload, little-endian. Every field little-endian.
 * Decoded payloads (libsbp layouts): MSG_BASELINE_NED 0x020C, MSG_POS_LLH 0x020A,
 * MSG_VEL_NED 0x020E, MSG_GPS_TIME 0x0102 (what the rover forwards) and
 * MSG_BASELINE_ECEF 0x020B, MSG_DOPS 0x0208, MSG_UTC_TIME 0x0103, MSG_IMU_RAW 0x0900.
 * Any other type is framed, CRC-checked, counted (`undecoded`) and handed over with
 * decoded = 0; so is a known type whose length does not match (`bad_length`).
 * After a bad CRC the parser rescans the bytes after the false preamble; a later frame
 * completed inside a false start's claimed length is delivered at once. Type 0 (a
 * preamble followed by zeros passes the CRC) is refused as a false start.
 */
#ifndef AW_SBP_H
#define AW_SBP_H

#include <stddef.h>
#include <stdint.h>

#define SBP_PREAMBLE 0x55u
#define SBP_MAX_FRAME (6u + 255u + 2u)

#define SBP_MSG_GPS_TIME 0x0102u
#define SBP_MSG_UTC_TIME 0x0103u
#define SBP_MSG_DOPS 0x0208u
#define SBP_MSG_POS_LLH 0x020Au
#define SBP_MSG_BASELINE_ECEF 0x020Bu
#define SBP_MSG_BASELINE_NED 0x020Cu
#define SBP_MSG_VEL_NED 0x020Eu
#define SBP_MSG_IMU_RAW 0x0900u

typedef struct {
    uint32_t tow;         /* GPS time of week, ms */
    int32_t n, e, d;      /* mm */
    uint16_t h_accuracy, v_accuracy; /* mm */
    uint8_t n_sats, flags; /* flags & 7: 0 invalid, 1 SPP, 2 DGNSS, 3 float, 4 fixed RTK */
} sbp_baseline_ned_t;

typedef struct {
    uint32_t tow;
    double lat, lon, height; /* deg, deg, m */
    uint16_t h_accuracy, v_accuracy;
    uint8_t n_sats, flags;
} sbp_pos_llh_t;

typedef struct {
    uint32_t tow;
    int32_t n, e, d; /* mm/s */
    uint16_t h_accuracy, v_accuracy;
    uint8_t n_sats, flags;
} sbp_vel_ned_t;

typedef struct {
    uint16_t wn;
    uint32_t tow;         /* ms */
    int32_t ns_residual;
    uint8_t flags;
} sbp_gps_time_t;

typedef struct {
    uint32_t tow;
    int32_t x, y, z; /* mm */
    uint16_t accuracy;
    uint8_t n_sats, flags;
} sbp_baseline_ecef_t;

typedef struct {
    uint32_t tow;
    uint16_t gdop, pdop, tdop, hdop, vdop; /* 0.01 */
    uint8_t flags;
} sbp_dops_t;

typedef struct {
    uint8_t flags;
    uint32_t tow;
    uint16_t year;
    uint8_t month, day, hours, minutes, seconds;
    uint32_t ns;
} sbp_utc_time_t;

typedef struct {
    uint32_t tow;
    uint8_t tow_f;
    int16_t acc_x, acc_y, acc_z, gyr_x, gyr_y, gyr_z;
} sbp_imu_raw_t;

typedef struct {
    uint16_t msg_type;
    uint16_t sender;
    uint8_t length;
    uint8_t decoded; /* 1: the member of `m` for msg_type is filled */
    union {
        sbp_baseline_ned_t baseline_ned;
        sbp_pos_llh_t pos_llh;
        sbp_vel_ned_t vel_ned;
        sbp_gps_time_t gps_time;
        sbp_baseline_ecef_t baseline_ecef;
        sbp_dops_t dops;
        sbp_utc_time_t utc_time;
        sbp_imu_raw_t imu_raw;
    } m;
    const uint8_t *payload; /* raw payload, valid during the handler call only */
} sbp_msg_t;

typedef void (*sbp_handler_t)(void *ctx, const sbp_msg_t *msg);

typedef struct {
    sbp_handler_t handler;
    void *ctx;
    size_t n;
    uint32_t frames;        /* CRC-valid frames delivered */
    uint32_t crc_errors;
    uint32_t undecoded;     /* valid frames of types we do not decode */
    uint32_t bad_length;    /* known type, unexpected payload length */
    uint32_t bytes_dropped;
    uint16_t later_syncs; /* sync bytes buffered after the front one */
    uint8_t buf[SBP_MAX_FRAME];
} sbp_parser_t;

void sbp_parser_init(sbp_parser_t *p, sbp_handler_t handler, void *ctx);
void sbp_parser_feed(sbp_parser_t *p, const uint8_t *data, size_t len);

/* Decode a payload of a known type into msg->m; returns 1 on success (also sets
 * msg->decoded), 0 for other types or lengths. */
int sbp_decode_payload(uint16_t msg_type, const uint8_t *payload, uint8_t len, sbp_msg_t *msg);

#endif
