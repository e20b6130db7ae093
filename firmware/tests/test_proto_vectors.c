/* Golden vectors (protocol/vectors/ JSON, as C data in test_proto_vectors.h): the C
 * codec must produce and accept exactly the bytes the Python codec and the reference
 * generator do, and count stream corruption exactly as they do. */
#include "test_proto_util.h"
#include "test_proto_vectors.h"

#define N_ITEMS(a) (sizeof(a) / sizeof((a)[0]))

/* Encoding the vector's struct must give its frame byte for byte. */
static void test_golden_frames_encode_byte_exact(void)
{
    for (size_t i = 0; i < N_ITEMS(aw_vec_frames); ++i) {
        const aw_vec_frame_t *v = &aw_vec_frames[i];
        uint8_t out[AW_MAX_WIRE_SIZE];
        const int n = aw_encode_msg(out, sizeof out, v->msg_id, v->seq, v->flags,
                                    v->board_time_us, v->msg);
        const int same = n == (int)v->frame_len && memcmp(out, v->frame, v->frame_len) == 0;
        CHECK(same);
        if (!same) {
            fprintf(stderr, "  vector %s\n", v->name);
        }
        uint8_t payload[AW_MAX_PAYLOAD_SIZE];
        CHECK(aw_pack_msg(v->msg_id, payload, sizeof payload, v->msg) == (int)v->payload_len);
        CHECK(memcmp(payload, v->payload, v->payload_len) == 0);
    }
}

/* Decoding the frame must give the vector's header and payload; unpacking and encoding
 * the decoded struct again must give the same frame (floats bit-exact, NaN included). */
static void test_golden_frames_decode_to_their_values(void)
{
    for (size_t i = 0; i < N_ITEMS(aw_vec_frames); ++i) {
        const aw_vec_frame_t *v = &aw_vec_frames[i];
        aw_decoder_t d;
        aw_decoder_init(&d, NULL, NULL);
        aw_frame_t f;
        int got = 0;
        for (size_t k = 0; k < v->frame_len; ++k) {
            got += aw_decoder_feed_byte(&d, v->frame[k], &f);
        }
        CHECK(got == 1);
        if (got != 1) {
            fprintf(stderr, "  vector %s\n", v->name);
            continue;
        }
        CHECK(f.header.msg_id == v->msg_id && f.header.seq == v->seq);
        CHECK(f.header.flags == v->flags && f.header.board_time_us == v->board_time_us);
        CHECK(f.payload_len == v->payload_len && memcmp(f.payload, v->payload, v->payload_len) == 0);
        aw_any_msg_t msg;
        CHECK(aw_unpack_msg(f.header.msg_id, &msg, f.payload, f.payload_len) == 0);
        uint8_t out[AW_MAX_WIRE_SIZE];
        const int n = aw_encode_msg(out, sizeof out, v->msg_id, v->seq, v->flags,
                                    v->board_time_us, &msg);
        CHECK(n == (int)v->frame_len && memcmp(out, v->frame, v->frame_len) == 0);
    }
}

static void check_stream(const aw_vec_stream_t *s, const aw_decoder_t *d, size_t delivered)
{
    const aw_counters_t *c = &d->counters, *e = &s->expect;
    const int same = c->frames_ok == e->frames_ok && c->crc_error == e->crc_error &&
                     c->unknown_id == e->unknown_id && c->def_mismatch == e->def_mismatch &&
                     c->oversize == e->oversize && c->cobs_error == e->cobs_error &&
                     c->bytes_dropped == e->bytes_dropped && delivered == s->frame_count;
    CHECK(same);
    if (!same) {
        fprintf(stderr, "  stream %s: ok %u crc %u unknown %u mismatch %u oversize %u cobs %u "
                        "dropped %u\n", s->name, c->frames_ok, c->crc_error, c->unknown_id,
                c->def_mismatch, c->oversize, c->cobs_error, c->bytes_dropped);
    }
}

typedef struct {
    const aw_vec_stream_t *s;
    size_t n;
} stream_sink_t;

static void on_stream_frame(void *ctx, const aw_frame_t *f)
{
    stream_sink_t *k = ctx;
    CHECK(k->n < k->s->frame_count);
    if (k->n >= k->s->frame_count) {
        return;
    }
    const aw_vec_decoded_t *e = &k->s->frames[k->n++];
    CHECK(f->header.msg_id == e->msg_id && f->header.seq == e->seq);
    CHECK(f->header.flags == e->flags && f->header.board_time_us == e->board_time_us);
    CHECK(f->payload_len == e->payload_len && memcmp(f->payload, e->payload, e->payload_len) == 0);
}

/* Corrupted streams: the same frames delivered and the same counters as the reference. */
static void test_golden_streams_count_like_the_reference(void)
{
    for (size_t i = 0; i < N_ITEMS(aw_vec_streams); ++i) {
        const aw_vec_stream_t *s = &aw_vec_streams[i];
        stream_sink_t sink = {s, 0};
        aw_decoder_t d;
        aw_decoder_init(&d, on_stream_frame, &sink);
        const size_t delivered = aw_decoder_feed(&d, s->bytes, s->len);
        check_stream(s, &d, delivered);
        CHECK(sink.n == s->frame_count);
    }
}

int main(void)
{
    RUN(test_golden_frames_encode_byte_exact);
    RUN(test_golden_frames_decode_to_their_values);
    RUN(test_golden_streams_count_like_the_reference);
    return tp_finish();
}
