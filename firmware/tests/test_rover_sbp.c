/* SBP frame parser: libsbp vectors, CRC errors, resync, unknown types. */
#include <stdint.h>
#include <string.h>

#include "rover/crc16_xmodem.h"
#include "rover/sbp.h"
#include "test_algos.h"

/* From libsbp's test_MsgBaselineNED.yaml / test_MsgPosLLH.yaml / test_MsgGPSTime.yaml
 * (the full sets run from Python: tests/firmware_algos/test_sbp.py). */
static const uint8_t BASELINE_NED[] = {0x55, 0x0c, 0x02, 0xd3, 0x88, 0x16, 0x28, 0xf4, 0x7a, 0x13,
                                       0xc9, 0x73, 0x0c, 0x00, 0xb3, 0x58, 0xe6, 0xff, 0x99, 0x7d,
                                       0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0e, 0x00, 0xe2, 0x46};
static const uint8_t POS_LLH[] = {0x55, 0x0a, 0x02, 0xd3, 0x88, 0x22, 0x28, 0xf4, 0x7a, 0x13, 0xc9,
                                  0x6a, 0x9b, 0xba, 0x2a, 0xa0, 0x42, 0x40, 0xa8, 0x6d, 0x1a, 0xe1,
                                  0x00, 0x78, 0x5e, 0xc0, 0x82, 0x66, 0xed, 0xe6, 0x2b, 0x36, 0x3c,
                                  0x40, 0x00, 0x00, 0x00, 0x00, 0x0e, 0x02, 0xaf, 0xa2};
static const uint8_t GPS_TIME[] = {0x55, 0x02, 0x01, 0xd3, 0x88, 0x0b, 0x80, 0x07, 0x28, 0xf4,
                                   0x7a, 0x13, 0xf4, 0x8b, 0x02, 0x00, 0x00, 0x22, 0x98};

typedef struct {
    sbp_msg_t last;
    int count;
    int decoded;
} sink_t;

static void on_msg(void *ctx, const sbp_msg_t *m)
{
    sink_t *s = ctx;
    s->last = *m;
    s->last.payload = NULL; /* only valid during the call */
    s->count++;
    s->decoded += m->decoded;
}

/* Real Piksi frames must decode to exactly libsbp's field values. */
static void test_sbp_decodes_libsbp_vectors(void)
{
    sbp_parser_t p;
    sink_t s = {.count = 0};
    sbp_parser_init(&p, on_msg, &s);
    sbp_parser_feed(&p, BASELINE_NED, sizeof BASELINE_NED);
    CHECK(s.count == 1 && s.last.decoded);
    CHECK(s.last.msg_type == SBP_MSG_BASELINE_NED && s.last.sender == 0x88d3);
    const sbp_baseline_ned_t *b = &s.last.m.baseline_ned;
    CHECK(b->tow == 326825000u && b->n == 816073 && b->e == -1681229 && b->d == 32153);
    CHECK(b->n_sats == 14 && b->flags == 0 && b->h_accuracy == 0);

    sbp_parser_feed(&p, POS_LLH, sizeof POS_LLH);
    const sbp_pos_llh_t *l = &s.last.m.pos_llh;
    CHECK(s.last.msg_type == SBP_MSG_POS_LLH);
    CHECK(l->lat == 37.25130398358085 && l->lon == -121.87505366879361 && l->height == 28.21160739227208);
    CHECK(l->flags == 2 && l->n_sats == 14);

    sbp_parser_feed(&p, GPS_TIME, sizeof GPS_TIME);
    const sbp_gps_time_t *g = &s.last.m.gps_time;
    CHECK(g->wn == 1920 && g->tow == 326825000u && g->ns_residual == 166900 && g->flags == 0);
    CHECK(p.frames == 3 && p.crc_errors == 0);
}

/* A corrupted frame must be counted and must not swallow the frame after it. */
static void test_sbp_bad_crc_counted_and_next_frame_kept(void)
{
    uint8_t stream[128];
    memcpy(stream, BASELINE_NED, sizeof BASELINE_NED);
    stream[10] ^= 0x01;
    memcpy(stream + sizeof BASELINE_NED, GPS_TIME, sizeof GPS_TIME);
    sbp_parser_t p;
    sink_t s = {.count = 0};
    sbp_parser_init(&p, on_msg, &s);
    for (size_t i = 0; i < sizeof BASELINE_NED + sizeof GPS_TIME; i++) {
        sbp_parser_feed(&p, &stream[i], 1);
    }
    CHECK(p.crc_errors == 1);
    CHECK(s.count == 1 && s.last.msg_type == SBP_MSG_GPS_TIME);
}

/* A truncated frame whose length byte points past the next frame: the next frame is
 * inside the bytes already held and must be found by the rescan. */
static void test_sbp_resyncs_into_frame_hidden_in_truncated_one(void)
{
    uint8_t stream[256];
    size_t n = 0;
    memcpy(stream, POS_LLH, 12); /* header says 34 payload bytes, only 6 follow */
    n = 12;
    memcpy(stream + n, GPS_TIME, sizeof GPS_TIME);
    n += sizeof GPS_TIME;
    memcpy(stream + n, BASELINE_NED, sizeof BASELINE_NED);
    n += sizeof BASELINE_NED;
    sbp_parser_t p;
    sink_t s = {.count = 0};
    sbp_parser_init(&p, on_msg, &s);
    for (size_t i = 0; i < n; i++) {
        sbp_parser_feed(&p, &stream[i], 1);
    }
    CHECK(s.count == 2);
    CHECK(s.last.msg_type == SBP_MSG_BASELINE_NED);
}

/* Types we do not decode are framed, counted and passed on undecoded. */
static void test_sbp_unknown_type_counted_not_decoded(void)
{
    uint8_t f[16] = {0x55, 0x34, 0x12, 0x01, 0x00, 0x03, 0xAA, 0xBB, 0xCC};
    const uint16_t crc = crc16_xmodem_update(0, f + 1, 8);
    f[9] = (uint8_t)crc;
    f[10] = (uint8_t)(crc >> 8);
    sbp_parser_t p;
    sink_t s = {.count = 0};
    sbp_parser_init(&p, on_msg, &s);
    sbp_parser_feed(&p, f, 11);
    CHECK(s.count == 1 && s.decoded == 0);
    CHECK(p.undecoded == 1 && p.frames == 1);
    CHECK(s.last.msg_type == 0x1234 && s.last.length == 3);
}

int main(void)
{
    RUN(test_sbp_decodes_libsbp_vectors);
    RUN(test_sbp_bad_crc_counted_and_next_frame_kept);
    RUN(test_sbp_resyncs_into_frame_hidden_in_truncated_one);
    RUN(test_sbp_unknown_type_counted_not_decoded);
    return ALGO_TEST_EXIT();
}
