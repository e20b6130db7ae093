/* test_board_base.c — the base wiring on the fake HAL: the rover's frames forwarded
 * to the host byte for byte between the base's own, RC PWM -> pilot_inputs. */
#include "test_board_util.h"

static test_frames_t out;
static uint8_t rover_stream[200000];
static uint8_t host_stream[FAKE_TX_CAP];

static bool contains(const uint8_t *hay, size_t n, const uint8_t *needle, size_t m)
{
    for (size_t i = 0; i + m <= n; i++) {
        if (hay[i] == needle[0] && memcmp(&hay[i], needle, m) == 0) {
            return true;
        }
    }
    return false;
}

/* The host must get the rover's frames exactly as the rover sent them (origin,
 * sequence, CRC), whatever chunks the XBee delivers them in. */
static int test_base_forwards_rover_frames_byte_exact(void)
{
    const hal_t *hal = fake_hal_init();
    fake_map_port(HAL_PORT_ROVER, true);
    board_init(hal);
    /* 300 rover frames of three kinds, as the rover's board_link would send them */
    size_t len = 0;
    size_t starts[300], lens[300];
    for (unsigned i = 0; i < 300; i++) {
        uint8_t wire[AW_MAX_WIRE_SIZE];
        int n;
        if (i % 3 == 0) {
            aw_ins_t m = {.time_startup_ns = i * 1000u, .ypr_deg = {(float)i, 0.0f, 0.0f},
                          .lat_deg = 47.0, .ins_status = 2};
            n = aw_encode_msg(wire, sizeof(wire), AW_ID_INS, (uint8_t)i, AW_BOARD_ROVER, i * 100u, &m);
        } else if (i % 3 == 1) {
            aw_rotor_speed_t m = {.rotor_speed_rad_s = 150.0f, .pulse_count = i};
            n = aw_encode_msg(wire, sizeof(wire), AW_ID_ROTOR_SPEED, (uint8_t)i, AW_BOARD_ROVER,
                              i * 100u, &m);
        } else {
            aw_rtk_baseline_t m = {.gps_tow_ms = i, .baseline_ned_mm = {1, 0, -2}};
            n = aw_encode_msg(wire, sizeof(wire), AW_ID_RTK_BASELINE, (uint8_t)i, AW_BOARD_ROVER,
                              i * 100u, &m);
        }
        CHECK(n > 0);
        memcpy(&rover_stream[len], wire, (size_t)n);
        starts[i] = len;
        lens[i] = (size_t)n;
        len += (size_t)n;
    }
    /* deliver in uneven chunks while the base runs (and sends its own frames) */
    size_t pos = 0;
    uint32_t x = 7u;
    while (pos < len) {
        x = x * 1103515245u + 12345u;
        size_t chunk = 1u + (x >> 16) % 97u;
        if (chunk > len - pos) {
            chunk = len - pos;
        }
        fake_uart_feed(HAL_PORT_ROVER, &rover_stream[pos], chunk);
        pos += chunk;
        test_run_until(hal, fake.now_us + 700u);
    }
    test_run_until(hal, fake.now_us + 1100000u);
    size_t host_len = fake_uart_take(HAL_PORT_HOST, host_stream, sizeof(host_stream));
    for (unsigned i = 0; i < 300; i++) {
        CHECK(contains(host_stream, host_len, &rover_stream[starts[i]], lens[i]));
    }
    test_frames_init(&out);
    aw_decoder_feed(&out.dec, host_stream, host_len);
    size_t from_rover = 0, from_base = 0;
    for (size_t i = 0; i < out.n; i++) {
        uint8_t origin = out.f[i].h.flags & AW_FLAGS_ORIGIN_MASK;
        if (origin == AW_BOARD_ROVER) {
            CHECK(out.f[i].h.seq == (uint8_t)from_rover); /* in order, none lost */
            from_rover++;
        } else {
            CHECK(origin == AW_BOARD_BASE);
            from_base++;
        }
    }
    CHECK(from_rover == 300);
    CHECK(from_base > 50); /* its own pilot inputs, heartbeat, schema, status */
    CHECK(out.dec.counters.crc_error == 0 && out.dec.counters.cobs_error == 0);
    CHECK(base_board.fwd.segments == 300 && base_board.fwd.dropped_bytes == 0);
    return 0;
}

/* A corrupt rover frame is the host's to count: passed on, and the next one intact. */
static int test_base_passes_corrupt_rover_frames_on_and_keeps_the_next(void)
{
    const hal_t *hal = fake_hal_init();
    fake_map_port(HAL_PORT_ROVER, true);
    board_init(hal);
    uint8_t a[AW_MAX_WIRE_SIZE], c[AW_MAX_WIRE_SIZE];
    aw_tail_servo_t m = {.pulse_width_us = 1500, .valid = 1};
    int na = aw_encode_msg(a, sizeof(a), AW_ID_TAIL_SERVO, 1, AW_BOARD_ROVER, 10u, &m);
    int nc = aw_encode_msg(c, sizeof(c), AW_ID_TAIL_SERVO, 2, AW_BOARD_ROVER, 20u, &m);
    a[4] ^= 0x40u; /* a bit flip on the radio link */
    fake_uart_feed(HAL_PORT_ROVER, a, (size_t)na);
    fake_uart_feed(HAL_PORT_ROVER, c, (size_t)nc);
    test_run_until(hal, fake.now_us + 30000u);
    size_t host_len = fake_uart_take(HAL_PORT_HOST, host_stream, sizeof(host_stream));
    CHECK(contains(host_stream, host_len, a, (size_t)na));
    CHECK(contains(host_stream, host_len, c, (size_t)nc));
    test_frames_init(&out);
    aw_decoder_feed(&out.dec, host_stream, host_len);
    CHECK(out.dec.counters.crc_error == 1);
    size_t rover_ok = 0;
    for (size_t i = 0; i < out.n; i++) {
        rover_ok += (out.f[i].h.flags & AW_FLAGS_ORIGIN_MASK) == AW_BOARD_ROVER;
    }
    CHECK(rover_ok == 1);
    return 0;
}

static void pulse(hal_capture_t ch, uint32_t rise_us, uint32_t width_us)
{
    fake_capture_push(ch, rise_us, 1);
    fake_capture_push(ch, rise_us + width_us, 0);
}

/* The pilot's sticks: five channels measured from edges, sent at 50 Hz. */
static int test_base_measures_five_rc_channels_into_pilot_inputs(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    const uint32_t width[5] = {1100, 1300, 1500, 1700, 1900};
    uint64_t t = fake.now_us;
    for (int frame = 0; frame < 50; frame++) { /* 1 s of a 50 Hz receiver */
        test_run_until(hal, t + 20000u);
        /* the edges of this 20 ms frame, queued as the capture interrupt would */
        for (int c = 0; c < 5; c++) {
            pulse((hal_capture_t)(HAL_CAPTURE_RC1 + c), (uint32_t)t + 2500u * (uint32_t)c, width[c]);
        }
        t += 20000u;
    }
    test_run_until(hal, t + 1000u);
    test_frames_take(&out, HAL_PORT_HOST);
    size_t n = test_count(&out, AW_ID_PILOT_INPUTS);
    CHECK(n >= 49 && n <= 51);
    aw_pilot_inputs_t last = {0};
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id == AW_ID_PILOT_INPUTS) {
            aw_unpack_msg(AW_ID_PILOT_INPUTS, &last, out.f[i].payload, out.f[i].len);
        }
    }
    CHECK(last.valid_mask == 0x1F);
    for (int c = 0; c < 5; c++) {
        CHECK(last.pwm_us[c] == width[c]);
        CHECK(last.glitch_count[c] == 0);
    }
    return 0;
}

/* The rover's clock can only be mapped if host time-sync requests reach it. */
static int test_base_relays_host_bytes_to_the_rover_unchanged(void)
{
    const hal_t *hal = fake_hal_init();
    fake_map_port(HAL_PORT_ROVER, true);
    board_init(hal);
    test_run_until(hal, fake.now_us + 10000u);
    fake_uart_take(HAL_PORT_ROVER, host_stream, sizeof(host_stream));
    uint8_t wire[AW_MAX_WIRE_SIZE];
    aw_time_sync_request_t req = {.request_id = 5, .host_time_us = 99};
    int n = aw_encode_msg(wire, sizeof(wire), AW_ID_TIME_SYNC_REQUEST, 0, AW_BOARD_HOST, 0, &req);
    CHECK(n > 0);
    fake_uart_feed(HAL_PORT_HOST, wire, (size_t)n);
    test_run_until(hal, fake.now_us + 10000u);
    size_t got = fake_uart_take(HAL_PORT_ROVER, host_stream, sizeof(host_stream));
    CHECK(got == (size_t)n && memcmp(host_stream, wire, (size_t)n) == 0);
    /* and the base answers it itself on the host port */
    test_frames_init(&out);
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(test_count(&out, AW_ID_TIME_SYNC_REPLY) == 1);
    return 0;
}

int main(void)
{
    int fails = 0;
    fails += test_base_forwards_rover_frames_byte_exact();
    fails += test_base_passes_corrupt_rover_frames_on_and_keeps_the_next();
    fails += test_base_measures_five_rc_channels_into_pilot_inputs();
    fails += test_base_relays_host_bytes_to_the_rover_unchanged();
    if (fails) {
        fprintf(stderr, "test_board_base: %d failed\n", fails);
        return 1;
    }
    printf("test_board_base: ok\n");
    return 0;
}
