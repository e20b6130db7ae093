/* VN-200 binary packet parser: framing, CRC, resync, field tables. */
#include <stdint.h>
#include <string.h>

#include "rover/crc16_xmodem.h"
#include "rover/vn200.h"
#include "test_algos.h"

typedef struct {
    vn200_ins_t last;
    int count;
} sink_t;

static void on_ins(void *ctx, const vn200_ins_t *ins)
{
    sink_t *s = ctx;
    s->last = *ins;
    s->count++;
}

static size_t put(uint8_t *b, size_t i, const void *v, size_t n)
{
    memcpy(b + i, v, n); /* little-endian host (x86-64, Cortex-M4) */
    return i + n;
}

/* Our configuration: group 1, mask 0x11E9, 82-byte payload. */
static size_t build_common_packet(uint8_t *b, uint64_t t_ns, float yaw)
{
    size_t i = 0;
    b[i++] = 0xFA;
    b[i++] = 0x01;
    b[i++] = 0xE9;
    b[i++] = 0x11;
    const float ypr[3] = {yaw, -2.5f, 1.25f};
    const float rate[3] = {0.1f, -0.2f, 0.3f};
    const double lla[3] = {37.25130398358085, -121.87505366879361, 28.2116};
    const float vel[3] = {1.0f, 2.0f, -0.5f};
    const float acc[3] = {0.05f, -0.1f, -9.79f};
    const uint16_t status = 0x0123;
    i = put(b, i, &t_ns, 8);
    i = put(b, i, ypr, 12);
    i = put(b, i, rate, 12);
    i = put(b, i, lla, 24);
    i = put(b, i, vel, 12);
    i = put(b, i, acc, 12);
    i = put(b, i, &status, 2);
    const uint16_t crc = crc16_xmodem(b + 1, i - 1);
    b[i++] = (uint8_t)(crc >> 8); /* big-endian */
    b[i++] = (uint8_t)crc;
    return i;
}

/* The CRC must be the catalogued CRC-16/XMODEM (same as VectorNav's and SBP's). */
static void test_crc16_xmodem_check_value(void)
{
    CHECK(crc16_xmodem((const uint8_t *)"123456789", 9) == 0x31C3);
}

/* Our 0x11E9 configuration: 82 payload bytes, 88 in all, every field decoded. */
static void test_vn200_decodes_rover_configuration(void)
{
    uint8_t pkt[128];
    const size_t n = build_common_packet(pkt, 123456789012ull, 45.5f);
    CHECK(n == 88);
    vn200_parser_t p;
    sink_t s = {.count = 0};
    vn200_parser_init(&p, on_ins, &s);
    vn200_parser_feed(&p, pkt, n);
    CHECK(s.count == 1);
    CHECK(s.last.present == 0x7F);
    CHECK(s.last.time_startup_ns == 123456789012ull);
    CHECK(s.last.ypr_deg[0] == 45.5f && s.last.ypr_deg[2] == 1.25f);
    CHECK(s.last.angular_rate_rad_s[1] == -0.2f);
    CHECK(s.last.lla[0] == 37.25130398358085 && s.last.lla[1] == -121.87505366879361);
    CHECK(s.last.vel_ned_m_s[2] == -0.5f);
    CHECK(s.last.accel_m_s2[2] == -9.79f);
    CHECK(s.last.ins_status == 0x0123);
    CHECK(p.crc_errors == 0 && p.bytes_dropped == 0);
}

/* A flipped bit must be rejected and counted, and the next packet still decoded. */
static void test_vn200_bad_crc_counted_next_packet_decoded(void)
{
    uint8_t a[128], b[128];
    const size_t na = build_common_packet(a, 1, 1.0f);
    const size_t nb = build_common_packet(b, 2, 2.0f);
    a[40] ^= 0x10;
    vn200_parser_t p;
    sink_t s = {.count = 0};
    vn200_parser_init(&p, on_ins, &s);
    vn200_parser_feed(&p, a, na);
    vn200_parser_feed(&p, b, nb);
    CHECK(p.crc_errors == 1);
    CHECK(s.count == 1);
    CHECK(s.last.time_startup_ns == 2);
}

/* A packet that starts inside a truncated one (lost bytes) must not be lost: the
 * parser rescans the bytes it already holds. */
static void test_vn200_resyncs_into_packet_hidden_in_truncated_one(void)
{
    uint8_t stream[256];
    uint8_t b[128];
    size_t n = build_common_packet(stream, 1, 1.0f);
    n = 30; /* first packet truncated after 30 bytes */
    const size_t nb = build_common_packet(b, 7, 7.0f);
    memcpy(stream + n, b, nb);
    n += nb;
    const size_t nc = build_common_packet(stream + n, 8, 8.0f);
    n += nc;
    vn200_parser_t p;
    sink_t s = {.count = 0};
    vn200_parser_init(&p, on_ins, &s);
    for (size_t i = 0; i < n; i++) {
        vn200_parser_feed(&p, &stream[i], 1); /* byte at a time, as from the UART */
    }
    CHECK(s.count == 2);
    CHECK(s.last.time_startup_ns == 8);
    CHECK(p.crc_errors >= 1);
}

/* Garbage between packets (e.g. ASCII responses) must be skipped and counted. */
static void test_vn200_skips_garbage_between_packets(void)
{
    uint8_t stream[256];
    size_t n = 0;
    const char *ascii = "$VNRRG,01,VN-200*58\r\n";
    memcpy(stream, ascii, strlen(ascii));
    n += strlen(ascii);
    n += build_common_packet(stream + n, 3, 3.0f);
    vn200_parser_t p;
    sink_t s = {.count = 0};
    vn200_parser_init(&p, on_ins, &s);
    vn200_parser_feed(&p, stream, n);
    CHECK(s.count == 1);
    CHECK(p.bytes_dropped == strlen(ascii));
}

/* Fields we do not use (group 3 temperature, group 5 quaternion...) must be skipped by
 * size so the ones after them decode; variable-length fields are refused. */
static void test_vn200_skips_unused_fields_by_size_table(void)
{
    uint8_t b[128];
    size_t i = 0;
    b[i++] = 0xFA;
    b[i++] = 0x01 | 0x04 | 0x10; /* Common, IMU, Attitude */
    b[i++] = 0x01; /* Common: TimeStartup */
    b[i++] = 0x00;
    b[i++] = 0x10; /* IMU: Temp (bit 4, f32) */
    b[i++] = 0x04; /* IMU: AngularRate (bit 10) */
    b[i++] = 0x04 | 0x02; /* Attitude: YPR (bit 1), Quaternion (bit 2) */
    b[i++] = 0x00;
    const uint64_t t = 99;
    const float temp = 25.0f, rate[3] = {1, 2, 3}, ypr[3] = {10, 20, 30}, q[4] = {0, 0, 0, 1};
    i = put(b, i, &t, 8);
    i = put(b, i, &temp, 4);
    i = put(b, i, rate, 12);
    i = put(b, i, ypr, 12);
    i = put(b, i, q, 16);
    const uint16_t crc = crc16_xmodem(b + 1, i - 1);
    b[i++] = (uint8_t)(crc >> 8);
    b[i++] = (uint8_t)crc;
    vn200_parser_t p;
    sink_t s = {.count = 0};
    vn200_parser_init(&p, on_ins, &s);
    vn200_parser_feed(&p, b, i);
    CHECK(s.count == 1);
    CHECK(s.last.time_startup_ns == 99);
    CHECK(s.last.angular_rate_rad_s[2] == 3.0f);
    CHECK(s.last.ypr_deg[1] == 20.0f);
    CHECK(vn200_field_size(4, 14) == 0); /* GNSS SatInfo: variable length */
    CHECK(vn200_field_size(1, 6) == 24);
    const uint8_t satinfo[] = {0xFA, 0x08, 0x00, 0x40};
    vn200_parser_feed(&p, satinfo, sizeof satinfo);
    CHECK(p.bad_headers == 1);
}

/* A VN-100 style configuration (groups 3+5, IMU 0x003E: UncompMag/Accel/Gyro, Temp,
 * Pres; Attitude 0x003A: YPR, DCM, MagNed, AccelNed): 29 floats, 124 bytes. */
static size_t build_vn100_packet(uint8_t *b, float yaw)
{
    size_t i = 0;
    b[i++] = 0xFA;
    b[i++] = 0x14;
    b[i++] = 0x3E;
    b[i++] = 0x00;
    b[i++] = 0x3A;
    b[i++] = 0x00;
    float f[29];
    for (int k = 0; k < 29; k++) {
        f[k] = (float)k * 0.5f - 3.0f;
    }
    f[11] = yaw; /* YPR follows the 11 IMU floats */
    i = put(b, i, f, sizeof f);
    const uint16_t crc = crc16_xmodem(b + 1, i - 1);
    b[i++] = (uint8_t)(crc >> 8);
    b[i++] = (uint8_t)crc;
    return i;
}

/* The shape of the real VN-100 capture's hard case: a logger's ASCII markers between
 * packets and a stray sync byte right before a packet (the upstream parser lost that
 * packet). Any group/field configuration is framed from its masks; only YPR of this one
 * is a field we decode. */
static void test_vn200_frames_vn100_layout_after_a_stray_sync(void)
{
    uint8_t stream[512];
    size_t n = 0;
    const char *marker = "M,123456\r\n";
    memcpy(stream, marker, strlen(marker));
    n += strlen(marker);
    n += build_vn100_packet(stream + n, 10.0f);
    CHECK(n - strlen(marker) == 124);
    stream[n++] = 0xFA; /* stray */
    n += build_vn100_packet(stream + n, 20.0f);
    stream[n++] = 0xFA; /* stray, then a packet cut short, then a whole one */
    const size_t cut = build_vn100_packet(stream + n, 30.0f);
    (void)cut;
    n += 60;
    n += build_vn100_packet(stream + n, 40.0f);
    vn200_parser_t p;
    sink_t s = {.count = 0};
    vn200_parser_init(&p, on_ins, &s);
    for (size_t i = 0; i < n; i++) {
        vn200_parser_feed(&p, &stream[i], 1);
    }
    CHECK(s.count == 3);
    CHECK(s.last.group == 0x14 && s.last.present == VN200_HAVE_YPR);
    CHECK(s.last.ypr_deg[0] == 40.0f && s.last.ypr_deg[1] == 3.0f);
    CHECK(p.bytes_dropped == n - 3 * 124 && p.n == 0);
}

int main(void)
{
    RUN(test_crc16_xmodem_check_value);
    RUN(test_vn200_decodes_rover_configuration);
    RUN(test_vn200_bad_crc_counted_next_packet_decoded);
    RUN(test_vn200_resyncs_into_packet_hidden_in_truncated_one);
    RUN(test_vn200_skips_garbage_between_packets);
    RUN(test_vn200_skips_unused_fields_by_size_table);
    RUN(test_vn200_frames_vn100_layout_after_a_stray_sync);
    return ALGO_TEST_EXIT();
}
