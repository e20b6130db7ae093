/* generated from protocol/messages by protocol/codegen — do not edit */
/*
 * airwake wire protocol: message ids, sizes, definition hashes, CRC seeds, payload
 * structs and their explicit little-endian pack/unpack. Framing (COBS, CRC, the
 * streaming decoder) is in aw_frame.h; docs/protocol.md is the specification.
 */
#ifndef AW_MESSAGES_H
#define AW_MESSAGES_H

#include <stddef.h>
#include <stdint.h>

#include "aw_wire.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AW_SCHEMA_HASH 0xE6AFF602u
#define AW_MSG_COUNT 22u
#define AW_HEADER_SIZE 7u
#define AW_CRC_SIZE 2u
#define AW_FRAME_OVERHEAD 9u
#define AW_MAX_PAYLOAD_SIZE 259u
#define AW_MAX_RAW_FRAME_SIZE 268u
/* longest valid COBS-encoded frame (without delimiters); longer is oversize */
#define AW_MAX_ENCODED_SIZE 270u
/* longest frame on the wire: leading 0x00, COBS, trailing 0x00 */
#define AW_MAX_WIRE_SIZE 272u

/* flags byte: bits 0-2 origin board id, bits 3-7 reserved (send 0, ignore) */
#define AW_FLAGS_ORIGIN_MASK 0x07u
#define AW_BOARD_HOST 0u
#define AW_BOARD_LOSA 1u
#define AW_BOARD_MARKER 2u
#define AW_BOARD_ROVER 3u
#define AW_BOARD_BASE 4u

/* ---- heartbeat (0x01) — frozen layout ---- */
/*
 * The HELLO: who the board is, which schema it speaks and its link counters. Its layout is
 * frozen (never changes), so every receiver decodes it whatever schema either side was
 * built from; new counters go into a new message.
 */
#define AW_ID_HEARTBEAT 0x01u
#define AW_SIZE_HEARTBEAT 65u
#define AW_HASH_HEARTBEAT 0x8DE3D5E4u
#define AW_SEED_HEARTBEAT 0x5807u
#define AW_WIRE_MAX_HEARTBEAT 77u
#define AW_HEARTBEAT_BOARD_ID_HOST 0u
#define AW_HEARTBEAT_BOARD_ID_LOSA 1u
#define AW_HEARTBEAT_BOARD_ID_MARKER 2u
#define AW_HEARTBEAT_BOARD_ID_ROVER 3u
#define AW_HEARTBEAT_BOARD_ID_BASE 4u
#define AW_HEARTBEAT_RESET_CAUSE_POWER_ON 0u
#define AW_HEARTBEAT_RESET_CAUSE_WATCHDOG 1u
#define AW_HEARTBEAT_RESET_CAUSE_SOFTWARE 2u
#define AW_HEARTBEAT_RESET_CAUSE_BROWNOUT 3u
#define AW_HEARTBEAT_RESET_CAUSE_PIN 4u
#define AW_HEARTBEAT_RESET_CAUSE_UNKNOWN 255u
typedef struct {
    uint8_t board_id; /* sending board (see Board ids) */
    uint8_t fw_version_major; /* firmware version, major */
    uint8_t fw_version_minor; /* firmware version, minor */
    uint8_t fw_version_patch; /* firmware version, patch */
    uint32_t schema_hash; /* whole-schema hash the firmware was generated from (AW_SCHEMA_HASH) */
    uint32_t uptime_ms; /* time since reset (wraps after 49.7 days); also unwraps the 32-bit frame clock [ms] */
    uint32_t boot_count; /* resets since the persistent config was written */
    uint8_t reset_cause; /* why the board last reset */
    uint32_t frames_sent; /* frames queued for transmission since reset */
    uint32_t bytes_sent; /* bytes queued for transmission since reset */
    uint32_t tx_bytes_dropped; /* bytes not sent because the transmit ring buffer was full */
    uint32_t rx_frames_ok; /* frames received and decoded */
    uint32_t rx_crc_error; /* received frames failing the CRC (corrupt) */
    uint32_t rx_unknown_id; /* received frames with a message id this firmware does not know */
    uint32_t rx_def_mismatch; /* received intact frames from a different definition of the message */
    uint32_t rx_cobs_error; /* received frames that were not valid COBS or too short */
    uint32_t rx_oversize; /* received frames longer than the largest message */
    uint32_t rx_bytes_dropped; /* received bytes belonging to frames not delivered */
    uint32_t buffer_overruns; /* ring-buffer overruns of every buffer on the board (UART rx/tx, samples) */
    uint32_t task_max_us; /* longest board task iteration since the previous heartbeat [us] */
} aw_heartbeat_t;
void aw_pack_heartbeat(uint8_t *out, const aw_heartbeat_t *m);
void aw_unpack_heartbeat(aw_heartbeat_t *m, const uint8_t *in);
int aw_encode_heartbeat(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_heartbeat_t *m);

/* ---- schema_entry (0x02) — frozen layout ---- */
/*
 * One entry of the sender's schema: the definition hash of one message id it sends or
 * receives. Boards send all their entries at boot, then one entry at least every 250 ms,
 * cycling, so a receiver that joins late learns them within seconds. A receiver uses the
 * announced hash to tell an intact frame from a different definition (def_mismatch) from a
 * corrupt one (crc_error). Frozen layout.
 */
#define AW_ID_SCHEMA_ENTRY 0x02u
#define AW_SIZE_SCHEMA_ENTRY 7u
#define AW_HASH_SCHEMA_ENTRY 0xA4D7A680u
#define AW_SEED_SCHEMA_ENTRY 0x0257u
#define AW_WIRE_MAX_SCHEMA_ENTRY 19u
typedef struct {
    uint8_t msg_id; /* the message id this entry describes */
    uint32_t def_hash; /* the sender's definition hash of that message */
    uint8_t entry_index; /* index of this entry in the sender's list (0 .. entry_count-1) */
    uint8_t entry_count; /* number of entries the sender announces */
} aw_schema_entry_t;
void aw_pack_schema_entry(uint8_t *out, const aw_schema_entry_t *m);
void aw_unpack_schema_entry(aw_schema_entry_t *m, const uint8_t *in);
int aw_encode_schema_entry(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_schema_entry_t *m);

/* ---- time_sync_request (0x03) ---- */
/*
 * Host -> board clock ping (NTP-style). The board answers with time_sync_reply carrying
 * its clock at receive and at transmit; the host estimates offset and drift of each board
 * clock from the four timestamps.
 */
#define AW_ID_TIME_SYNC_REQUEST 0x03u
#define AW_SIZE_TIME_SYNC_REQUEST 12u
#define AW_HASH_TIME_SYNC_REQUEST 0x73556730u
#define AW_SEED_TIME_SYNC_REQUEST 0x1465u
#define AW_WIRE_MAX_TIME_SYNC_REQUEST 24u
typedef struct {
    uint32_t request_id; /* chosen by the host, echoed in the reply */
    uint64_t host_time_us; /* host monotonic clock when the request was written [us] */
} aw_time_sync_request_t;
void aw_pack_time_sync_request(uint8_t *out, const aw_time_sync_request_t *m);
void aw_unpack_time_sync_request(aw_time_sync_request_t *m, const uint8_t *in);
int aw_encode_time_sync_request(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_time_sync_request_t *m);

/* ---- time_sync_reply (0x04) ---- */
/*
 * Board answer to time_sync_request. offset = ((board_rx - host_tx) + (board_tx -
 * host_rx)) / 2 with host_rx the host's clock when the reply arrived. The 64-bit board
 * times also let the host unwrap the 32-bit frame clock.
 */
#define AW_ID_TIME_SYNC_REPLY 0x04u
#define AW_SIZE_TIME_SYNC_REPLY 28u
#define AW_HASH_TIME_SYNC_REPLY 0x85D4B8FAu
#define AW_SEED_TIME_SYNC_REPLY 0x3D2Eu
#define AW_WIRE_MAX_TIME_SYNC_REPLY 40u
typedef struct {
    uint32_t request_id; /* request_id of the request being answered */
    uint64_t host_time_us; /* host_time_us of the request, echoed [us] */
    uint64_t board_rx_time_us; /* board clock when the request's last byte was received [us] */
    uint64_t board_tx_time_us; /* board clock when this reply was queued [us] */
} aw_time_sync_reply_t;
void aw_pack_time_sync_reply(uint8_t *out, const aw_time_sync_reply_t *m);
void aw_unpack_time_sync_reply(aw_time_sync_reply_t *m, const uint8_t *in);
int aw_encode_time_sync_reply(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_time_sync_reply_t *m);

/* ---- log_text (0x05) ---- */
/* A short human-readable event from the board (sensor missing, mode change). */
#define AW_ID_LOG_TEXT 0x05u
#define AW_SIZE_LOG_TEXT 51u
#define AW_HASH_LOG_TEXT 0x21E4B6F8u
#define AW_SEED_LOG_TEXT 0x971Cu
#define AW_WIRE_MAX_LOG_TEXT 63u
#define AW_LOG_TEXT_LEVEL_DEBUG 0u
#define AW_LOG_TEXT_LEVEL_INFO 1u
#define AW_LOG_TEXT_LEVEL_WARNING 2u
#define AW_LOG_TEXT_LEVEL_ERROR 3u
typedef struct {
    uint8_t level; /* severity */
    uint16_t code; /* machine-readable event code, board specific */
    uint8_t text_utf8[48]; /* UTF-8 text, zero padded */
} aw_log_text_t;
void aw_pack_log_text(uint8_t *out, const aw_log_text_t *m);
void aw_unpack_log_text(aw_log_text_t *m, const uint8_t *in);
int aw_encode_log_text(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_log_text_t *m);

/* ---- stamp_latency (0x06) ---- */
/*
 * What one message's board_time_us marks and how long after the instant its data describe
 * (the sample instant) that is, as far as the sender's firmware knows it: fixed parts only
 * (a peer's documented output latency, a packet's time on a UART at the configured baud),
 * from the firmware's own constants. The host subtracts it from the mapped times when it
 * exports a flight table. A board sends one entry per message it describes after each
 * heartbeat, so a receiver that joins late learns them within a second.
 */
#define AW_ID_STAMP_LATENCY 0x06u
#define AW_SIZE_STAMP_LATENCY 8u
#define AW_HASH_STAMP_LATENCY 0x9E56D74Du
#define AW_SEED_STAMP_LATENCY 0x491Bu
#define AW_WIRE_MAX_STAMP_LATENCY 20u
#define AW_STAMP_LATENCY_STAMP_EVENT_TRANSMIT 0u
#define AW_STAMP_LATENCY_STAMP_EVENT_PEER_PACKET_END 1u
#define AW_STAMP_LATENCY_STAMP_EVENT_RC_FRAME_START 2u
#define AW_STAMP_LATENCY_STAMP_EVENT_PEER_PACKET_START 3u
typedef struct {
    uint8_t msg_id; /* the message id this entry describes */
    uint32_t latency_us; /* board_time_us of that message minus the sample instant of its data [us] */
    uint8_t stamp_event; /* what board_time_us of that message marks */
    uint8_t entry_index; /* index of this entry in the sender's list (0 .. entry_count-1) */
    uint8_t entry_count; /* number of entries the sender declares */
} aw_stamp_latency_t;
void aw_pack_stamp_latency(uint8_t *out, const aw_stamp_latency_t *m);
void aw_unpack_stamp_latency(aw_stamp_latency_t *m, const uint8_t *in);
int aw_encode_stamp_latency(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_stamp_latency_t *m);

/* ---- imu (0x10) ---- */
/*
 * Raw inertial sample of a board's IMU (LOSA and marker: MPU9250-class over SPI; rover and
 * base: the VN200's IMU when configured). The origin board is in the frame flags; axes are
 * the board's body frame, x forward, y right, z down.
 */
#define AW_ID_IMU 0x10u
#define AW_SIZE_IMU 41u
#define AW_HASH_IMU 0x9ABEA190u
#define AW_SEED_IMU 0x3B2Eu
#define AW_WIRE_MAX_IMU 53u
#define AW_IMU_STATUS_GYRO_SATURATED (1u << 0)
#define AW_IMU_STATUS_ACCEL_SATURATED (1u << 1)
#define AW_IMU_STATUS_MAG_VALID (1u << 2)
typedef struct {
    float gyro_frd_rad_s[3]; /* angular rate, body axes [rad/s] */
    float accel_frd_m_s2[3]; /* specific force, body axes (at rest z = -9.81) [m/s^2] */
    float mag_frd_ut[3]; /* magnetic field, body axes [uT] */
    float temperature_c; /* IMU die temperature [degC] */
    uint8_t status; /* sample flags */
} aw_imu_t;
void aw_pack_imu(uint8_t *out, const aw_imu_t *m);
void aw_unpack_imu(aw_imu_t *m, const uint8_t *in);
int aw_encode_imu(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_imu_t *m);

/* ---- losa_peaks (0x20) ---- */
/*
 * The LOSA tracker's per-frame result for its four TSL1401 sensors: sub-pixel peak
 * position (weighted least-squares line intersection in a +-3 pixel window, §3.3.1.5),
 * unwrapped across the three slots (peak_px = pixel on the array + 128 * slot), peak
 * intensity, slot index and the exposure the line was taken with.
 */
#define AW_ID_LOSA_PEAKS 0x20u
#define AW_SIZE_LOSA_PEAKS 40u
#define AW_HASH_LOSA_PEAKS 0x40424835u
#define AW_SEED_LOSA_PEAKS 0x0877u
#define AW_WIRE_MAX_LOSA_PEAKS 52u
#define AW_LOSA_PEAKS_SENSOR_FLAGS_VALID (1u << 0)
#define AW_LOSA_PEAKS_SENSOR_FLAGS_SATURATED (1u << 1)
#define AW_LOSA_PEAKS_SENSOR_FLAGS_SLOT_JUMP (1u << 2)
#define AW_LOSA_PEAKS_SENSOR_FLAGS_EXPOSURE_CHANGED (1u << 3)
typedef struct {
    float peak_px[4]; /* sub-pixel peak position per sensor, unwrapped across slots [px] */
    uint16_t intensity_counts[4]; /* peak pixel value per sensor (ADC counts) [counts] */
    int8_t slot[4]; /* slot the peak is attributed to per sensor: -1, 0 (centre), +1 */
    uint16_t exposure_us[4]; /* integration time of the line per sensor [us] */
    uint8_t sensor_flags[4]; /* per-sensor state */
} aw_losa_peaks_t;
void aw_pack_losa_peaks(uint8_t *out, const aw_losa_peaks_t *m);
void aw_unpack_losa_peaks(aw_losa_peaks_t *m, const uint8_t *in);
int aw_encode_losa_peaks(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_losa_peaks_t *m);

/* ---- losa_raw_line (0x21) ---- */
/*
 * One sensor's full 128-pixel line, sent only while requested by losa_raw_request
 * (diagnostics, optics calibration). Longer than 254 bytes: its COBS encoding needs a 0xFF
 * block.
 */
#define AW_ID_LOSA_RAW_LINE 0x21u
#define AW_SIZE_LOSA_RAW_LINE 259u
#define AW_HASH_LOSA_RAW_LINE 0x25A45C47u
#define AW_SEED_LOSA_RAW_LINE 0x79E3u
#define AW_WIRE_MAX_LOSA_RAW_LINE 272u
typedef struct {
    uint8_t sensor_index; /* sensor 0..3 */
    uint16_t exposure_us; /* integration time of the line [us] */
    uint16_t pixels_counts[128]; /* pixel values in array order (ADC counts) [counts] */
} aw_losa_raw_line_t;
void aw_pack_losa_raw_line(uint8_t *out, const aw_losa_raw_line_t *m);
void aw_unpack_losa_raw_line(aw_losa_raw_line_t *m, const uint8_t *in);
int aw_encode_losa_raw_line(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_losa_raw_line_t *m);

/* ---- losa_raw_request (0x22) ---- */
/* Host -> LOSA: send raw lines of the selected sensors (count 0 stops). */
#define AW_ID_LOSA_RAW_REQUEST 0x22u
#define AW_SIZE_LOSA_RAW_REQUEST 4u
#define AW_HASH_LOSA_RAW_REQUEST 0x405119ABu
#define AW_SEED_LOSA_RAW_REQUEST 0x59FAu
#define AW_WIRE_MAX_LOSA_RAW_REQUEST 16u
#define AW_LOSA_RAW_REQUEST_SENSOR_MASK_SENSOR0 (1u << 0)
#define AW_LOSA_RAW_REQUEST_SENSOR_MASK_SENSOR1 (1u << 1)
#define AW_LOSA_RAW_REQUEST_SENSOR_MASK_SENSOR2 (1u << 2)
#define AW_LOSA_RAW_REQUEST_SENSOR_MASK_SENSOR3 (1u << 3)
typedef struct {
    uint8_t sensor_mask; /* sensors to send, bit i = sensor i */
    uint16_t line_count; /* lines to send per selected sensor; 0 stops, 65535 = until stopped */
    uint8_t decimation; /* send every Nth tracker frame (0 and 1: every frame) */
} aw_losa_raw_request_t;
void aw_pack_losa_raw_request(uint8_t *out, const aw_losa_raw_request_t *m);
void aw_unpack_losa_raw_request(aw_losa_raw_request_t *m, const uint8_t *in);
int aw_encode_losa_raw_request(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_losa_raw_request_t *m);

/* ---- marker_attitude (0x30) ---- */
/*
 * The active marker's state (§3.3.1.4): integrated attitude, the tracked gravity and line-
 * of-sight vectors, mode, which LED is lit and how bright, gyro bias estimate.
 */
#define AW_ID_MARKER_ATTITUDE 0x30u
#define AW_SIZE_MARKER_ATTITUDE 58u
#define AW_HASH_MARKER_ATTITUDE 0x8FA9EE5Cu
#define AW_SEED_MARKER_ATTITUDE 0x61F5u
#define AW_WIRE_MAX_MARKER_ATTITUDE 70u
#define AW_MARKER_ATTITUDE_MODE_BOOT 0u
#define AW_MARKER_ATTITUDE_MODE_CALIBRATE_STILL 1u
#define AW_MARKER_ATTITUDE_MODE_CALIBRATE_LEDS 2u
#define AW_MARKER_ATTITUDE_MODE_TRACKING 3u
#define AW_MARKER_ATTITUDE_MODE_IR_LOST 4u
typedef struct {
    float quat_init_from_body_wxyz[4]; /* unit quaternion rotating body-frame vectors into the frame of the last calibration (w, x, y, z), eq 3.9 */
    float gravity_frd_unit[3]; /* gravity direction in the current body frame [unit vector] */
    float los_frd_unit[3]; /* line of sight to the tracker in the current body frame [unit vector] */
    uint8_t mode; /* marker state machine */
    uint8_t active_led; /* LED lit now (0..3), 255 = none */
    uint16_t led_duty_q16; /* LED drive duty cycle, 65535 = full [1/65535] */
    float gyro_bias_frd_rad_s[3]; /* current gyro bias estimate, body axes [rad/s] */
    uint16_t ir_feedback_age_ms; /* time since the last marker_command with a seen peak (saturates at 65535) [ms] */
} aw_marker_attitude_t;
void aw_pack_marker_attitude(uint8_t *out, const aw_marker_attitude_t *m);
void aw_unpack_marker_attitude(aw_marker_attitude_t *m, const uint8_t *in);
int aw_encode_marker_attitude(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_marker_attitude_t *m);

/* ---- marker_command (0x31) ---- */
/*
 * Host -> marker feedback: the peak intensity the tracker measured for each LED (the host
 * attributes a peak to the LED the marker reported lit) and the host's position estimate
 * of the marker in the tracker frame.
 */
#define AW_ID_MARKER_COMMAND 0x31u
#define AW_SIZE_MARKER_COMMAND 23u
#define AW_HASH_MARKER_COMMAND 0x2BFFD56Cu
#define AW_SEED_MARKER_COMMAND 0xFE93u
#define AW_WIRE_MAX_MARKER_COMMAND 35u
typedef struct {
    uint16_t led_peak_counts[4]; /* brightest tracker peak seen for each LED (0 = not seen) [counts] */
    uint16_t full_scale_counts; /* tracker ADC full scale (the marker holds its peak at ~20 % of it) [counts] */
    float pos_tracker_m[3]; /* marker position estimate in the tracker frame [m] */
    uint8_t pos_valid; /* 1 when pos_tracker_m is valid */
} aw_marker_command_t;
void aw_pack_marker_command(uint8_t *out, const aw_marker_command_t *m);
void aw_unpack_marker_command(aw_marker_command_t *m, const uint8_t *in);
int aw_encode_marker_command(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_marker_command_t *m);

/* ---- ins (0x40) ---- */
/*
 * VN200-class INS solution as the rover and base read it (VectorNav binary group 1:
 * TimeStartup, YawPitchRoll, AngularRate, Position, Velocity, Accel, InsStatus), forwarded
 * with the sensor's own units.
 */
#define AW_ID_INS 0x40u
#define AW_SIZE_INS 82u
#define AW_HASH_INS 0x06B84EBAu
#define AW_SEED_INS 0x4802u
#define AW_WIRE_MAX_INS 94u
#define AW_INS_INS_STATUS_GNSS_FIX (1u << 2)
#define AW_INS_INS_STATUS_IMU_ERROR (1u << 4)
#define AW_INS_INS_STATUS_MAG_PRES_ERROR (1u << 5)
#define AW_INS_INS_STATUS_GNSS_ERROR (1u << 6)
typedef struct {
    uint64_t time_startup_ns; /* VN200 time since its startup [ns] */
    float ypr_deg[3]; /* yaw, pitch, roll (3-2-1 Euler angles of body from NED) [deg] */
    float angular_rate_frd_rad_s[3]; /* angular rate, body axes (bias compensated) [rad/s] */
    double lat_deg; /* latitude, WGS84 [deg] */
    double lon_deg; /* longitude, WGS84 [deg] */
    double alt_m; /* height above the WGS84 ellipsoid [m] */
    float vel_ned_m_s[3]; /* velocity, north east down [m/s] */
    float accel_frd_m_s2[3]; /* acceleration as VN200 reports it, body axes (includes gravity: at rest z = -9.8) [m/s^2] */
    uint16_t ins_status; /* VN200 InsStatus word (bits 0-1 mode: 0 not tracking, 1 aligning, 2 tracking, 3 loss of GNSS) */
} aw_ins_t;
void aw_pack_ins(uint8_t *out, const aw_ins_t *m);
void aw_unpack_ins(aw_ins_t *m, const uint8_t *in);
int aw_encode_ins(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_ins_t *m);

/* ---- rtk_baseline (0x41) ---- */
/* Piksi RTK baseline rover minus base, from SBP MSG_BASELINE_NED. */
#define AW_ID_RTK_BASELINE 0x41u
#define AW_SIZE_RTK_BASELINE 22u
#define AW_HASH_RTK_BASELINE 0xAC79FC26u
#define AW_SEED_RTK_BASELINE 0x505Fu
#define AW_WIRE_MAX_RTK_BASELINE 34u
#define AW_RTK_BASELINE_FIX_MODE_INVALID 0u
#define AW_RTK_BASELINE_FIX_MODE_SPP 1u
#define AW_RTK_BASELINE_FIX_MODE_DGNSS 2u
#define AW_RTK_BASELINE_FIX_MODE_FLOAT_RTK 3u
#define AW_RTK_BASELINE_FIX_MODE_FIXED_RTK 4u
typedef struct {
    uint32_t gps_tow_ms; /* GPS time of week of the solution [ms] */
    int32_t baseline_ned_mm[3]; /* baseline north, east, down [mm] */
    uint16_t h_accuracy_mm; /* horizontal accuracy estimate [mm] */
    uint16_t v_accuracy_mm; /* vertical accuracy estimate [mm] */
    uint8_t num_sats; /* satellites used */
    uint8_t fix_mode; /* SBP flags bits 0-2 */
} aw_rtk_baseline_t;
void aw_pack_rtk_baseline(uint8_t *out, const aw_rtk_baseline_t *m);
void aw_unpack_rtk_baseline(aw_rtk_baseline_t *m, const uint8_t *in);
int aw_encode_rtk_baseline(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rtk_baseline_t *m);

/* ---- rtk_pos (0x42) ---- */
/* Piksi geodetic position, from SBP MSG_POS_LLH. */
#define AW_ID_RTK_POS 0x42u
#define AW_SIZE_RTK_POS 34u
#define AW_HASH_RTK_POS 0x552E6E1Du
#define AW_SEED_RTK_POS 0x3B33u
#define AW_WIRE_MAX_RTK_POS 46u
#define AW_RTK_POS_FIX_MODE_INVALID 0u
#define AW_RTK_POS_FIX_MODE_SPP 1u
#define AW_RTK_POS_FIX_MODE_DGNSS 2u
#define AW_RTK_POS_FIX_MODE_FLOAT_RTK 3u
#define AW_RTK_POS_FIX_MODE_FIXED_RTK 4u
#define AW_RTK_POS_FIX_MODE_DEAD_RECKONING 5u
#define AW_RTK_POS_FIX_MODE_SBAS 6u
typedef struct {
    uint32_t gps_tow_ms; /* GPS time of week of the solution [ms] */
    double lat_deg; /* latitude, WGS84 [deg] */
    double lon_deg; /* longitude, WGS84 [deg] */
    double height_m; /* height above the WGS84 ellipsoid [m] */
    uint16_t h_accuracy_mm; /* horizontal accuracy estimate [mm] */
    uint16_t v_accuracy_mm; /* vertical accuracy estimate [mm] */
    uint8_t num_sats; /* satellites used */
    uint8_t fix_mode; /* SBP flags bits 0-2 */
} aw_rtk_pos_t;
void aw_pack_rtk_pos(uint8_t *out, const aw_rtk_pos_t *m);
void aw_unpack_rtk_pos(aw_rtk_pos_t *m, const uint8_t *in);
int aw_encode_rtk_pos(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rtk_pos_t *m);

/* ---- rtk_vel (0x43) ---- */
/* Piksi velocity, from SBP MSG_VEL_NED. */
#define AW_ID_RTK_VEL 0x43u
#define AW_SIZE_RTK_VEL 22u
#define AW_HASH_RTK_VEL 0xAB0D5924u
#define AW_SEED_RTK_VEL 0xF229u
#define AW_WIRE_MAX_RTK_VEL 34u
#define AW_RTK_VEL_FIX_MODE_INVALID 0u
#define AW_RTK_VEL_FIX_MODE_MEASURED_DOPPLER 1u
#define AW_RTK_VEL_FIX_MODE_COMPUTED_DOPPLER 2u
#define AW_RTK_VEL_FIX_MODE_DEAD_RECKONING 3u
typedef struct {
    uint32_t gps_tow_ms; /* GPS time of week of the solution [ms] */
    int32_t vel_ned_mm_s[3]; /* velocity north, east, down [mm/s] */
    uint16_t h_accuracy_mm_s; /* horizontal velocity accuracy estimate [mm/s] */
    uint16_t v_accuracy_mm_s; /* vertical velocity accuracy estimate [mm/s] */
    uint8_t num_sats; /* satellites used */
    uint8_t fix_mode; /* SBP flags bits 0-2 */
} aw_rtk_vel_t;
void aw_pack_rtk_vel(uint8_t *out, const aw_rtk_vel_t *m);
void aw_unpack_rtk_vel(aw_rtk_vel_t *m, const uint8_t *in);
int aw_encode_rtk_vel(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rtk_vel_t *m);

/* ---- gps_time (0x44) ---- */
/* Piksi GPS time, from SBP MSG_GPS_TIME: ties board clocks to GPS time. */
#define AW_ID_GPS_TIME 0x44u
#define AW_SIZE_GPS_TIME 11u
#define AW_HASH_GPS_TIME 0x8FD60FB1u
#define AW_SEED_GPS_TIME 0x8067u
#define AW_WIRE_MAX_GPS_TIME 23u
#define AW_GPS_TIME_TIME_SOURCE_NONE 0u
#define AW_GPS_TIME_TIME_SOURCE_GNSS 1u
#define AW_GPS_TIME_TIME_SOURCE_PROPAGATED 2u
typedef struct {
    uint16_t gps_week; /* GPS week number */
    uint32_t gps_tow_ms; /* GPS time of week [ms] */
    int32_t ns_residual_ns; /* nanosecond residual of the time of week (-500000 .. 500000) [ns] */
    uint8_t time_source; /* SBP flags bits 0-2 */
} aw_gps_time_t;
void aw_pack_gps_time(uint8_t *out, const aw_gps_time_t *m);
void aw_unpack_gps_time(aw_gps_time_t *m, const uint8_t *in);
int aw_encode_gps_time(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_gps_time_t *m);

/* ---- rtk_status (0x45) ---- */
/*
 * Health of a board's Piksi link: the SBP parser's counters and the last fix (the base's
 * Piksi runs in base mode and sends corrections to the rover by radio).
 */
#define AW_ID_RTK_STATUS 0x45u
#define AW_SIZE_RTK_STATUS 16u
#define AW_HASH_RTK_STATUS 0x2F8BD6D0u
#define AW_SEED_RTK_STATUS 0xF95Bu
#define AW_WIRE_MAX_RTK_STATUS 28u
#define AW_RTK_STATUS_FIX_MODE_INVALID 0u
#define AW_RTK_STATUS_FIX_MODE_SPP 1u
#define AW_RTK_STATUS_FIX_MODE_DGNSS 2u
#define AW_RTK_STATUS_FIX_MODE_FLOAT_RTK 3u
#define AW_RTK_STATUS_FIX_MODE_FIXED_RTK 4u
#define AW_RTK_STATUS_FIX_MODE_DEAD_RECKONING 5u
#define AW_RTK_STATUS_FIX_MODE_SBAS 6u
typedef struct {
    uint32_t sbp_frames_ok; /* SBP frames with a good CRC */
    uint32_t sbp_crc_errors; /* SBP frames with a bad CRC */
    uint32_t sbp_unhandled; /* SBP frames of message types the board does not decode */
    uint16_t last_frame_age_ms; /* time since the last good SBP frame (saturates at 65535) [ms] */
    uint8_t num_sats; /* satellites in the last solution */
    uint8_t fix_mode; /* fix mode of the last position solution */
} aw_rtk_status_t;
void aw_pack_rtk_status(uint8_t *out, const aw_rtk_status_t *m);
void aw_unpack_rtk_status(aw_rtk_status_t *m, const uint8_t *in);
int aw_encode_rtk_status(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rtk_status_t *m);

/* ---- rotor_speed (0x46) ---- */
/*
 * Main-rotor speed from the IR reflection interval of the two blades (TSMP6000, §5.2):
 * omega = pi / interval.
 */
#define AW_ID_ROTOR_SPEED 0x46u
#define AW_SIZE_ROTOR_SPEED 14u
#define AW_HASH_ROTOR_SPEED 0x49A50297u
#define AW_SEED_ROTOR_SPEED 0x4B32u
#define AW_WIRE_MAX_ROTOR_SPEED 26u
typedef struct {
    float rotor_speed_rad_s; /* main rotor speed (0 when stopped or no pulses) [rad/s] */
    uint32_t pulse_interval_us; /* last accepted interval between blade reflections [us] */
    uint32_t pulse_count; /* accepted pulses since reset */
    uint16_t rejected_pulses; /* pulses rejected as glitches or missed-pulse intervals since reset (wraps) */
} aw_rotor_speed_t;
void aw_pack_rotor_speed(uint8_t *out, const aw_rotor_speed_t *m);
void aw_unpack_rotor_speed(aw_rotor_speed_t *m, const uint8_t *in);
int aw_encode_rotor_speed(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rotor_speed_t *m);

/* ---- tail_servo (0x47) ---- */
/* Tail-servo command pulse width from the heading-hold gyro, captured on the rover. */
#define AW_ID_TAIL_SERVO 0x47u
#define AW_SIZE_TAIL_SERVO 5u
#define AW_HASH_TAIL_SERVO 0x2A97FA41u
#define AW_SEED_TAIL_SERVO 0xD0D6u
#define AW_WIRE_MAX_TAIL_SERVO 17u
typedef struct {
    uint16_t pulse_width_us; /* pulse width (valid range 1000-2000) [us] */
    uint8_t valid; /* 1 when a valid pulse was seen within the last 100 ms */
    uint16_t glitch_count; /* rejected pulses since reset (wraps) */
} aw_tail_servo_t;
void aw_pack_tail_servo(uint8_t *out, const aw_tail_servo_t *m);
void aw_unpack_tail_servo(aw_tail_servo_t *m, const uint8_t *in);
int aw_encode_tail_servo(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_tail_servo_t *m);

/* ---- pilot_inputs (0x50) ---- */
/*
 * The pilot's five RC channels measured on the base from the RC receiver's PWM outputs (1
 * aileron/lateral cyclic, 2 elevator/longitudinal cyclic, 3 collective, 4 rudder/tail
 * pitch, 5 aux/gyro gain).
 */
#define AW_ID_PILOT_INPUTS 0x50u
#define AW_SIZE_PILOT_INPUTS 21u
#define AW_HASH_PILOT_INPUTS 0xAF7789F4u
#define AW_SEED_PILOT_INPUTS 0x2683u
#define AW_WIRE_MAX_PILOT_INPUTS 33u
#define AW_PILOT_INPUTS_VALID_MASK_CH1 (1u << 0)
#define AW_PILOT_INPUTS_VALID_MASK_CH2 (1u << 1)
#define AW_PILOT_INPUTS_VALID_MASK_CH3 (1u << 2)
#define AW_PILOT_INPUTS_VALID_MASK_CH4 (1u << 3)
#define AW_PILOT_INPUTS_VALID_MASK_CH5 (1u << 4)
typedef struct {
    uint16_t pwm_us[5]; /* pulse width per channel 1..5 (1000-2000 when valid) [us] */
    uint8_t valid_mask; /* bit i set when channel i+1 is valid */
    uint16_t glitch_count[5]; /* rejected pulses per channel since reset (wraps) */
} aw_pilot_inputs_t;
void aw_pack_pilot_inputs(uint8_t *out, const aw_pilot_inputs_t *m);
void aw_unpack_pilot_inputs(aw_pilot_inputs_t *m, const uint8_t *in);
int aw_encode_pilot_inputs(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_pilot_inputs_t *m);

/* ---- anemometer (0x60) ---- */
/*
 * Sonic anemometer sample (Young 81000-class) in the instrument's own frame, forwarded by
 * the marker board that rides with it during wind mapping (§3.4).
 */
#define AW_ID_ANEMOMETER 0x60u
#define AW_SIZE_ANEMOMETER 17u
#define AW_HASH_ANEMOMETER 0xC95D0D8Cu
#define AW_SEED_ANEMOMETER 0xC4D1u
#define AW_WIRE_MAX_ANEMOMETER 29u
typedef struct {
    float wind_uvw_inst_m_s[3]; /* wind u, v, w in the instrument frame, x, y, z down (Young's W, positive up, negated) [m/s] */
    float sonic_temp_c; /* sonic temperature [degC] */
    uint8_t status; /* instrument status code (0 = ok) */
} aw_anemometer_t;
void aw_pack_anemometer(uint8_t *out, const aw_anemometer_t *m);
void aw_unpack_anemometer(aw_anemometer_t *m, const uint8_t *in);
int aw_encode_anemometer(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_anemometer_t *m);

/* One row per message, in id order: what a decoder needs. */
typedef struct {
    uint8_t id;
    uint16_t payload_size;
    uint16_t crc_seed;
    uint32_t def_hash;
    uint16_t struct_size; /* sizeof(aw_<name>_t) */
    const char *name;
} aw_msg_info_t;

extern const aw_msg_info_t aw_msg_table[AW_MSG_COUNT];

/* Row index of msg_id in aw_msg_table, or -1 when the id is unknown. */
int aw_msg_index(uint8_t msg_id);
/* Row of msg_id, or NULL when the id is unknown. */
const aw_msg_info_t *aw_msg_info(uint8_t msg_id);

/* Storage for any message struct (decoded by id). */
typedef union {
    aw_heartbeat_t heartbeat;
    aw_schema_entry_t schema_entry;
    aw_time_sync_request_t time_sync_request;
    aw_time_sync_reply_t time_sync_reply;
    aw_log_text_t log_text;
    aw_stamp_latency_t stamp_latency;
    aw_imu_t imu;
    aw_losa_peaks_t losa_peaks;
    aw_losa_raw_line_t losa_raw_line;
    aw_losa_raw_request_t losa_raw_request;
    aw_marker_attitude_t marker_attitude;
    aw_marker_command_t marker_command;
    aw_ins_t ins;
    aw_rtk_baseline_t rtk_baseline;
    aw_rtk_pos_t rtk_pos;
    aw_rtk_vel_t rtk_vel;
    aw_gps_time_t gps_time;
    aw_rtk_status_t rtk_status;
    aw_rotor_speed_t rotor_speed;
    aw_tail_servo_t tail_servo;
    aw_pilot_inputs_t pilot_inputs;
    aw_anemometer_t anemometer;
} aw_any_msg_t;

/* Dispatch by id. `msg` points to the aw_<name>_t of that id. Return the payload
 * size / frame length, or AW_ERR_UNKNOWN_ID, AW_ERR_NO_SPACE, AW_ERR_SIZE. */
int aw_pack_msg(uint8_t msg_id, uint8_t *out, size_t cap, const void *msg);
int aw_unpack_msg(uint8_t msg_id, void *msg, const uint8_t *in, size_t len);
int aw_encode_msg(uint8_t *out, size_t cap, uint8_t msg_id, uint8_t seq, uint8_t flags,
                  uint32_t board_time_us, const void *msg);

#ifdef __cplusplus
}
#endif

#endif /* AW_MESSAGES_H */
