/* young81000.c — see young81000.h. */
#include "young81000.h"

#include <string.h>

void young_init(young_parser_t *p)
{
    memset(p, 0, sizeof(*p));
}

static bool is_sep(char c)
{
    return c == ' ' || c == ',' || c == '\t';
}

/* One decimal number at *s: [+-]digits[.digits] (at least one digit, at most 9 in all).
 * Advances *s past it; false when malformed. */
static bool parse_number(const char **s, float *out)
{
    const char *c = *s;
    bool neg = false;
    if (*c == '+' || *c == '-') {
        neg = *c == '-';
        c++;
    }
    uint32_t mant = 0;
    int digits = 0;
    int frac = 0;
    bool point = false;
    for (;; c++) {
        if (*c >= '0' && *c <= '9') {
            if (++digits > 9) {
                return false;
            }
            mant = mant * 10u + (uint32_t)(*c - '0');
            frac += point;
        } else if (*c == '.' && !point) {
            point = true;
        } else {
            break;
        }
    }
    if (digits == 0 || (*c != '\0' && !is_sep(*c))) {
        return false;
    }
    float v = (float)mant;
    static const float scale[] = {1.0f, 1e-1f, 1e-2f, 1e-3f, 1e-4f, 1e-5f,
                                  1e-6f, 1e-7f, 1e-8f, 1e-9f};
    v *= scale[frac];
    *out = neg ? -v : v;
    *s = c;
    return true;
}

/* The fields of a complete line; false when it is not 4 or 5 numbers. */
static bool parse_line(const char *line, young_sample_t *s)
{
    float f[5];
    int n = 0;
    const char *c = line;
    for (;;) {
        while (is_sep(*c)) {
            c++;
        }
        if (*c == '\0') {
            break;
        }
        if (n == 5 || !parse_number(&c, &f[n])) {
            return false;
        }
        n++;
    }
    if (n < 4) {
        return false;
    }
    if (n == 5 && (f[4] < 0.0f || f[4] > 255.0f || f[4] != (float)(uint32_t)f[4])) {
        return false;
    }
    s->uvw_m_s[0] = f[0];
    s->uvw_m_s[1] = f[1];
    s->uvw_m_s[2] = -f[2]; /* W up -> z down */
    s->temp_c = f[3];
    s->status = n == 5 ? (uint8_t)f[4] : 0u;
    return true;
}

size_t young_feed(young_parser_t *p, const uint8_t *data, size_t len, uint64_t t_us,
                  young_sample_t *out, size_t cap, size_t *consumed)
{
    size_t n = 0;
    size_t i = 0;
    for (; i < len; i++) {
        char c = (char)data[i];
        if (c == '\n') {
            if (p->overflow) {
                p->lines_bad++;
            } else if (p->len > 0) {
                if (n == cap) {
                    break; /* keep the line: the caller drains and feeds the rest */
                }
                p->line[p->len] = '\0';
                young_sample_t s;
                if (parse_line(p->line, &s)) {
                    s.t_us = p->line_t_us;
                    out[n++] = s;
                    p->lines_ok++;
                } else {
                    p->lines_bad++;
                }
            }
            p->len = 0;
            p->overflow = false;
            p->bytes++;
            continue;
        }
        p->bytes++;
        if (c == '\r') {
            continue;
        }
        if (p->len == 0 && !p->overflow) {
            p->line_t_us = t_us;
        }
        if (p->overflow) {
            continue;
        }
        if (p->len == YOUNG_LINE_MAX || (unsigned char)c < 0x20u || (unsigned char)c > 0x7eu) {
            p->overflow = true; /* too long or binary garbage: skip to the next line */
            p->len = 0;
            continue;
        }
        p->line[p->len++] = c;
    }
    if (consumed != NULL) {
        *consumed = i;
    }
    return n;
}
