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

/* The pilot's sticks: five channels measured from edges, one frame per RC frame. */
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

/* Runs the board to an edge's instant and queues the edge there, as the capture
 * interrupt would. */
static void edge_at(const hal_t *hal, hal_capture_t ch, uint64_t t_us, uint8_t level)
{
    test_run_until(hal, t_us);
    fake_capture_push(ch, (uint32_t)t_us, level);
}

/* One RC frame from `start`: the five channels back to back (a sequential receiver),
 * channel `skip` (0..4, or 5 for none) missing its pulse. */
static void rc_frame(const hal_t *hal, uint64_t start, const uint32_t width[5], int skip)
{
    uint64_t t = start;
    for (int c = 0; c < 5; c++) {
        if (c != skip) {
            edge_at(hal, (hal_capture_t)(HAL_CAPTURE_RC1 + c), t, 1);
            edge_at(hal, (hal_capture_t)(HAL_CAPTURE_RC1 + c), t + width[c], 0);
        }
        t += width[c];
    }
}

/* The pilot_inputs frames stamped `t_us` in what was taken from the host port. */
static size_t pilot_at(const test_frames_t *t, uint32_t t_us, aw_pilot_inputs_t *m)
{
    size_t n = 0;
    for (size_t i = 0; i < t->n; i++) {
        if (t->f[i].h.msg_id == AW_ID_PILOT_INPUTS && t->f[i].h.board_time_us == t_us) {
            aw_unpack_msg(AW_ID_PILOT_INPUTS, m, t->f[i].payload, t->f[i].len);
            n++;
        }
    }
    return n;
}

/* The analysis lines pilot inputs up with the INS by their stamps: a frame stamped at a
 * 50 Hz tick of the board's clock would lag its commands by the phase between the tick
 * and the receiver's frame (0-20 ms, drifting), so each frame is stamped at its start and
 * sent as soon as its last pulse is in, whatever the receiver's frame rate (47 Hz here). */
static int test_base_stamps_each_rc_frame_at_its_first_rising_edge(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    const uint32_t width[5] = {1100, 1300, 1500, 1700, 1900};
    const uint64_t period = 21277u, t0 = fake.now_us + 3700u;
    for (int k = 0; k < 47; k++) {
        uint64_t start = t0 + (uint64_t)k * period;
        if (k == 10) {
            /* not sent before the frame's last pulse has ended */
            uint64_t last_fall = start + 1100u + 1300u + 1500u + 1700u + 1900u;
            rc_frame(hal, start, width, 5);
            test_run_until(hal, last_fall - 1u);
            test_frames_take(&out, HAL_PORT_HOST);
            aw_pilot_inputs_t m;
            CHECK(pilot_at(&out, (uint32_t)start, &m) == 0);
            continue;
        }
        rc_frame(hal, start, width, 5);
    }
    test_run_until(hal, t0 + 47u * period);
    test_frames_take(&out, HAL_PORT_HOST);
    for (int k = 2; k < 47; k++) { /* frames 0 and 1 are gathered while channels appear */
        aw_pilot_inputs_t m = {0};
        CHECK(pilot_at(&out, (uint32_t)(t0 + (uint64_t)k * period), &m) == 1);
        CHECK(m.valid_mask == 0x1F);
        for (int c = 0; c < 5; c++) {
            CHECK(m.pwm_us[c] == width[c]);
        }
    }
    CHECK(test_count(&out, AW_ID_PILOT_INPUTS) <= 47u + 2u);
    return 0;
}

/* A channel that misses its pulse must not hold the frame back (nor merge two frames):
 * the frame goes out 3/4 of a period after its start with that channel's last width. */
static int test_base_sends_a_frame_whose_channel_missed_its_pulse(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    const uint32_t width[5] = {1500, 1500, 1500, 1500, 1700};
    const uint32_t moved[5] = {1600, 1600, 1200, 1600, 1700};
    const uint64_t period = 20000u, t0 = fake.now_us + 1000u;
    for (int k = 0; k < 8; k++) {
        rc_frame(hal, t0 + (uint64_t)k * period, k < 5 ? width : moved, k == 5 ? 2 : 5);
    }
    test_run_until(hal, t0 + 8u * period);
    test_frames_take(&out, HAL_PORT_HOST);
    aw_pilot_inputs_t m = {0};
    CHECK(pilot_at(&out, (uint32_t)(t0 + 5u * period), &m) == 1);
    CHECK(m.pwm_us[0] == 1600 && m.pwm_us[2] == 1500 && m.valid_mask == 0x1F);
    CHECK(pilot_at(&out, (uint32_t)(t0 + 6u * period), &m) == 1);
    CHECK(m.pwm_us[2] == 1500); /* a 300 us jump waits for its confirmation */
    CHECK(pilot_at(&out, (uint32_t)(t0 + 7u * period), &m) == 1);
    CHECK(m.pwm_us[2] == 1200);
    return 0;
}

/* With the receiver off the host still hears from the pilot-input stream (every channel
 * invalid), at the nominal 50 Hz. */
static int test_base_keeps_pilot_inputs_alive_without_a_receiver(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    test_run_until(hal, fake.now_us + 1000000u);
    test_frames_take(&out, HAL_PORT_HOST);
    size_t n = 0;
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id == AW_ID_PILOT_INPUTS) {
            aw_pilot_inputs_t m;
            aw_unpack_msg(AW_ID_PILOT_INPUTS, &m, out.f[i].payload, out.f[i].len);
            CHECK(m.valid_mask == 0);
            n++;
        }
    }
    CHECK(n >= 46 && n <= 51);
    return 0;
}

/* The host removes what the board declares from each stream's times; a board that
 * declared nothing (or wrong numbers) would leave a known delay in every flight table. */
static int test_base_declares_its_stamp_latencies_after_each_heartbeat(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    test_run_until(hal, fake.now_us + 2500000u);
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(test_count(&out, AW_ID_HEARTBEAT) == 3);
    CHECK(test_count(&out, AW_ID_STAMP_LATENCY) == 6);
    bool ins = false, pilot = false;
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id != AW_ID_STAMP_LATENCY) {
            continue;
        }
        aw_stamp_latency_t e;
        CHECK(aw_unpack_msg(AW_ID_STAMP_LATENCY, &e, out.f[i].payload, out.f[i].len) >= 0);
        CHECK(e.entry_count == 2);
        if (e.msg_id == AW_ID_INS) {
            /* VN200 output latency 500 us + 88 bytes at 921600 baud (954.9 us) */
            CHECK(e.latency_us == 1455u && e.stamp_event == AW_STAMP_LATENCY_STAMP_EVENT_PEER_PACKET_END);
            ins = true;
        } else if (e.msg_id == AW_ID_PILOT_INPUTS) {
            CHECK(e.latency_us == 0u && e.stamp_event == AW_STAMP_LATENCY_STAMP_EVENT_RC_FRAME_START);
            pilot = true;
        }
    }
    CHECK(ins && pilot);
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
    fails += test_base_stamps_each_rc_frame_at_its_first_rising_edge();
    fails += test_base_sends_a_frame_whose_channel_missed_its_pulse();
    fails += test_base_keeps_pilot_inputs_alive_without_a_receiver();
    fails += test_base_declares_its_stamp_latencies_after_each_heartbeat();
    if (fails) {
        fprintf(stderr, "test_board_base: %d failed\n", fails);
        return 1;
    }
    printf("test_board_base: ok\n");
    return 0;
}
