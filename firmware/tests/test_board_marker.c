/* test_board_marker.c — the marker wiring on the fake HAL: IMU at 450 Hz into the
 * marker logic, attitude + IMU frames at 120 Hz, one LED lit, host feedback in. */
#include <math.h>

#include "test_board_util.h"

static test_frames_t out;

static unsigned lit_leds(void)
{
    unsigned n = 0;
    for (unsigned i = 0; i < HAL_PWM_COUNT; i++) {
        n += fake.pwm[i] != 0;
    }
    return n;
}

/* 120 Hz attitude + IMU, and never two LEDs at once (the tracker would see two peaks). */
static int test_marker_sends_attitude_and_imu_at_120_hz_with_one_led_lit(void)
{
    const hal_t *hal = fake_hal_init();
    const float gyro[3] = {0.0f, 0.0f, 0.0f};
    const float accel[3] = {0.0f, 0.0f, -9.81f};
    const float mag[3] = {20.0f, 0.0f, 40.0f};
    fake_imu_sample(gyro, accel, mag);
    board_init(hal);
    test_frames_init(&out);
    uint64_t t0 = fake.now_us;
    unsigned max_lit = 0;
    while (fake.now_us < t0 + 1000000u) {
        fake_imu_sample(gyro, accel, mag); /* the chip samples at 1 kHz */
        test_run_until(hal, fake.now_us + 1000u);
        unsigned lit = lit_leds();
        max_lit = lit > max_lit ? lit : max_lit;
    }
    test_frames_take(&out, HAL_PORT_HOST);
    size_t att = test_count(&out, AW_ID_MARKER_ATTITUDE);
    size_t imu = test_count(&out, AW_ID_IMU);
    CHECK(att >= 119 && att <= 121);
    CHECK(imu == att);
    CHECK(max_lit == 1); /* the calibration sweep lights one LED at a time */
    CHECK(marker_board.imu_k >= 449 && marker_board.imu_k <= 451);
    aw_marker_attitude_t a;
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id == AW_ID_MARKER_ATTITUDE) {
            aw_unpack_msg(AW_ID_MARKER_ATTITUDE, &a, out.f[i].payload, out.f[i].len);
        }
    }
    CHECK(a.mode == AW_MARKER_ATTITUDE_MODE_CALIBRATE_LEDS); /* first 5 s */
    CHECK(a.active_led < 4);
    return 0;
}

/* Host feedback reaches the marker logic: after calibration the marker tracks. */
static int test_marker_uses_host_feedback_to_finish_calibration(void)
{
    const hal_t *hal = fake_hal_init();
    const float gyro[3] = {0.0f, 0.0f, 0.0f};
    const float accel[3] = {0.0f, 0.0f, -9.81f};
    const float mag[3] = {20.0f, 0.0f, 40.0f};
    fake_imu_sample(gyro, accel, mag);
    board_init(hal);
    test_frames_init(&out);
    uint64_t t0 = fake.now_us;
    while (fake.now_us < t0 + 6000000u) {
        fake_imu_sample(gyro, accel, mag);
        if ((fake.now_us - t0) % 20000u < 1000u) { /* 50 Hz feedback: LED 0 seen at 20 % */
            aw_marker_command_t cmd = {.led_peak_counts = {819, 0, 0, 0},
                                       .full_scale_counts = 4095};
            test_feed_msg(HAL_PORT_HOST, AW_ID_MARKER_COMMAND, &cmd);
        }
        test_run_until(hal, fake.now_us + 1000u);
    }
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(marker_board.commands >= 290);
    aw_marker_attitude_t a;
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id == AW_ID_MARKER_ATTITUDE) {
            aw_unpack_msg(AW_ID_MARKER_ATTITUDE, &a, out.f[i].payload, out.f[i].len);
        }
    }
    CHECK(a.mode == AW_MARKER_ATTITUDE_MODE_TRACKING);
    CHECK(fabsf(a.gravity_frd_unit[2] - 1.0f) < 1e-3f); /* gravity points down the body z */
    CHECK(a.active_led == 0 && lit_leds() == 1 && fake.pwm[0] > 0);
    return 0;
}

/* The carried anemometer: each ASCII line becomes one anemometer frame, stamped with the
 * board time its first byte was read, z down; the stamp latency is declared. */
static int test_marker_forwards_anemometer_lines(void)
{
    const hal_t *hal = fake_hal_init();
    const float gyro[3] = {0.0f, 0.0f, 0.0f};
    const float accel[3] = {0.0f, 0.0f, -9.81f};
    const float mag[3] = {20.0f, 0.0f, 40.0f};
    fake_imu_sample(gyro, accel, mag);
    fake_map_port(HAL_PORT_ANEMO, true);
    board_init(hal);
    test_frames_init(&out);
    test_run_until(hal, fake.now_us + 1500000u); /* past the first heartbeat */
    test_frames_take(&out, HAL_PORT_HOST);
    test_frames_init(&out);
    uint64_t first = 0;
    for (int k = 0; k < 10; k++) {
        char line[48];
        int n = snprintf(line, sizeof(line), "%7.2f %7.2f %7.2f %7.2f\r\n", 0.5 * k, -1.0,
                         0.25, 20.0);
        uint64_t t = fake.now_us;
        if (k == 0) {
            first = t;
        }
        fake_uart_feed(HAL_PORT_ANEMO, (const uint8_t *)line, 1); /* first byte alone */
        test_run_until(hal, t + 300u);
        fake_uart_feed(HAL_PORT_ANEMO, (const uint8_t *)line + 1, (size_t)n - 1);
        test_run_until(hal, t + 10000u);
    }
    fake_uart_feed(HAL_PORT_ANEMO, (const uint8_t *)"garbage\x01\r\n", 10);
    test_run_until(hal, fake.now_us + 1100000u);
    test_frames_take(&out, HAL_PORT_HOST);
    int fails = 0;
    size_t got = 0;
    bool declared = false;
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id == AW_ID_ANEMOMETER) {
            aw_anemometer_t a;
            aw_unpack_msg(AW_ID_ANEMOMETER, &a, out.f[i].payload, out.f[i].len);
            fails += fabsf(a.wind_uvw_inst_m_s[0] - 0.5f * (float)got) > 1e-5f;
            fails += fabsf(a.wind_uvw_inst_m_s[2] + 0.25f) > 1e-6f;
            fails += a.status != 0u;
            /* stamped when the first byte was read, not when the line completed */
            fails += out.f[i].h.board_time_us != (uint32_t)(first + 10000u * got);
            got++;
        }
        if (out.f[i].h.msg_id == AW_ID_STAMP_LATENCY) {
            aw_stamp_latency_t e;
            aw_unpack_msg(AW_ID_STAMP_LATENCY, &e, out.f[i].payload, out.f[i].len);
            declared |= e.msg_id == AW_ID_ANEMOMETER && e.latency_us == YOUNG_STAMP_LATENCY_US;
        }
    }
    CHECK(got == 10);
    CHECK(fails == 0);
    CHECK(declared);
    CHECK(marker_board.anemo.lines_bad == 1u);
    return 0;
}

int main(void)
{
    int fails = 0;
    fails += test_marker_sends_attitude_and_imu_at_120_hz_with_one_led_lit();
    fails += test_marker_uses_host_feedback_to_finish_calibration();
    fails += test_marker_forwards_anemometer_lines();
    if (fails) {
        fprintf(stderr, "test_board_marker: %d failed\n", fails);
        return 1;
    }
    printf("test_board_marker: ok\n");
    return 0;
}
