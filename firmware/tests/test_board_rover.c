/* test_board_rover.c — the rover wiring on the fake HAL: VN200 packets -> ins frames,
 * SBP -> rtk frames, rotor IR edges -> rotor_speed, tail-servo edges -> tail_servo. */
#include <math.h>

#include "crc16_xmodem.h"
#include "test_board_util.h"

static test_frames_t out;

static size_t put(uint8_t *b, size_t i, const void *v, size_t n)
{
    memcpy(&b[i], v, n);
    return i + n;
}

/* The rover/base VN200 configuration: group 1, mask 0x11E9 (see vn200.h). */
static size_t vn200_packet(uint8_t *b, uint64_t t_ns, float yaw_deg, double lat_deg)
{
    size_t i = 0;
    b[i++] = 0xFA;
    b[i++] = 0x01;
    b[i++] = 0xE9;
    b[i++] = 0x11;
    const float ypr[3] = {yaw_deg, 2.0f, -3.0f};
    const float rate[3] = {0.1f, -0.2f, 0.3f};
    const double lla[3] = {lat_deg, -122.5, 12.0};
    const float vel[3] = {1.0f, 2.0f, -0.5f};
    const float acc[3] = {0.0f, 0.1f, -9.8f};
    const uint16_t status = 0x0002;
    i = put(b, i, &t_ns, 8);
    i = put(b, i, ypr, 12);
    i = put(b, i, rate, 12);
    i = put(b, i, lla, 24);
    i = put(b, i, vel, 12);
    i = put(b, i, acc, 12);
    i = put(b, i, &status, 2);
    uint16_t crc = crc16_xmodem(&b[1], i - 1);
    b[i++] = (uint8_t)(crc >> 8);
    b[i++] = (uint8_t)crc;
    return i;
}

/* libsbp framing: 0x55, type, sender, len, payload, CRC-16/XMODEM (LE) over type..payload */
static size_t sbp_frame(uint8_t *b, uint16_t type, const uint8_t *payload, uint8_t len)
{
    size_t i = 0;
    b[i++] = 0x55;
    b[i++] = (uint8_t)type;
    b[i++] = (uint8_t)(type >> 8);
    b[i++] = 0x42;
    b[i++] = 0x00;
    b[i++] = len;
    i = put(b, i, payload, len);
    uint16_t crc = crc16_xmodem(&b[1], i - 1);
    b[i++] = (uint8_t)crc;
    b[i++] = (uint8_t)(crc >> 8);
    return i;
}

/* The INS is the helicopter's state: every packet must become one ins frame, values intact. */
static int test_rover_turns_each_vn200_packet_into_an_ins_frame(void)
{
    const hal_t *hal = fake_hal_init();
    fake_map_port(HAL_PORT_INS, true);
    board_init(hal);
    test_frames_init(&out);
    for (unsigned k = 0; k < 150; k++) { /* 1 s at 150 Hz */
        uint8_t pkt[128];
        size_t n = vn200_packet(pkt, 1000000ull * k, (float)k, 47.0 + 1e-7 * k);
        fake_uart_feed(HAL_PORT_INS, pkt, n);
        test_run_until(hal, fake.now_us + 6667u);
    }
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(test_count(&out, AW_ID_INS) == 150);
    unsigned k = 0;
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id != AW_ID_INS) {
            continue;
        }
        aw_ins_t m;
        aw_unpack_msg(AW_ID_INS, &m, out.f[i].payload, out.f[i].len);
        CHECK(m.time_startup_ns == 1000000ull * k);
        CHECK(m.ypr_deg[0] == (float)k && m.ypr_deg[2] == -3.0f);
        CHECK(m.lat_deg == 47.0 + 1e-7 * k && m.lon_deg == -122.5);
        CHECK(m.accel_frd_m_s2[2] == -9.8f && m.ins_status == 2);
        k++;
    }
    return 0;
}

/* An ins frame is stamped when its packet's last byte is parsed: the host must learn
 * from the rover how long after the sample that is, or every INS row is late by it. */
static int test_rover_declares_the_ins_stamp_latency_from_its_constants(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    test_run_until(hal, fake.now_us + 1500000u);
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(test_count(&out, AW_ID_STAMP_LATENCY) == 2); /* one per heartbeat */
    for (size_t i = 0; i < out.n; i++) {
        if (out.f[i].h.msg_id == AW_ID_STAMP_LATENCY) {
            aw_stamp_latency_t e;
            aw_unpack_msg(AW_ID_STAMP_LATENCY, &e, out.f[i].payload, out.f[i].len);
            CHECK(e.msg_id == AW_ID_INS && e.entry_index == 0 && e.entry_count == 1);
            CHECK(e.latency_us == NAV_INS_STAMP_LATENCY_US && e.latency_us == 1455u);
            CHECK(e.stamp_event == AW_STAMP_LATENCY_STAMP_EVENT_PEER_PACKET_END);
        }
    }
    return 0;
}

/* The RTK baseline is the helicopter's position relative to the ship. */
static int test_rover_forwards_sbp_baseline_as_rtk_baseline(void)
{
    const hal_t *hal = fake_hal_init();
    fake_map_port(HAL_PORT_RTK, true);
    board_init(hal);
    test_frames_init(&out);
    /* MSG_BASELINE_NED: tow u32, n e d i32, h_acc v_acc u16, n_sats u8, flags u8 */
    uint8_t p[22];
    uint32_t tow = 345600000u;
    int32_t ned[3] = {12345, -678, -900};
    uint16_t acc[2] = {10, 20};
    size_t i = put(p, 0, &tow, 4);
    i = put(p, i, ned, 12);
    i = put(p, i, acc, 4);
    p[i++] = 14;
    p[i++] = 4; /* fixed RTK */
    uint8_t frame[64];
    size_t n = sbp_frame(frame, 0x020C, p, (uint8_t)i);
    fake_uart_feed(HAL_PORT_RTK, frame, n);
    test_run_until(hal, fake.now_us + 1100000u);
    test_frames_take(&out, HAL_PORT_HOST);
    CHECK(test_count(&out, AW_ID_RTK_BASELINE) == 1);
    CHECK(test_count(&out, AW_ID_RTK_STATUS) == 1);
    for (size_t k = 0; k < out.n; k++) {
        if (out.f[k].h.msg_id == AW_ID_RTK_BASELINE) {
            aw_rtk_baseline_t m;
            aw_unpack_msg(AW_ID_RTK_BASELINE, &m, out.f[k].payload, out.f[k].len);
            CHECK(m.gps_tow_ms == tow && m.baseline_ned_mm[0] == 12345 &&
                  m.baseline_ned_mm[2] == -900);
            CHECK(m.num_sats == 14 && m.fix_mode == AW_RTK_BASELINE_FIX_MODE_FIXED_RTK);
        }
        if (out.f[k].h.msg_id == AW_ID_RTK_STATUS) {
            aw_rtk_status_t s;
            aw_unpack_msg(AW_ID_RTK_STATUS, &s, out.f[k].payload, out.f[k].len);
            CHECK(s.sbp_frames_ok == 1 && s.sbp_crc_errors == 0);
        }
    }
    return 0;
}

/* Rotor speed from the two blades' reflections: Omega = pi / interval. */
static int test_rover_measures_rotor_speed_and_tail_servo_from_edges(void)
{
    const hal_t *hal = fake_hal_init();
    board_init(hal);
    test_frames_init(&out);
    const uint32_t half_rev_us = 10000u; /* 314.16 rad/s (3000 rpm) */
    uint64_t t = fake.now_us;
    for (int k = 0; k < 100; k++) {
        test_run_until(hal, t + half_rev_us);
        fake_capture_push(HAL_CAPTURE_ROTOR_IR, (uint32_t)t + 100u, 1);
        fake_capture_push(HAL_CAPTURE_ROTOR_IR, (uint32_t)t + 180u, 0);
        if (k % 2 == 0) { /* 50 Hz tail-servo pulses of 1520 us */
            fake_capture_push(HAL_CAPTURE_TAIL_SERVO, (uint32_t)t + 500u, 1);
            fake_capture_push(HAL_CAPTURE_TAIL_SERVO, (uint32_t)t + 2020u, 0);
        }
        t += half_rev_us;
    }
    test_run_until(hal, t + 1000u);
    test_frames_take(&out, HAL_PORT_HOST);
    size_t n = test_count(&out, AW_ID_ROTOR_SPEED);
    CHECK(n >= 149 && n <= 152); /* 150 Hz over ~1 s */
    aw_rotor_speed_t r = {0};
    aw_tail_servo_t ts = {0};
    for (size_t k = 0; k < out.n; k++) {
        if (out.f[k].h.msg_id == AW_ID_ROTOR_SPEED) {
            aw_unpack_msg(AW_ID_ROTOR_SPEED, &r, out.f[k].payload, out.f[k].len);
        }
        if (out.f[k].h.msg_id == AW_ID_TAIL_SERVO) {
            aw_unpack_msg(AW_ID_TAIL_SERVO, &ts, out.f[k].payload, out.f[k].len);
        }
    }
    CHECK(fabsf(r.rotor_speed_rad_s - 314.159f) < 0.5f);
    CHECK(r.pulse_interval_us == half_rev_us);
    CHECK(ts.valid == 1 && ts.pulse_width_us == 1520);
    return 0;
}

int main(void)
{
    int fails = 0;
    fails += test_rover_turns_each_vn200_packet_into_an_ins_frame();
    fails += test_rover_forwards_sbp_baseline_as_rtk_baseline();
    fails += test_rover_measures_rotor_speed_and_tail_servo_from_edges();
    fails += test_rover_declares_the_ins_stamp_latency_from_its_constants();
    if (fails) {
        fprintf(stderr, "test_board_rover: %d failed\n", fails);
        return 1;
    }
    printf("test_board_rover: ok\n");
    return 0;
}
