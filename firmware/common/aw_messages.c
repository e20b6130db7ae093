/* generated from protocol/messages by protocol/codegen — do not edit */
#include "aw_messages.h"

#include "aw_frame.h"

void aw_pack_heartbeat(uint8_t *out, const aw_heartbeat_t *m)
{
    aw_put_u8(out + 0u, m->board_id);
    aw_put_u8(out + 1u, m->fw_version_major);
    aw_put_u8(out + 2u, m->fw_version_minor);
    aw_put_u8(out + 3u, m->fw_version_patch);
    aw_put_u32(out + 4u, m->schema_hash);
    aw_put_u32(out + 8u, m->uptime_ms);
    aw_put_u32(out + 12u, m->boot_count);
    aw_put_u8(out + 16u, m->reset_cause);
    aw_put_u32(out + 17u, m->frames_sent);
    aw_put_u32(out + 21u, m->bytes_sent);
    aw_put_u32(out + 25u, m->tx_bytes_dropped);
    aw_put_u32(out + 29u, m->rx_frames_ok);
    aw_put_u32(out + 33u, m->rx_crc_error);
    aw_put_u32(out + 37u, m->rx_unknown_id);
    aw_put_u32(out + 41u, m->rx_def_mismatch);
    aw_put_u32(out + 45u, m->rx_cobs_error);
    aw_put_u32(out + 49u, m->rx_oversize);
    aw_put_u32(out + 53u, m->rx_bytes_dropped);
    aw_put_u32(out + 57u, m->buffer_overruns);
    aw_put_u32(out + 61u, m->task_max_us);
}

void aw_unpack_heartbeat(aw_heartbeat_t *m, const uint8_t *in)
{
    aw_get_u8(&m->board_id, in + 0u);
    aw_get_u8(&m->fw_version_major, in + 1u);
    aw_get_u8(&m->fw_version_minor, in + 2u);
    aw_get_u8(&m->fw_version_patch, in + 3u);
    aw_get_u32(&m->schema_hash, in + 4u);
    aw_get_u32(&m->uptime_ms, in + 8u);
    aw_get_u32(&m->boot_count, in + 12u);
    aw_get_u8(&m->reset_cause, in + 16u);
    aw_get_u32(&m->frames_sent, in + 17u);
    aw_get_u32(&m->bytes_sent, in + 21u);
    aw_get_u32(&m->tx_bytes_dropped, in + 25u);
    aw_get_u32(&m->rx_frames_ok, in + 29u);
    aw_get_u32(&m->rx_crc_error, in + 33u);
    aw_get_u32(&m->rx_unknown_id, in + 37u);
    aw_get_u32(&m->rx_def_mismatch, in + 41u);
    aw_get_u32(&m->rx_cobs_error, in + 45u);
    aw_get_u32(&m->rx_oversize, in + 49u);
    aw_get_u32(&m->rx_bytes_dropped, in + 53u);
    aw_get_u32(&m->buffer_overruns, in + 57u);
    aw_get_u32(&m->task_max_us, in + 61u);
}

int aw_encode_heartbeat(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_heartbeat_t *m)
{
    uint8_t payload[AW_SIZE_HEARTBEAT];
    aw_pack_heartbeat(payload, m);
    const aw_header_t h = {AW_ID_HEARTBEAT, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_schema_entry(uint8_t *out, const aw_schema_entry_t *m)
{
    aw_put_u8(out + 0u, m->msg_id);
    aw_put_u32(out + 1u, m->def_hash);
    aw_put_u8(out + 5u, m->entry_index);
    aw_put_u8(out + 6u, m->entry_count);
}

void aw_unpack_schema_entry(aw_schema_entry_t *m, const uint8_t *in)
{
    aw_get_u8(&m->msg_id, in + 0u);
    aw_get_u32(&m->def_hash, in + 1u);
    aw_get_u8(&m->entry_index, in + 5u);
    aw_get_u8(&m->entry_count, in + 6u);
}

int aw_encode_schema_entry(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_schema_entry_t *m)
{
    uint8_t payload[AW_SIZE_SCHEMA_ENTRY];
    aw_pack_schema_entry(payload, m);
    const aw_header_t h = {AW_ID_SCHEMA_ENTRY, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_time_sync_request(uint8_t *out, const aw_time_sync_request_t *m)
{
    aw_put_u32(out + 0u, m->request_id);
    aw_put_u64(out + 4u, m->host_time_us);
}

void aw_unpack_time_sync_request(aw_time_sync_request_t *m, const uint8_t *in)
{
    aw_get_u32(&m->request_id, in + 0u);
    aw_get_u64(&m->host_time_us, in + 4u);
}

int aw_encode_time_sync_request(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_time_sync_request_t *m)
{
    uint8_t payload[AW_SIZE_TIME_SYNC_REQUEST];
    aw_pack_time_sync_request(payload, m);
    const aw_header_t h = {AW_ID_TIME_SYNC_REQUEST, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_time_sync_reply(uint8_t *out, const aw_time_sync_reply_t *m)
{
    aw_put_u32(out + 0u, m->request_id);
    aw_put_u64(out + 4u, m->host_time_us);
    aw_put_u64(out + 12u, m->board_rx_time_us);
    aw_put_u64(out + 20u, m->board_tx_time_us);
}

void aw_unpack_time_sync_reply(aw_time_sync_reply_t *m, const uint8_t *in)
{
    aw_get_u32(&m->request_id, in + 0u);
    aw_get_u64(&m->host_time_us, in + 4u);
    aw_get_u64(&m->board_rx_time_us, in + 12u);
    aw_get_u64(&m->board_tx_time_us, in + 20u);
}

int aw_encode_time_sync_reply(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_time_sync_reply_t *m)
{
    uint8_t payload[AW_SIZE_TIME_SYNC_REPLY];
    aw_pack_time_sync_reply(payload, m);
    const aw_header_t h = {AW_ID_TIME_SYNC_REPLY, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_log_text(uint8_t *out, const aw_log_text_t *m)
{
    aw_put_u8(out + 0u, m->level);
    aw_put_u16(out + 1u, m->code);
    for (size_t i = 0; i < 48u; ++i) {
        aw_put_u8(out + 3u + 1u * i, m->text_utf8[i]);
    }
}

void aw_unpack_log_text(aw_log_text_t *m, const uint8_t *in)
{
    aw_get_u8(&m->level, in + 0u);
    aw_get_u16(&m->code, in + 1u);
    for (size_t i = 0; i < 48u; ++i) {
        aw_get_u8(&m->text_utf8[i], in + 3u + 1u * i);
    }
}

int aw_encode_log_text(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_log_text_t *m)
{
    uint8_t payload[AW_SIZE_LOG_TEXT];
    aw_pack_log_text(payload, m);
    const aw_header_t h = {AW_ID_LOG_TEXT, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_stamp_latency(uint8_t *out, const aw_stamp_latency_t *m)
{
    aw_put_u8(out + 0u, m->msg_id);
    aw_put_u32(out + 1u, m->latency_us);
    aw_put_u8(out + 5u, m->stamp_event);
    aw_put_u8(out + 6u, m->entry_index);
    aw_put_u8(out + 7u, m->entry_count);
}

void aw_unpack_stamp_latency(aw_stamp_latency_t *m, const uint8_t *in)
{
    aw_get_u8(&m->msg_id, in + 0u);
    aw_get_u32(&m->latency_us, in + 1u);
    aw_get_u8(&m->stamp_event, in + 5u);
    aw_get_u8(&m->entry_index, in + 6u);
    aw_get_u8(&m->entry_count, in + 7u);
}

int aw_encode_stamp_latency(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_stamp_latency_t *m)
{
    uint8_t payload[AW_SIZE_STAMP_LATENCY];
    aw_pack_stamp_latency(payload, m);
    const aw_header_t h = {AW_ID_STAMP_LATENCY, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_imu(uint8_t *out, const aw_imu_t *m)
{
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 0u + 4u * i, m->gyro_frd_rad_s[i]);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 12u + 4u * i, m->accel_frd_m_s2[i]);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 24u + 4u * i, m->mag_frd_ut[i]);
    }
    aw_put_f32(out + 36u, m->temperature_c);
    aw_put_u8(out + 40u, m->status);
}

void aw_unpack_imu(aw_imu_t *m, const uint8_t *in)
{
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->gyro_frd_rad_s[i], in + 0u + 4u * i);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->accel_frd_m_s2[i], in + 12u + 4u * i);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->mag_frd_ut[i], in + 24u + 4u * i);
    }
    aw_get_f32(&m->temperature_c, in + 36u);
    aw_get_u8(&m->status, in + 40u);
}

int aw_encode_imu(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_imu_t *m)
{
    uint8_t payload[AW_SIZE_IMU];
    aw_pack_imu(payload, m);
    const aw_header_t h = {AW_ID_IMU, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_losa_peaks(uint8_t *out, const aw_losa_peaks_t *m)
{
    for (size_t i = 0; i < 4u; ++i) {
        aw_put_f32(out + 0u + 4u * i, m->peak_px[i]);
    }
    for (size_t i = 0; i < 4u; ++i) {
        aw_put_u16(out + 16u + 2u * i, m->intensity_counts[i]);
    }
    for (size_t i = 0; i < 4u; ++i) {
        aw_put_i8(out + 24u + 1u * i, m->slot[i]);
    }
    for (size_t i = 0; i < 4u; ++i) {
        aw_put_u16(out + 28u + 2u * i, m->exposure_us[i]);
    }
    for (size_t i = 0; i < 4u; ++i) {
        aw_put_u8(out + 36u + 1u * i, m->sensor_flags[i]);
    }
}

void aw_unpack_losa_peaks(aw_losa_peaks_t *m, const uint8_t *in)
{
    for (size_t i = 0; i < 4u; ++i) {
        aw_get_f32(&m->peak_px[i], in + 0u + 4u * i);
    }
    for (size_t i = 0; i < 4u; ++i) {
        aw_get_u16(&m->intensity_counts[i], in + 16u + 2u * i);
    }
    for (size_t i = 0; i < 4u; ++i) {
        aw_get_i8(&m->slot[i], in + 24u + 1u * i);
    }
    for (size_t i = 0; i < 4u; ++i) {
        aw_get_u16(&m->exposure_us[i], in + 28u + 2u * i);
    }
    for (size_t i = 0; i < 4u; ++i) {
        aw_get_u8(&m->sensor_flags[i], in + 36u + 1u * i);
    }
}

int aw_encode_losa_peaks(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_losa_peaks_t *m)
{
    uint8_t payload[AW_SIZE_LOSA_PEAKS];
    aw_pack_losa_peaks(payload, m);
    const aw_header_t h = {AW_ID_LOSA_PEAKS, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_losa_raw_line(uint8_t *out, const aw_losa_raw_line_t *m)
{
    aw_put_u8(out + 0u, m->sensor_index);
    aw_put_u16(out + 1u, m->exposure_us);
    for (size_t i = 0; i < 128u; ++i) {
        aw_put_u16(out + 3u + 2u * i, m->pixels_counts[i]);
    }
}

void aw_unpack_losa_raw_line(aw_losa_raw_line_t *m, const uint8_t *in)
{
    aw_get_u8(&m->sensor_index, in + 0u);
    aw_get_u16(&m->exposure_us, in + 1u);
    for (size_t i = 0; i < 128u; ++i) {
        aw_get_u16(&m->pixels_counts[i], in + 3u + 2u * i);
    }
}

int aw_encode_losa_raw_line(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_losa_raw_line_t *m)
{
    uint8_t payload[AW_SIZE_LOSA_RAW_LINE];
    aw_pack_losa_raw_line(payload, m);
    const aw_header_t h = {AW_ID_LOSA_RAW_LINE, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_losa_raw_request(uint8_t *out, const aw_losa_raw_request_t *m)
{
    aw_put_u8(out + 0u, m->sensor_mask);
    aw_put_u16(out + 1u, m->line_count);
    aw_put_u8(out + 3u, m->decimation);
}

void aw_unpack_losa_raw_request(aw_losa_raw_request_t *m, const uint8_t *in)
{
    aw_get_u8(&m->sensor_mask, in + 0u);
    aw_get_u16(&m->line_count, in + 1u);
    aw_get_u8(&m->decimation, in + 3u);
}

int aw_encode_losa_raw_request(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_losa_raw_request_t *m)
{
    uint8_t payload[AW_SIZE_LOSA_RAW_REQUEST];
    aw_pack_losa_raw_request(payload, m);
    const aw_header_t h = {AW_ID_LOSA_RAW_REQUEST, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_marker_attitude(uint8_t *out, const aw_marker_attitude_t *m)
{
    for (size_t i = 0; i < 4u; ++i) {
        aw_put_f32(out + 0u + 4u * i, m->quat_init_from_body_wxyz[i]);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 16u + 4u * i, m->gravity_frd_unit[i]);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 28u + 4u * i, m->los_frd_unit[i]);
    }
    aw_put_u8(out + 40u, m->mode);
    aw_put_u8(out + 41u, m->active_led);
    aw_put_u16(out + 42u, m->led_duty_q16);
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 44u + 4u * i, m->gyro_bias_frd_rad_s[i]);
    }
    aw_put_u16(out + 56u, m->ir_feedback_age_ms);
}

void aw_unpack_marker_attitude(aw_marker_attitude_t *m, const uint8_t *in)
{
    for (size_t i = 0; i < 4u; ++i) {
        aw_get_f32(&m->quat_init_from_body_wxyz[i], in + 0u + 4u * i);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->gravity_frd_unit[i], in + 16u + 4u * i);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->los_frd_unit[i], in + 28u + 4u * i);
    }
    aw_get_u8(&m->mode, in + 40u);
    aw_get_u8(&m->active_led, in + 41u);
    aw_get_u16(&m->led_duty_q16, in + 42u);
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->gyro_bias_frd_rad_s[i], in + 44u + 4u * i);
    }
    aw_get_u16(&m->ir_feedback_age_ms, in + 56u);
}

int aw_encode_marker_attitude(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_marker_attitude_t *m)
{
    uint8_t payload[AW_SIZE_MARKER_ATTITUDE];
    aw_pack_marker_attitude(payload, m);
    const aw_header_t h = {AW_ID_MARKER_ATTITUDE, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_marker_command(uint8_t *out, const aw_marker_command_t *m)
{
    for (size_t i = 0; i < 4u; ++i) {
        aw_put_u16(out + 0u + 2u * i, m->led_peak_counts[i]);
    }
    aw_put_u16(out + 8u, m->full_scale_counts);
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 10u + 4u * i, m->pos_tracker_m[i]);
    }
    aw_put_u8(out + 22u, m->pos_valid);
}

void aw_unpack_marker_command(aw_marker_command_t *m, const uint8_t *in)
{
    for (size_t i = 0; i < 4u; ++i) {
        aw_get_u16(&m->led_peak_counts[i], in + 0u + 2u * i);
    }
    aw_get_u16(&m->full_scale_counts, in + 8u);
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->pos_tracker_m[i], in + 10u + 4u * i);
    }
    aw_get_u8(&m->pos_valid, in + 22u);
}

int aw_encode_marker_command(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_marker_command_t *m)
{
    uint8_t payload[AW_SIZE_MARKER_COMMAND];
    aw_pack_marker_command(payload, m);
    const aw_header_t h = {AW_ID_MARKER_COMMAND, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_ins(uint8_t *out, const aw_ins_t *m)
{
    aw_put_u64(out + 0u, m->time_startup_ns);
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 8u + 4u * i, m->ypr_deg[i]);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 20u + 4u * i, m->angular_rate_frd_rad_s[i]);
    }
    aw_put_f64(out + 32u, m->lat_deg);
    aw_put_f64(out + 40u, m->lon_deg);
    aw_put_f64(out + 48u, m->alt_m);
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 56u + 4u * i, m->vel_ned_m_s[i]);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 68u + 4u * i, m->accel_frd_m_s2[i]);
    }
    aw_put_u16(out + 80u, m->ins_status);
}

void aw_unpack_ins(aw_ins_t *m, const uint8_t *in)
{
    aw_get_u64(&m->time_startup_ns, in + 0u);
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->ypr_deg[i], in + 8u + 4u * i);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->angular_rate_frd_rad_s[i], in + 20u + 4u * i);
    }
    aw_get_f64(&m->lat_deg, in + 32u);
    aw_get_f64(&m->lon_deg, in + 40u);
    aw_get_f64(&m->alt_m, in + 48u);
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->vel_ned_m_s[i], in + 56u + 4u * i);
    }
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->accel_frd_m_s2[i], in + 68u + 4u * i);
    }
    aw_get_u16(&m->ins_status, in + 80u);
}

int aw_encode_ins(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_ins_t *m)
{
    uint8_t payload[AW_SIZE_INS];
    aw_pack_ins(payload, m);
    const aw_header_t h = {AW_ID_INS, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_rtk_baseline(uint8_t *out, const aw_rtk_baseline_t *m)
{
    aw_put_u32(out + 0u, m->gps_tow_ms);
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_i32(out + 4u + 4u * i, m->baseline_ned_mm[i]);
    }
    aw_put_u16(out + 16u, m->h_accuracy_mm);
    aw_put_u16(out + 18u, m->v_accuracy_mm);
    aw_put_u8(out + 20u, m->num_sats);
    aw_put_u8(out + 21u, m->fix_mode);
}

void aw_unpack_rtk_baseline(aw_rtk_baseline_t *m, const uint8_t *in)
{
    aw_get_u32(&m->gps_tow_ms, in + 0u);
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_i32(&m->baseline_ned_mm[i], in + 4u + 4u * i);
    }
    aw_get_u16(&m->h_accuracy_mm, in + 16u);
    aw_get_u16(&m->v_accuracy_mm, in + 18u);
    aw_get_u8(&m->num_sats, in + 20u);
    aw_get_u8(&m->fix_mode, in + 21u);
}

int aw_encode_rtk_baseline(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rtk_baseline_t *m)
{
    uint8_t payload[AW_SIZE_RTK_BASELINE];
    aw_pack_rtk_baseline(payload, m);
    const aw_header_t h = {AW_ID_RTK_BASELINE, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_rtk_pos(uint8_t *out, const aw_rtk_pos_t *m)
{
    aw_put_u32(out + 0u, m->gps_tow_ms);
    aw_put_f64(out + 4u, m->lat_deg);
    aw_put_f64(out + 12u, m->lon_deg);
    aw_put_f64(out + 20u, m->height_m);
    aw_put_u16(out + 28u, m->h_accuracy_mm);
    aw_put_u16(out + 30u, m->v_accuracy_mm);
    aw_put_u8(out + 32u, m->num_sats);
    aw_put_u8(out + 33u, m->fix_mode);
}

void aw_unpack_rtk_pos(aw_rtk_pos_t *m, const uint8_t *in)
{
    aw_get_u32(&m->gps_tow_ms, in + 0u);
    aw_get_f64(&m->lat_deg, in + 4u);
    aw_get_f64(&m->lon_deg, in + 12u);
    aw_get_f64(&m->height_m, in + 20u);
    aw_get_u16(&m->h_accuracy_mm, in + 28u);
    aw_get_u16(&m->v_accuracy_mm, in + 30u);
    aw_get_u8(&m->num_sats, in + 32u);
    aw_get_u8(&m->fix_mode, in + 33u);
}

int aw_encode_rtk_pos(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rtk_pos_t *m)
{
    uint8_t payload[AW_SIZE_RTK_POS];
    aw_pack_rtk_pos(payload, m);
    const aw_header_t h = {AW_ID_RTK_POS, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_rtk_vel(uint8_t *out, const aw_rtk_vel_t *m)
{
    aw_put_u32(out + 0u, m->gps_tow_ms);
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_i32(out + 4u + 4u * i, m->vel_ned_mm_s[i]);
    }
    aw_put_u16(out + 16u, m->h_accuracy_mm_s);
    aw_put_u16(out + 18u, m->v_accuracy_mm_s);
    aw_put_u8(out + 20u, m->num_sats);
    aw_put_u8(out + 21u, m->fix_mode);
}

void aw_unpack_rtk_vel(aw_rtk_vel_t *m, const uint8_t *in)
{
    aw_get_u32(&m->gps_tow_ms, in + 0u);
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_i32(&m->vel_ned_mm_s[i], in + 4u + 4u * i);
    }
    aw_get_u16(&m->h_accuracy_mm_s, in + 16u);
    aw_get_u16(&m->v_accuracy_mm_s, in + 18u);
    aw_get_u8(&m->num_sats, in + 20u);
    aw_get_u8(&m->fix_mode, in + 21u);
}

int aw_encode_rtk_vel(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rtk_vel_t *m)
{
    uint8_t payload[AW_SIZE_RTK_VEL];
    aw_pack_rtk_vel(payload, m);
    const aw_header_t h = {AW_ID_RTK_VEL, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_gps_time(uint8_t *out, const aw_gps_time_t *m)
{
    aw_put_u16(out + 0u, m->gps_week);
    aw_put_u32(out + 2u, m->gps_tow_ms);
    aw_put_i32(out + 6u, m->ns_residual_ns);
    aw_put_u8(out + 10u, m->time_source);
}

void aw_unpack_gps_time(aw_gps_time_t *m, const uint8_t *in)
{
    aw_get_u16(&m->gps_week, in + 0u);
    aw_get_u32(&m->gps_tow_ms, in + 2u);
    aw_get_i32(&m->ns_residual_ns, in + 6u);
    aw_get_u8(&m->time_source, in + 10u);
}

int aw_encode_gps_time(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_gps_time_t *m)
{
    uint8_t payload[AW_SIZE_GPS_TIME];
    aw_pack_gps_time(payload, m);
    const aw_header_t h = {AW_ID_GPS_TIME, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_rtk_status(uint8_t *out, const aw_rtk_status_t *m)
{
    aw_put_u32(out + 0u, m->sbp_frames_ok);
    aw_put_u32(out + 4u, m->sbp_crc_errors);
    aw_put_u32(out + 8u, m->sbp_unhandled);
    aw_put_u16(out + 12u, m->last_frame_age_ms);
    aw_put_u8(out + 14u, m->num_sats);
    aw_put_u8(out + 15u, m->fix_mode);
}

void aw_unpack_rtk_status(aw_rtk_status_t *m, const uint8_t *in)
{
    aw_get_u32(&m->sbp_frames_ok, in + 0u);
    aw_get_u32(&m->sbp_crc_errors, in + 4u);
    aw_get_u32(&m->sbp_unhandled, in + 8u);
    aw_get_u16(&m->last_frame_age_ms, in + 12u);
    aw_get_u8(&m->num_sats, in + 14u);
    aw_get_u8(&m->fix_mode, in + 15u);
}

int aw_encode_rtk_status(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rtk_status_t *m)
{
    uint8_t payload[AW_SIZE_RTK_STATUS];
    aw_pack_rtk_status(payload, m);
    const aw_header_t h = {AW_ID_RTK_STATUS, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_rotor_speed(uint8_t *out, const aw_rotor_speed_t *m)
{
    aw_put_f32(out + 0u, m->rotor_speed_rad_s);
    aw_put_u32(out + 4u, m->pulse_interval_us);
    aw_put_u32(out + 8u, m->pulse_count);
    aw_put_u16(out + 12u, m->rejected_pulses);
}

void aw_unpack_rotor_speed(aw_rotor_speed_t *m, const uint8_t *in)
{
    aw_get_f32(&m->rotor_speed_rad_s, in + 0u);
    aw_get_u32(&m->pulse_interval_us, in + 4u);
    aw_get_u32(&m->pulse_count, in + 8u);
    aw_get_u16(&m->rejected_pulses, in + 12u);
}

int aw_encode_rotor_speed(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_rotor_speed_t *m)
{
    uint8_t payload[AW_SIZE_ROTOR_SPEED];
    aw_pack_rotor_speed(payload, m);
    const aw_header_t h = {AW_ID_ROTOR_SPEED, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_tail_servo(uint8_t *out, const aw_tail_servo_t *m)
{
    aw_put_u16(out + 0u, m->pulse_width_us);
    aw_put_u8(out + 2u, m->valid);
    aw_put_u16(out + 3u, m->glitch_count);
}

void aw_unpack_tail_servo(aw_tail_servo_t *m, const uint8_t *in)
{
    aw_get_u16(&m->pulse_width_us, in + 0u);
    aw_get_u8(&m->valid, in + 2u);
    aw_get_u16(&m->glitch_count, in + 3u);
}

int aw_encode_tail_servo(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_tail_servo_t *m)
{
    uint8_t payload[AW_SIZE_TAIL_SERVO];
    aw_pack_tail_servo(payload, m);
    const aw_header_t h = {AW_ID_TAIL_SERVO, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_pilot_inputs(uint8_t *out, const aw_pilot_inputs_t *m)
{
    for (size_t i = 0; i < 5u; ++i) {
        aw_put_u16(out + 0u + 2u * i, m->pwm_us[i]);
    }
    aw_put_u8(out + 10u, m->valid_mask);
    for (size_t i = 0; i < 5u; ++i) {
        aw_put_u16(out + 11u + 2u * i, m->glitch_count[i]);
    }
}

void aw_unpack_pilot_inputs(aw_pilot_inputs_t *m, const uint8_t *in)
{
    for (size_t i = 0; i < 5u; ++i) {
        aw_get_u16(&m->pwm_us[i], in + 0u + 2u * i);
    }
    aw_get_u8(&m->valid_mask, in + 10u);
    for (size_t i = 0; i < 5u; ++i) {
        aw_get_u16(&m->glitch_count[i], in + 11u + 2u * i);
    }
}

int aw_encode_pilot_inputs(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_pilot_inputs_t *m)
{
    uint8_t payload[AW_SIZE_PILOT_INPUTS];
    aw_pack_pilot_inputs(payload, m);
    const aw_header_t h = {AW_ID_PILOT_INPUTS, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

void aw_pack_anemometer(uint8_t *out, const aw_anemometer_t *m)
{
    for (size_t i = 0; i < 3u; ++i) {
        aw_put_f32(out + 0u + 4u * i, m->wind_uvw_inst_m_s[i]);
    }
    aw_put_f32(out + 12u, m->sonic_temp_c);
    aw_put_u8(out + 16u, m->status);
}

void aw_unpack_anemometer(aw_anemometer_t *m, const uint8_t *in)
{
    for (size_t i = 0; i < 3u; ++i) {
        aw_get_f32(&m->wind_uvw_inst_m_s[i], in + 0u + 4u * i);
    }
    aw_get_f32(&m->sonic_temp_c, in + 12u);
    aw_get_u8(&m->status, in + 16u);
}

int aw_encode_anemometer(uint8_t *out, size_t cap, uint8_t seq, uint8_t flags,
        uint32_t board_time_us, const aw_anemometer_t *m)
{
    uint8_t payload[AW_SIZE_ANEMOMETER];
    aw_pack_anemometer(payload, m);
    const aw_header_t h = {AW_ID_ANEMOMETER, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, sizeof payload);
}

const aw_msg_info_t aw_msg_table[AW_MSG_COUNT] = {
    {AW_ID_HEARTBEAT, AW_SIZE_HEARTBEAT, AW_SEED_HEARTBEAT, AW_HASH_HEARTBEAT, sizeof(aw_heartbeat_t), "heartbeat"},
    {AW_ID_SCHEMA_ENTRY, AW_SIZE_SCHEMA_ENTRY, AW_SEED_SCHEMA_ENTRY, AW_HASH_SCHEMA_ENTRY, sizeof(aw_schema_entry_t), "schema_entry"},
    {AW_ID_TIME_SYNC_REQUEST, AW_SIZE_TIME_SYNC_REQUEST, AW_SEED_TIME_SYNC_REQUEST, AW_HASH_TIME_SYNC_REQUEST, sizeof(aw_time_sync_request_t), "time_sync_request"},
    {AW_ID_TIME_SYNC_REPLY, AW_SIZE_TIME_SYNC_REPLY, AW_SEED_TIME_SYNC_REPLY, AW_HASH_TIME_SYNC_REPLY, sizeof(aw_time_sync_reply_t), "time_sync_reply"},
    {AW_ID_LOG_TEXT, AW_SIZE_LOG_TEXT, AW_SEED_LOG_TEXT, AW_HASH_LOG_TEXT, sizeof(aw_log_text_t), "log_text"},
    {AW_ID_STAMP_LATENCY, AW_SIZE_STAMP_LATENCY, AW_SEED_STAMP_LATENCY, AW_HASH_STAMP_LATENCY, sizeof(aw_stamp_latency_t), "stamp_latency"},
    {AW_ID_IMU, AW_SIZE_IMU, AW_SEED_IMU, AW_HASH_IMU, sizeof(aw_imu_t), "imu"},
    {AW_ID_LOSA_PEAKS, AW_SIZE_LOSA_PEAKS, AW_SEED_LOSA_PEAKS, AW_HASH_LOSA_PEAKS, sizeof(aw_losa_peaks_t), "losa_peaks"},
    {AW_ID_LOSA_RAW_LINE, AW_SIZE_LOSA_RAW_LINE, AW_SEED_LOSA_RAW_LINE, AW_HASH_LOSA_RAW_LINE, sizeof(aw_losa_raw_line_t), "losa_raw_line"},
    {AW_ID_LOSA_RAW_REQUEST, AW_SIZE_LOSA_RAW_REQUEST, AW_SEED_LOSA_RAW_REQUEST, AW_HASH_LOSA_RAW_REQUEST, sizeof(aw_losa_raw_request_t), "losa_raw_request"},
    {AW_ID_MARKER_ATTITUDE, AW_SIZE_MARKER_ATTITUDE, AW_SEED_MARKER_ATTITUDE, AW_HASH_MARKER_ATTITUDE, sizeof(aw_marker_attitude_t), "marker_attitude"},
    {AW_ID_MARKER_COMMAND, AW_SIZE_MARKER_COMMAND, AW_SEED_MARKER_COMMAND, AW_HASH_MARKER_COMMAND, sizeof(aw_marker_command_t), "marker_command"},
    {AW_ID_INS, AW_SIZE_INS, AW_SEED_INS, AW_HASH_INS, sizeof(aw_ins_t), "ins"},
    {AW_ID_RTK_BASELINE, AW_SIZE_RTK_BASELINE, AW_SEED_RTK_BASELINE, AW_HASH_RTK_BASELINE, sizeof(aw_rtk_baseline_t), "rtk_baseline"},
    {AW_ID_RTK_POS, AW_SIZE_RTK_POS, AW_SEED_RTK_POS, AW_HASH_RTK_POS, sizeof(aw_rtk_pos_t), "rtk_pos"},
    {AW_ID_RTK_VEL, AW_SIZE_RTK_VEL, AW_SEED_RTK_VEL, AW_HASH_RTK_VEL, sizeof(aw_rtk_vel_t), "rtk_vel"},
    {AW_ID_GPS_TIME, AW_SIZE_GPS_TIME, AW_SEED_GPS_TIME, AW_HASH_GPS_TIME, sizeof(aw_gps_time_t), "gps_time"},
    {AW_ID_RTK_STATUS, AW_SIZE_RTK_STATUS, AW_SEED_RTK_STATUS, AW_HASH_RTK_STATUS, sizeof(aw_rtk_status_t), "rtk_status"},
    {AW_ID_ROTOR_SPEED, AW_SIZE_ROTOR_SPEED, AW_SEED_ROTOR_SPEED, AW_HASH_ROTOR_SPEED, sizeof(aw_rotor_speed_t), "rotor_speed"},
    {AW_ID_TAIL_SERVO, AW_SIZE_TAIL_SERVO, AW_SEED_TAIL_SERVO, AW_HASH_TAIL_SERVO, sizeof(aw_tail_servo_t), "tail_servo"},
    {AW_ID_PILOT_INPUTS, AW_SIZE_PILOT_INPUTS, AW_SEED_PILOT_INPUTS, AW_HASH_PILOT_INPUTS, sizeof(aw_pilot_inputs_t), "pilot_inputs"},
    {AW_ID_ANEMOMETER, AW_SIZE_ANEMOMETER, AW_SEED_ANEMOMETER, AW_HASH_ANEMOMETER, sizeof(aw_anemometer_t), "anemometer"},
};

/* msg id -> row + 1 (0: unknown id) */
static const uint8_t aw_row_of[256] = {
    [0x01] = 1,
    [0x02] = 2,
    [0x03] = 3,
    [0x04] = 4,
    [0x05] = 5,
    [0x06] = 6,
    [0x10] = 7,
    [0x20] = 8,
    [0x21] = 9,
    [0x22] = 10,
    [0x30] = 11,
    [0x31] = 12,
    [0x40] = 13,
    [0x41] = 14,
    [0x42] = 15,
    [0x43] = 16,
    [0x44] = 17,
    [0x45] = 18,
    [0x46] = 19,
    [0x47] = 20,
    [0x50] = 21,
    [0x60] = 22,
};

int aw_msg_index(uint8_t msg_id)
{
    return (int)aw_row_of[msg_id] - 1;
}

const aw_msg_info_t *aw_msg_info(uint8_t msg_id)
{
    const int row = aw_msg_index(msg_id);
    return row < 0 ? NULL : &aw_msg_table[row];
}

int aw_pack_msg(uint8_t msg_id, uint8_t *out, size_t cap, const void *msg)
{
    const aw_msg_info_t *info = aw_msg_info(msg_id);
    if (info == NULL) {
        return AW_ERR_UNKNOWN_ID;
    }
    if (cap < info->payload_size) {
        return AW_ERR_NO_SPACE;
    }
    switch (msg_id) {
    case AW_ID_HEARTBEAT:
        aw_pack_heartbeat(out, (const aw_heartbeat_t *)msg);
        break;
    case AW_ID_SCHEMA_ENTRY:
        aw_pack_schema_entry(out, (const aw_schema_entry_t *)msg);
        break;
    case AW_ID_TIME_SYNC_REQUEST:
        aw_pack_time_sync_request(out, (const aw_time_sync_request_t *)msg);
        break;
    case AW_ID_TIME_SYNC_REPLY:
        aw_pack_time_sync_reply(out, (const aw_time_sync_reply_t *)msg);
        break;
    case AW_ID_LOG_TEXT:
        aw_pack_log_text(out, (const aw_log_text_t *)msg);
        break;
    case AW_ID_STAMP_LATENCY:
        aw_pack_stamp_latency(out, (const aw_stamp_latency_t *)msg);
        break;
    case AW_ID_IMU:
        aw_pack_imu(out, (const aw_imu_t *)msg);
        break;
    case AW_ID_LOSA_PEAKS:
        aw_pack_losa_peaks(out, (const aw_losa_peaks_t *)msg);
        break;
    case AW_ID_LOSA_RAW_LINE:
        aw_pack_losa_raw_line(out, (const aw_losa_raw_line_t *)msg);
        break;
    case AW_ID_LOSA_RAW_REQUEST:
        aw_pack_losa_raw_request(out, (const aw_losa_raw_request_t *)msg);
        break;
    case AW_ID_MARKER_ATTITUDE:
        aw_pack_marker_attitude(out, (const aw_marker_attitude_t *)msg);
        break;
    case AW_ID_MARKER_COMMAND:
        aw_pack_marker_command(out, (const aw_marker_command_t *)msg);
        break;
    case AW_ID_INS:
        aw_pack_ins(out, (const aw_ins_t *)msg);
        break;
    case AW_ID_RTK_BASELINE:
        aw_pack_rtk_baseline(out, (const aw_rtk_baseline_t *)msg);
        break;
    case AW_ID_RTK_POS:
        aw_pack_rtk_pos(out, (const aw_rtk_pos_t *)msg);
        break;
    case AW_ID_RTK_VEL:
        aw_pack_rtk_vel(out, (const aw_rtk_vel_t *)msg);
        break;
    case AW_ID_GPS_TIME:
        aw_pack_gps_time(out, (const aw_gps_time_t *)msg);
        break;
    case AW_ID_RTK_STATUS:
        aw_pack_rtk_status(out, (const aw_rtk_status_t *)msg);
        break;
    case AW_ID_ROTOR_SPEED:
        aw_pack_rotor_speed(out, (const aw_rotor_speed_t *)msg);
        break;
    case AW_ID_TAIL_SERVO:
        aw_pack_tail_servo(out, (const aw_tail_servo_t *)msg);
        break;
    case AW_ID_PILOT_INPUTS:
        aw_pack_pilot_inputs(out, (const aw_pilot_inputs_t *)msg);
        break;
    case AW_ID_ANEMOMETER:
        aw_pack_anemometer(out, (const aw_anemometer_t *)msg);
        break;
    default:
        return AW_ERR_UNKNOWN_ID;
    }
    return (int)info->payload_size;
}

int aw_unpack_msg(uint8_t msg_id, void *msg, const uint8_t *in, size_t len)
{
    const aw_msg_info_t *info = aw_msg_info(msg_id);
    if (info == NULL) {
        return AW_ERR_UNKNOWN_ID;
    }
    if (len != info->payload_size) {
        return AW_ERR_SIZE;
    }
    switch (msg_id) {
    case AW_ID_HEARTBEAT:
        aw_unpack_heartbeat((aw_heartbeat_t *)msg, in);
        break;
    case AW_ID_SCHEMA_ENTRY:
        aw_unpack_schema_entry((aw_schema_entry_t *)msg, in);
        break;
    case AW_ID_TIME_SYNC_REQUEST:
        aw_unpack_time_sync_request((aw_time_sync_request_t *)msg, in);
        break;
    case AW_ID_TIME_SYNC_REPLY:
        aw_unpack_time_sync_reply((aw_time_sync_reply_t *)msg, in);
        break;
    case AW_ID_LOG_TEXT:
        aw_unpack_log_text((aw_log_text_t *)msg, in);
        break;
    case AW_ID_STAMP_LATENCY:
        aw_unpack_stamp_latency((aw_stamp_latency_t *)msg, in);
        break;
    case AW_ID_IMU:
        aw_unpack_imu((aw_imu_t *)msg, in);
        break;
    case AW_ID_LOSA_PEAKS:
        aw_unpack_losa_peaks((aw_losa_peaks_t *)msg, in);
        break;
    case AW_ID_LOSA_RAW_LINE:
        aw_unpack_losa_raw_line((aw_losa_raw_line_t *)msg, in);
        break;
    case AW_ID_LOSA_RAW_REQUEST:
        aw_unpack_losa_raw_request((aw_losa_raw_request_t *)msg, in);
        break;
    case AW_ID_MARKER_ATTITUDE:
        aw_unpack_marker_attitude((aw_marker_attitude_t *)msg, in);
        break;
    case AW_ID_MARKER_COMMAND:
        aw_unpack_marker_command((aw_marker_command_t *)msg, in);
        break;
    case AW_ID_INS:
        aw_unpack_ins((aw_ins_t *)msg, in);
        break;
    case AW_ID_RTK_BASELINE:
        aw_unpack_rtk_baseline((aw_rtk_baseline_t *)msg, in);
        break;
    case AW_ID_RTK_POS:
        aw_unpack_rtk_pos((aw_rtk_pos_t *)msg, in);
        break;
    case AW_ID_RTK_VEL:
        aw_unpack_rtk_vel((aw_rtk_vel_t *)msg, in);
        break;
    case AW_ID_GPS_TIME:
        aw_unpack_gps_time((aw_gps_time_t *)msg, in);
        break;
    case AW_ID_RTK_STATUS:
        aw_unpack_rtk_status((aw_rtk_status_t *)msg, in);
        break;
    case AW_ID_ROTOR_SPEED:
        aw_unpack_rotor_speed((aw_rotor_speed_t *)msg, in);
        break;
    case AW_ID_TAIL_SERVO:
        aw_unpack_tail_servo((aw_tail_servo_t *)msg, in);
        break;
    case AW_ID_PILOT_INPUTS:
        aw_unpack_pilot_inputs((aw_pilot_inputs_t *)msg, in);
        break;
    case AW_ID_ANEMOMETER:
        aw_unpack_anemometer((aw_anemometer_t *)msg, in);
        break;
    default:
        return AW_ERR_UNKNOWN_ID;
    }
    return 0;
}

int aw_encode_msg(uint8_t *out, size_t cap, uint8_t msg_id, uint8_t seq, uint8_t flags,
                  uint32_t board_time_us, const void *msg)
{
    uint8_t payload[AW_MAX_PAYLOAD_SIZE];
    const int size = aw_pack_msg(msg_id, payload, sizeof payload, msg);
    if (size < 0) {
        return size;
    }
    const aw_header_t h = {msg_id, seq, flags, board_time_us};
    return aw_frame_encode(out, cap, &h, payload, (size_t)size);
}
