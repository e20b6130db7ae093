/* SBP frame parser, see sbp.h. */
#include "sbp.h"

#include <string.h>

#include "crc16_xmodem.h"
#include "le_bytes.h"
#include "resync_buf.h"

#define HEADER_LEN 6u

void sbp_parser_init(sbp_parser_t *p, sbp_handler_t handler, void *ctx)
{
    memset(p, 0, sizeof *p);
    p->handler = handler;
    p->ctx = ctx;
}

static int decode_baseline_ned(const uint8_t *b, sbp_baseline_ned_t *m)
{
    m->tow = le_u32(b);
    m->n = le_i32(b + 4);
    m->e = le_i32(b + 8);
    m->d = le_i32(b + 12);
    m->h_accuracy = le_u16(b + 16);
    m->v_accuracy = le_u16(b + 18);
    m->n_sats = b[20];
    m->flags = b[21];
    return 1;
}

int sbp_decode_payload(uint16_t msg_type, const uint8_t *b, uint8_t len, sbp_msg_t *msg)
{
    msg->decoded = 0;
    switch (msg_type) {
    case SBP_MSG_BASELINE_NED:
        if (len != 22) {
            return 0;
        }
        decode_baseline_ned(b, &msg->m.baseline_ned);
        break;
    case SBP_MSG_VEL_NED: /* same layout as BASELINE_NED, mm/s */
        if (len != 22) {
            return 0;
        }
        {
            sbp_baseline_ned_t t;
            decode_baseline_ned(b, &t);
            sbp_vel_ned_t *v = &msg->m.vel_ned;
            v->tow = t.tow;
            v->n = t.n;
            v->e = t.e;
            v->d = t.d;
            v->h_accuracy = t.h_accuracy;
            v->v_accuracy = t.v_accuracy;
            v->n_sats = t.n_sats;
            v->flags = t.flags;
        }
        break;
    case SBP_MSG_POS_LLH: {
        if (len != 34) {
            return 0;
        }
        sbp_pos_llh_t *m = &msg->m.pos_llh;
        m->tow = le_u32(b);
        m->lat = le_f64(b + 4);
        m->lon = le_f64(b + 12);
        m->height = le_f64(b + 20);
        m->h_accuracy = le_u16(b + 28);
        m->v_accuracy = le_u16(b + 30);
        m->n_sats = b[32];
        m->flags = b[33];
        break;
    }
    case SBP_MSG_GPS_TIME: {
        if (len != 11) {
            return 0;
        }
        sbp_gps_time_t *m = &msg->m.gps_time;
        m->wn = le_u16(b);
        m->tow = le_u32(b + 2);
        m->ns_residual = le_i32(b + 6);
        m->flags = b[10];
        break;
    }
    case SBP_MSG_BASELINE_ECEF: {
        if (len != 20) {
            return 0;
        }
        sbp_baseline_ecef_t *m = &msg->m.baseline_ecef;
        m->tow = le_u32(b);
        m->x = le_i32(b + 4);
        m->y = le_i32(b + 8);
        m->z = le_i32(b + 12);
        m->accuracy = le_u16(b + 16);
        m->n_sats = b[18];
        m->flags = b[19];
        break;
    }
    case SBP_MSG_DOPS: {
        if (len != 15) {
            return 0;
        }
        sbp_dops_t *m = &msg->m.dops;
        m->tow = le_u32(b);
        m->gdop = le_u16(b + 4);
        m->pdop = le_u16(b + 6);
        m->tdop = le_u16(b + 8);
        m->hdop = le_u16(b + 10);
        m->vdop = le_u16(b + 12);
        m->flags = b[14];
        break;
    }
    case SBP_MSG_UTC_TIME: {
        if (len != 16) {
            return 0;
        }
        sbp_utc_time_t *m = &msg->m.utc_time;
        m->flags = b[0];
        m->tow = le_u32(b + 1);
        m->year = le_u16(b + 5);
        m->month = b[7];
        m->day = b[8];
        m->hours = b[9];
        m->minutes = b[10];
        m->seconds = b[11];
        m->ns = le_u32(b + 12);
        break;
    }
    case SBP_MSG_IMU_RAW: {
        if (len != 17) {
            return 0;
        }
        sbp_imu_raw_t *m = &msg->m.imu_raw;
        m->tow = le_u32(b);
        m->tow_f = b[4];
        m->acc_x = le_i16(b + 5);
        m->acc_y = le_i16(b + 7);
        m->acc_z = le_i16(b + 9);
        m->gyr_x = le_i16(b + 11);
        m->gyr_y = le_i16(b + 13);
        m->gyr_z = le_i16(b + 15);
        break;
    }
    default:
        return 0;
    }
    msg->decoded = 1;
    return 1;
}

static int known_type(uint16_t t)
{
    switch (t) {
    case SBP_MSG_BASELINE_NED:
    case SBP_MSG_VEL_NED:
    case SBP_MSG_POS_LLH:
    case SBP_MSG_GPS_TIME:
    case SBP_MSG_BASELINE_ECEF:
    case SBP_MSG_DOPS:
    case SBP_MSG_UTC_TIME:
    case SBP_MSG_IMU_RAW:
        return 1;
    default:
        return 0;
    }
}

static void deliver(sbp_parser_t *p)
{
    sbp_msg_t msg;
    memset(&msg, 0, sizeof msg);
    msg.msg_type = le_u16(p->buf + 1);
    msg.sender = le_u16(p->buf + 3);
    msg.length = p->buf[5];
    msg.payload = p->buf + HEADER_LEN;
    if (!sbp_decode_payload(msg.msg_type, msg.payload, msg.length, &msg)) {
        if (known_type(msg.msg_type)) {
            p->bad_length++;
        } else {
            p->undecoded++;
        }
    }
    p->frames++;
    if (p->handler) {
        p->handler(p->ctx, &msg);
    }
}

static void discard(sbp_parser_t *p, size_t k)
{
    resync_discard(p->buf, &p->n, k);
    p->later_syncs = resync_count(p->buf, p->n, SBP_PREAMBLE);
}

static void hunt(sbp_parser_t *p)
{
    p->bytes_dropped += resync_hunt(p->buf, &p->n, SBP_PREAMBLE);
}

/* CRC-16/XMODEM starts at 0, so a preamble followed by zeros is a "valid" empty frame
 * of type 0 (zeros are common in payloads): type 0 does not exist and is refused. */
static int frame_ok(const uint8_t *b, size_t total)
{
    return le_u16(b + 1) != 0u && crc16_xmodem(b + 1, total - 3) == le_u16(b + total - 2);
}

/* The frame at the front is still incomplete. If a later preamble in the buffer starts
 * a frame that the last byte just completed with a valid CRC, the front one was a false
 * start (garbage or a truncated frame whose length byte points far ahead): drop up to
 * the later frame now instead of holding it back until up to 263 bytes have arrived.
 * Each later candidate is CRC-checked once, when its last byte arrives. */
static int later_frame_completed(sbp_parser_t *p)
{
    if (p->later_syncs == 0) {
        return 0; /* the usual case: no other sync byte since the front one */
    }
    for (size_t j = 1; j + HEADER_LEN <= p->n; j++) {
        if (p->buf[j] == SBP_PREAMBLE && HEADER_LEN + p->buf[j + 5] + 2u == p->n - j &&
            frame_ok(p->buf + j, p->n - j)) {
            p->bytes_dropped += (uint32_t)j;
            discard(p, j);
            return 1;
        }
    }
    return 0;
}

static void process(sbp_parser_t *p)
{
    while (p->n >= HEADER_LEN) {
        const size_t total = HEADER_LEN + p->buf[5] + 2u;
        if (p->n < total) {
            if (!later_frame_completed(p)) {
                return;
            }
            continue;
        }
        if (frame_ok(p->buf, total)) {
            deliver(p);
            discard(p, total);
            hunt(p); /* leftovers come from a rescan */
        } else {
            p->crc_errors++;
            p->bytes_dropped++; /* a false sync: rescan what follows it */
            discard(p, 1);
            hunt(p);
        }
    }
}

void sbp_parser_feed(sbp_parser_t *p, const uint8_t *data, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        if (p->n == 0 && data[i] != SBP_PREAMBLE) {
            p->bytes_dropped++;
            continue;
        }
        if (p->n > 0 && data[i] == SBP_PREAMBLE) {
            p->later_syncs++;
        }
        p->buf[p->n++] = data[i];
        process(p);
    }
}
