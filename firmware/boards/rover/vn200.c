/* VN-200 binary packet parser, see vn200.h. */
#include "vn200.h"

#include <string.h>

#include "crc16_xmodem.h"
#include "le_bytes.h"
#include "resync_buf.h"

/* Field sizes per group (rows 1..7) and bit (0..14); 0 = unknown or variable length. */
static const uint8_t field_size[VN200_GROUPS][15] = {
    {8, 8, 8, 12, 16, 12, 24, 12, 12, 24, 20, 28, 2, 4, 8},    /* 1 Common */
    {8, 8, 8, 2, 8, 8, 8, 4, 4, 1, 0, 0, 0, 0, 0},             /* 2 Time */
    {2, 12, 12, 12, 4, 4, 16, 12, 12, 12, 12, 2, 40, 0, 0},    /* 3 IMU */
    {8, 8, 2, 1, 1, 24, 24, 12, 12, 12, 4, 4, 2, 28, 0},       /* 4 GNSS */
    {2, 12, 16, 36, 12, 12, 12, 12, 12, 12, 28, 24, 12, 0, 0}, /* 5 Attitude */
    {2, 24, 24, 12, 12, 12, 12, 12, 12, 4, 4, 68, 64, 0, 0},   /* 6 INS */
    {8, 8, 2, 1, 1, 24, 24, 12, 12, 12, 4, 4, 2, 28, 0},       /* 7 GNSS2 */
};

enum { HDR_NEED_MORE, HDR_OK, HDR_BAD };

unsigned vn200_field_size(unsigned group, unsigned bit)
{
    if (group < 1u || group > VN200_GROUPS || bit > 14u) {
        return 0;
    }
    return field_size[group - 1u][bit];
}

void vn200_parser_init(vn200_parser_t *p, vn200_handler_t handler, void *ctx)
{
    memset(p, 0, sizeof *p);
    p->handler = handler;
    p->ctx = ctx;
}

/* Validate the header in buf[0..n) and compute the packet length. */
static int header(const uint8_t *b, size_t n, size_t *total)
{
    if (n < 2) {
        return HDR_NEED_MORE;
    }
    const uint8_t groups = b[1];
    if (groups == 0 || (groups & 0x80u)) {
        return HDR_BAD;
    }
    size_t idx = 2;
    size_t payload = 0;
    for (unsigned g = 0; g < VN200_GROUPS; g++) {
        if (!(groups & (1u << g))) {
            continue;
        }
        if (n < idx + 2) {
            return HDR_NEED_MORE;
        }
        const uint16_t mask = le_u16(&b[idx]);
        idx += 2;
        if (mask == 0 || (mask & 0x8000u)) {
            return HDR_BAD;
        }
        /* only the set bits (this runs for every byte of a pending packet) */
        for (unsigned rest = mask; rest != 0; rest &= rest - 1u) {
            const unsigned sz = field_size[g][__builtin_ctz(rest)];
            if (sz == 0) {
                return HDR_BAD;
            }
            payload += sz;
        }
    }
    *total = idx + payload + 2;
    return HDR_OK;
}

static void read_f32x3(const uint8_t *p, float out[3])
{
    for (int i = 0; i < 3; i++) {
        out[i] = le_f32(p + 4 * i);
    }
}

/* Decode one field into *ins if it is one we use. */
static void decode_field(unsigned g, unsigned bit, const uint8_t *f, vn200_ins_t *ins)
{
    const unsigned key = (g + 1u) * 16u + bit; /* group number, bit */
    switch (key) {
    case 0x10: /* Common TimeStartup */
    case 0x20: /* Time TimeStartup */
        ins->time_startup_ns = le_u64(f);
        ins->present |= VN200_HAVE_TIME_STARTUP;
        break;
    case 0x13: /* Common YawPitchRoll */
    case 0x51: /* Attitude YawPitchRoll */
        read_f32x3(f, ins->ypr_deg);
        ins->present |= VN200_HAVE_YPR;
        break;
    case 0x15: /* Common AngularRate */
    case 0x3a: /* IMU AngularRate */
        read_f32x3(f, ins->angular_rate_rad_s);
        ins->present |= VN200_HAVE_ANGULAR_RATE;
        break;
    case 0x16: /* Common Position (LLA) */
    case 0x61: /* INS PosLla */
        for (int i = 0; i < 3; i++) {
            ins->lla[i] = le_f64(f + 8 * i);
        }
        ins->present |= VN200_HAVE_POSITION;
        break;
    case 0x17: /* Common Velocity (NED) */
    case 0x64: /* INS VelNed */
        read_f32x3(f, ins->vel_ned_m_s);
        ins->present |= VN200_HAVE_VELOCITY;
        break;
    case 0x18: /* Common Accel */
    case 0x39: /* IMU Accel */
        read_f32x3(f, ins->accel_m_s2);
        ins->present |= VN200_HAVE_ACCEL;
        break;
    case 0x1c: /* Common InsStatus */
    case 0x60: /* INS InsStatus */
        ins->ins_status = le_u16(f);
        ins->present |= VN200_HAVE_INS_STATUS;
        break;
    default:
        break;
    }
}

static void decode(vn200_parser_t *p)
{
    vn200_ins_t ins;
    memset(&ins, 0, sizeof ins);
    const uint8_t *b = p->buf;
    ins.group = b[1];
    uint16_t masks[VN200_GROUPS] = {0};
    size_t idx = 2;
    for (unsigned g = 0; g < VN200_GROUPS; g++) {
        if (ins.group & (1u << g)) {
            masks[g] = le_u16(&b[idx]);
            idx += 2;
        }
    }
    for (unsigned g = 0; g < VN200_GROUPS; g++) {
        for (unsigned bit = 0; bit < 15; bit++) {
            if (masks[g] & (1u << bit)) {
                decode_field(g, bit, &b[idx], &ins);
                idx += field_size[g][bit];
            }
        }
    }
    p->packets++;
    if (p->handler) {
        p->handler(p->ctx, &ins);
    }
}

static void discard(vn200_parser_t *p, size_t k)
{
    resync_discard(p->buf, &p->n, k);
    p->later_syncs = resync_count(p->buf, p->n, VN200_SYNC);
}

static void hunt(vn200_parser_t *p)
{
    p->bytes_dropped += resync_hunt(p->buf, &p->n, VN200_SYNC);
}

/* The packet at the front is still incomplete. If a later sync byte in the buffer
 * starts a packet that the last byte just completed with a valid CRC, the front one was
 * a false start: drop up to the later packet now instead of holding it back until the
 * false length is reached. Each later candidate is CRC-checked once, when complete. */
static int later_packet_completed(vn200_parser_t *p)
{
    if (p->later_syncs == 0) {
        return 0; /* the usual case: no other sync byte since the front one */
    }
    /* visit only the buffered sync bytes (memchr), not every position */
    for (size_t j = 1; j + 2 < p->n; j++) {
        const uint8_t *s = memchr(p->buf + j, VN200_SYNC, p->n - 2 - j);
        if (s == NULL) {
            break;
        }
        j = (size_t)(s - p->buf);
        size_t total = 0;
        if (header(p->buf + j, p->n - j, &total) == HDR_OK && total == p->n - j &&
            crc16_xmodem(p->buf + j + 1, total - 1) == 0) {
            p->bytes_dropped += (uint32_t)j;
            discard(p, j);
            return 1;
        }
    }
    return 0;
}

static void process(vn200_parser_t *p)
{
    while (p->n > 0) {
        size_t total = 0;
        const int h = header(p->buf, p->n, &total);
        if (h == HDR_NEED_MORE) {
            return;
        }
        if (h == HDR_OK && total <= VN200_MAX_PACKET && p->n < total) {
            if (!later_packet_completed(p)) {
                return;
            }
            continue;
        }
        if (h == HDR_OK && total > VN200_MAX_PACKET) {
            p->oversize++;
        } else if (h == HDR_BAD) {
            p->bad_headers++;
        } else if (crc16_xmodem(p->buf + 1, total - 1) == 0) {
            decode(p);
            discard(p, total);
            hunt(p); /* leftovers come from a rescan */
            continue;
        } else {
            p->crc_errors++;
        }
        /* Not a packet: this sync byte was false; rescan what follows it. */
        p->bytes_dropped++;
        discard(p, 1);
        hunt(p);
    }
}

void vn200_parser_feed(vn200_parser_t *p, const uint8_t *data, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        if (p->n == 0 && data[i] != VN200_SYNC) {
            p->bytes_dropped++;
            continue;
        }
        if (p->n > 0 && data[i] == VN200_SYNC) {
            p->later_syncs++;
        }
        p->buf[p->n++] = data[i];
        process(p);
    }
}
