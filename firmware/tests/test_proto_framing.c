/* CRC, COBS encoder and decoder, pack/unpack: unit tests named after what they pin. */
#include "test_proto_util.h"

static uint16_t crc_bitwise(uint16_t crc, const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        crc ^= (uint16_t)(p[i] << 8);
        for (int k = 0; k < 8; ++k) {
            crc = (uint16_t)((crc & 0x8000u) ? ((unsigned)crc << 1) ^ 0x1021u : (unsigned)crc << 1);
        }
    }
    return crc;
}

/* The CRC must be CRC-16/CCITT-FALSE's, or Python's binascii.crc_hqx disagrees. */
static void test_crc_is_ccitt_false(void)
{
    const uint8_t check[] = "123456789";
    CHECK_EQ_U(aw_crc16(0xFFFF, check, 9), 0x29B1);
    tp_rng_t r = {42};
    for (int i = 0; i < 200; ++i) {
        uint8_t buf[64];
        const size_t n = tp_below(&r, sizeof buf);
        tp_fill(&r, buf, n, 100);
        const uint16_t seed = (uint16_t)tp_next(&r);
        CHECK_EQ_U(aw_crc16(seed, buf, n), crc_bitwise(seed, buf, n));
    }
}

/* The seed is the documented fold of the definition hash, per message. */
static void test_crc_seed_is_fold_of_definition_hash(void)
{
    for (size_t i = 0; i < AW_MSG_COUNT; ++i) {
        const aw_msg_info_t *m = &aw_msg_table[i];
        CHECK_EQ_U(m->crc_seed, ((m->def_hash >> 16) ^ m->def_hash) & 0xFFFFu);
        CHECK(aw_msg_info(m->id) == m);
    }
    CHECK(aw_msg_info(0) == NULL);
    CHECK(aw_msg_info(0xEE) == NULL);
}

/* A too-small output buffer must be refused before a single byte is written. */
static void test_encoder_refuses_small_buffer_without_writing(void)
{
    uint8_t payload[AW_SIZE_IMU] = {0};
    uint8_t out[AW_WIRE_MAX_IMU + 8];
    memset(out, 0xA5, sizeof out);
    const aw_header_t h = {AW_ID_IMU, 1, AW_BOARD_LOSA, 5};
    CHECK(aw_frame_encode(out, AW_WIRE_MAX_IMU - 1, &h, payload, sizeof payload) ==
          AW_ERR_NO_SPACE);
    for (size_t i = 0; i < sizeof out; ++i) {
        CHECK(out[i] == 0xA5);
    }
    CHECK(aw_frame_encode(out, AW_WIRE_MAX_IMU, &h, payload, sizeof payload) > 0);
    for (size_t i = AW_WIRE_MAX_IMU; i < sizeof out; ++i) {
        CHECK(out[i] == 0xA5);
    }
}

/* Unknown ids and wrong payload sizes are errors, not frames nobody can decode. */
static void test_encoder_rejects_unknown_id_and_wrong_size(void)
{
    uint8_t payload[AW_MAX_PAYLOAD_SIZE] = {0};
    uint8_t out[AW_MAX_WIRE_SIZE];
    aw_header_t h = {0xEE, 0, 0, 0};
    CHECK(aw_frame_encode(out, sizeof out, &h, payload, 4) == AW_ERR_UNKNOWN_ID);
    h.msg_id = AW_ID_IMU;
    CHECK(aw_frame_encode(out, sizeof out, &h, payload, AW_SIZE_IMU + 1) == AW_ERR_SIZE);
    CHECK(aw_encode_msg(out, sizeof out, 0xEE, 0, 0, 0, payload) == AW_ERR_UNKNOWN_ID);
}

typedef struct {
    int count;
    aw_frame_t last;
    uint8_t payload[AW_MAX_PAYLOAD_SIZE];
} sink_t;

static void on_frame(void *ctx, const aw_frame_t *f)
{
    sink_t *s = ctx;
    s->count++;
    s->last = *f;
    memcpy(s->payload, f->payload, f->payload_len);
    s->last.payload = s->payload;
}

/* Every message, payloads from all-zero to no-zero (0xFF COBS blocks), encodes within
 * its documented worst case and decodes back bit-exact. */
static void test_every_message_roundtrips_at_every_zero_density(void)
{
    static const uint32_t densities[] = {0, 5, 100, 500, 1000};
    tp_rng_t r = {7};
    for (size_t i = 0; i < AW_MSG_COUNT; ++i) {
        const aw_msg_info_t *m = &aw_msg_table[i];
        for (size_t k = 0; k < sizeof densities / sizeof densities[0]; ++k) {
            uint8_t payload[AW_MAX_PAYLOAD_SIZE];
            uint8_t out[AW_MAX_WIRE_SIZE];
            tp_fill(&r, payload, m->payload_size, densities[k]);
            const aw_header_t h = {m->id, (uint8_t)k, AW_BOARD_ROVER, (uint32_t)tp_next(&r)};
            const int n = aw_frame_encode(out, sizeof out, &h, payload, m->payload_size);
            CHECK(n > 0 && (size_t)n <= aw_wire_max(m->payload_size));
            CHECK(out[0] == 0 && out[n - 1] == 0 && memchr(out + 1, 0, (size_t)n - 2) == NULL);
            sink_t s = {0};
            aw_decoder_t d;
            aw_decoder_init(&d, on_frame, &s);
            CHECK_EQ_U(aw_decoder_feed(&d, out, (size_t)n), 1);
            CHECK(s.count == 1 && s.last.header.msg_id == m->id && s.last.header.seq == k);
            CHECK(s.last.header.board_time_us == h.board_time_us);
            CHECK(s.last.payload_len == m->payload_size &&
                  memcmp(s.payload, payload, m->payload_size) == 0);
            CHECK_EQ_U(d.counters.frames_ok, 1);
            CHECK_EQ_U(d.counters.bytes_dropped, 0);
        }
    }
}

/* pack(unpack(bytes)) must give the same bytes for any bit pattern, NaNs included. */
static void test_pack_unpack_are_bit_exact_inverses(void)
{
    tp_rng_t r = {99};
    for (size_t i = 0; i < AW_MSG_COUNT; ++i) {
        const aw_msg_info_t *m = &aw_msg_table[i];
        for (int rep = 0; rep < 50; ++rep) {
            uint8_t in[AW_MAX_PAYLOAD_SIZE], again[AW_MAX_PAYLOAD_SIZE];
            tp_fill(&r, in, m->payload_size, 200);
            aw_any_msg_t msg;
            CHECK(aw_unpack_msg(m->id, &msg, in, m->payload_size) == 0);
            CHECK(aw_pack_msg(m->id, again, sizeof again, &msg) == (int)m->payload_size);
            CHECK(memcmp(in, again, m->payload_size) == 0);
        }
    }
    aw_any_msg_t msg;
    uint8_t buf[4] = {0};
    CHECK(aw_unpack_msg(AW_ID_IMU, &msg, buf, sizeof buf) == AW_ERR_SIZE);
}

/* Known field values land at the documented offsets, little-endian. */
static void test_imu_fields_are_little_endian_at_documented_offsets(void)
{
    aw_imu_t m = {0};
    m.gyro_frd_rad_s[0] = 1.0f; /* 0x3F800000 */
    m.temperature_c = -2.0f;    /* 0xC0000000 */
    m.status = AW_IMU_STATUS_MAG_VALID;
    uint8_t p[AW_SIZE_IMU];
    aw_pack_imu(p, &m);
    CHECK(p[0] == 0x00 && p[1] == 0x00 && p[2] == 0x80 && p[3] == 0x3F);
    CHECK(p[36] == 0x00 && p[39] == 0xC0);
    CHECK(p[40] == 0x04);
    aw_losa_peaks_t pk = {0};
    pk.slot[1] = -1;
    pk.intensity_counts[0] = 0x1234;
    uint8_t q[AW_SIZE_LOSA_PEAKS];
    aw_pack_losa_peaks(q, &pk);
    CHECK(q[16] == 0x34 && q[17] == 0x12);
    CHECK(q[24 + 1] == 0xFF);
}

/* Byte-at-a-time polling and the buffer form must see the same frames and counters. */
static void test_poll_and_buffer_forms_agree(void)
{
    tp_rng_t r = {5};
    uint8_t stream[4096];
    size_t len = 0;
    while (len + AW_MAX_WIRE_SIZE + 16 < sizeof stream) {
        const aw_msg_info_t *m = &aw_msg_table[tp_below(&r, AW_MSG_COUNT)];
        uint8_t payload[AW_MAX_PAYLOAD_SIZE];
        tp_fill(&r, payload, m->payload_size, 100);
        const aw_header_t h = {m->id, 0, 1, 0};
        len += (size_t)aw_frame_encode(stream + len, sizeof stream - len, &h, payload,
                                       m->payload_size);
        if (tp_below(&r, 4) == 0) {
            stream[len++] = (uint8_t)tp_next(&r); /* noise */
        }
    }
    aw_decoder_t a, b;
    aw_decoder_init(&a, NULL, NULL);
    aw_decoder_init(&b, NULL, NULL);
    size_t polled = 0;
    aw_frame_t f;
    for (size_t i = 0; i < len; ++i) {
        polled += aw_decoder_feed_byte(&a, stream[i], &f);
    }
    CHECK_EQ_U(aw_decoder_feed(&b, stream, len), polled);
    CHECK(memcmp(&a.counters, &b.counters, sizeof a.counters) == 0);
    CHECK(polled > 10);
}

/* After a peer announces another definition, its intact frames are a mismatch, not
 * corruption; frames corrupt under both seeds stay CRC errors. */
static void test_announced_hash_turns_crc_error_into_def_mismatch(void)
{
    const uint32_t other_hash = AW_HASH_IMU ^ 0x00010000u;
    uint8_t payload[AW_SIZE_IMU + 1] = {1, 2, 3};
    uint8_t out[AW_MAX_WIRE_SIZE];
    const aw_header_t h = {AW_ID_IMU, 0, AW_BOARD_MARKER, 0};
    const int n = aw_frame_encode_seeded(out, sizeof out, &h, payload, sizeof payload,
                                         aw_crc_seed(other_hash));
    aw_decoder_t d;
    aw_decoder_init(&d, NULL, NULL);
    aw_decoder_feed(&d, out, (size_t)n);
    CHECK_EQ_U(d.counters.crc_error, 1);
    aw_schema_entry_t e = {.msg_id = AW_ID_IMU, .def_hash = other_hash, .entry_count = 1};
    uint8_t ann[AW_WIRE_MAX_SCHEMA_ENTRY];
    const int na = aw_encode_schema_entry(ann, sizeof ann, 0, AW_BOARD_MARKER, 0, &e);
    CHECK_EQ_U(aw_decoder_feed(&d, ann, (size_t)na), 1);
    aw_decoder_feed(&d, out, (size_t)n);
    CHECK_EQ_U(d.counters.def_mismatch, 1);
    out[4] ^= 0x40; /* the flags byte: corrupt under both seeds */
    aw_decoder_feed(&d, out, (size_t)n);
    CHECK_EQ_U(d.counters.crc_error, 2);
    CHECK_EQ_U(d.counters.frames_ok, 1);
}

int main(void)
{
    RUN(test_crc_is_ccitt_false);
    RUN(test_crc_seed_is_fold_of_definition_hash);
    RUN(test_encoder_refuses_small_buffer_without_writing);
    RUN(test_encoder_rejects_unknown_id_and_wrong_size);
    RUN(test_every_message_roundtrips_at_every_zero_density);
    RUN(test_pack_unpack_are_bit_exact_inverses);
    RUN(test_imu_fields_are_little_endian_at_documented_offsets);
    RUN(test_poll_and_buffer_forms_agree);
    RUN(test_announced_hash_turns_crc_error_into_def_mismatch);
    return tp_finish();
}
