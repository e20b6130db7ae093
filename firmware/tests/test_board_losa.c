/* test_board_losa.c — the LOSA wiring on the fake HAL: TSL1401 readout -> F2's frame
 * processing -> losa_peaks frames, raw lines on request, link housekeeping. */
#include <math.h>

#include "test_board_util.h"

static test_frames_t out;

static void put_peak(unsigned sensor, double centre_px, double height)
{
    for (unsigned i = 0; i < 128; i++) {
        double d = ((double)i - centre_px) / 1.6;
        fake.scene[sensor][i] = (uint16_t)lround(60.0 + height * exp(-0.5 * d * d));
    }
}

/* The host triangulates from these frames: rate, positions and time stamps must hold. */
static int test_losa_sends_peaks_at_320_hz_at_the_right_positions(void)
{
    const hal_t *hal = fake_hal_init();
    const double truth[4] = {20.3, 47.75, 64.0, 101.6};
    for (unsigned s = 0; s < 4; s++) {
        put_peak(s, truth[s], 1500.0);
    }
    board_init(hal);
    test_frames_init(&out);
    uint64_t t0 = fake.now_us;
    test_run_until(hal, t0 + 1000000u);
    test_frames_take(&out, HAL_PORT_HOST);

    size_t peaks = test_count(&out, AW_ID_LOSA_PEAKS);
    CHECK(peaks >= 319 && peaks <= 321);
    uint32_t prev_t = 0;
    uint8_t prev_seq = 0;
    size_t k = 0;
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id != AW_ID_LOSA_PEAKS) {
            continue;
        }
        aw_losa_peaks_t m;
        CHECK(aw_unpack_msg(AW_ID_LOSA_PEAKS, &m, out.f[i].payload, out.f[i].len) >= 0);
        for (unsigned s = 0; s < 4; s++) {
            CHECK(m.sensor_flags[s] & AW_LOSA_PEAKS_SENSOR_FLAGS_VALID);
            CHECK(fabs(m.peak_px[s] - truth[s]) < 0.1);
            CHECK(m.slot[s] == 0);
            CHECK(m.intensity_counts[s] > 1400 && m.intensity_counts[s] < 1600);
        }
        if (k > 0) {
            CHECK(out.f[i].h.board_time_us - prev_t == LOSA_FRAME_PERIOD_US);
            CHECK((uint8_t)(out.f[i].h.seq - prev_seq) == 1);
        }
        CHECK((out.f[i].h.flags & AW_FLAGS_ORIGIN_MASK) == AW_BOARD_LOSA);
        prev_t = out.f[i].h.board_time_us;
        prev_seq = out.f[i].h.seq;
        k++;
    }
    CHECK(fake.tsl_violations == 0);
    CHECK(out.dec.counters.crc_error == 0 && out.dec.counters.cobs_error == 0);
    return 0;
}

/* The exposure the board reports must be the integration time it really used. */
static int test_losa_reports_the_flush_to_read_exposure(void)
{
    const hal_t *hal = fake_hal_init();
    put_peak(0, 64.0, 1500.0);
    board_init(hal);
    test_frames_init(&out);
    test_run_until(hal, fake.now_us + 100000u);
    test_frames_take(&out, HAL_PORT_HOST);
    size_t seen = 0;
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id == AW_ID_LOSA_PEAKS) {
            aw_losa_peaks_t m;
            aw_unpack_msg(AW_ID_LOSA_PEAKS, &m, out.f[i].payload, out.f[i].len);
            CHECK(m.exposure_us[0] == LOSA_INITIAL_EXPOSURE_US); /* in band: held */
            seen++;
        }
    }
    CHECK(seen > 25);
    /* two SI latches per frame (flush + read) plus the one at init */
    CHECK(fake.si_latches == 1u + 2u * seen);
    return 0;
}

/* Raw lines are the optics-calibration tool: exactly the sensors and count asked for. */
static int test_losa_sends_exactly_the_raw_lines_requested(void)
{
    const hal_t *hal = fake_hal_init();
    for (unsigned s = 0; s < 4; s++) {
        put_peak(s, 30.0 + 20.0 * s, 1000.0);
    }
    board_init(hal);
    test_frames_init(&out);
    test_run_until(hal, fake.now_us + 20000u);
    aw_losa_raw_request_t req = {.sensor_mask = 0x05, .line_count = 3, .decimation = 2};
    test_feed_msg(HAL_PORT_HOST, AW_ID_LOSA_RAW_REQUEST, &req);
    test_run_until(hal, fake.now_us + 200000u);
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(test_count(&out, AW_ID_LOSA_RAW_LINE) == 6);
    unsigned per_sensor[4] = {0};
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id != AW_ID_LOSA_RAW_LINE) {
            continue;
        }
        static aw_losa_raw_line_t m;
        aw_unpack_msg(AW_ID_LOSA_RAW_LINE, &m, out.f[i].payload, out.f[i].len);
        CHECK(m.sensor_index == 0 || m.sensor_index == 2);
        per_sensor[m.sensor_index]++;
        CHECK(memcmp(m.pixels_counts, fake.scene[m.sensor_index], sizeof(m.pixels_counts)) == 0);
    }
    CHECK(per_sensor[0] == 3 && per_sensor[2] == 3);
    return 0;
}

/* A late joiner must learn the schema and see counters: HELLO + entries at boot. */
static int test_losa_announces_heartbeat_and_full_schema_at_boot(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    test_run_until(hal, fake.now_us + 2100000u);
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(out.f[0].h.msg_id == AW_ID_HEARTBEAT);
    CHECK(test_count(&out, AW_ID_HEARTBEAT) == 3); /* t = 0, 1 s, 2 s */
    size_t entries = test_count(&out, AW_ID_SCHEMA_ENTRY);
    CHECK(entries >= 8 + 7); /* all at boot, then one per 250 ms */
    aw_heartbeat_t hb;
    aw_unpack_msg(AW_ID_HEARTBEAT, &hb, out.f[0].payload, out.f[0].len);
    CHECK(hb.board_id == AW_BOARD_LOSA && hb.schema_hash == AW_SCHEMA_HASH);
    CHECK(fake.watchdog_started && fake.watchdog_refreshes > 600);
    return 0;
}

/* A time-sync request is answered with the board clock at receive and transmit. */
static int test_losa_answers_time_sync_with_its_clock(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    test_run_until(hal, fake.now_us + 50000u);
    fake_uart_take(HAL_PORT_HOST, (uint8_t[4096]){0}, 4096);
    aw_time_sync_request_t req = {.request_id = 77, .host_time_us = 123456789u};
    uint64_t sent_at = fake.now_us;
    test_feed_msg(HAL_PORT_HOST, AW_ID_TIME_SYNC_REQUEST, &req);
    test_run_until(hal, fake.now_us + 10000u);
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(test_count(&out, AW_ID_TIME_SYNC_REPLY) == 1);
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id == AW_ID_TIME_SYNC_REPLY) {
            aw_time_sync_reply_t r;
            aw_unpack_msg(AW_ID_TIME_SYNC_REPLY, &r, out.f[i].payload, out.f[i].len);
            CHECK(r.request_id == 77 && r.host_time_us == 123456789u);
            CHECK(r.board_rx_time_us >= sent_at && r.board_tx_time_us >= r.board_rx_time_us);
            CHECK(r.board_tx_time_us - sent_at < 10000u);
        }
    }
    return 0;
}

int main(void)
{
    int fails = 0;
    fails += test_losa_sends_peaks_at_320_hz_at_the_right_positions();
    fails += test_losa_reports_the_flush_to_read_exposure();
    fails += test_losa_sends_exactly_the_raw_lines_requested();
    fails += test_losa_announces_heartbeat_and_full_schema_at_boot();
    fails += test_losa_answers_time_sync_with_its_clock();
    if (fails) {
        fprintf(stderr, "test_board_losa: %d failed\n", fails);
        return 1;
    }
    printf("test_board_losa: ok\n");
    return 0;
}
