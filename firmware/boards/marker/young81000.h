/* young81000.h — the Young 81000 ultrasonic anemometer's ASCII serial output (reference
 * §3.4: the anemometer rides with the marker during wind mapping).
 *
 * The 81000 is configured for its custom ASCII output, one line per sample:
 *     "U V W T\r\n"   e.g. "   1.25   -0.40    0.07   21.36\r\n"
 * U, V along the instrument's x and y, W positive UPWARD (as Young reports it), T the
 * sonic temperature in degC; optionally a fifth field, the instrument's error code
 * (0 = ok). Numbers are plain decimals (sign, digits, point, digits), separated by
 * spaces or commas.
 *
 * The parser takes bytes as they arrive and the board time of each chunk; a sample is
 * stamped with the time its line's first byte was read. Lines that are too long, have a
 * malformed number, or the wrong field count are counted and skipped; the next line
 * parses normally (resync on '\n'). The output is in the instrument's x, y, z-down axes
 * (w = -W), the frame the host's flight table uses (anemo_u/v/w_m_s).
 */
#ifndef AW_YOUNG81000_H
#define AW_YOUNG81000_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define YOUNG_LINE_MAX 64u /* longest accepted line, without CR/LF */
#define YOUNG_BAUD 38400u  /* the 81000's serial output as configured */
/* The 81000 starts a line at its output instant; the board stamps the line when its
 * first byte has been read: one byte time (8N1: 10 bits) after it. Declared to the host. */
#define YOUNG_STAMP_LATENCY_US ((10u * 1000000u + YOUNG_BAUD / 2u) / YOUNG_BAUD)

typedef struct {
    float uvw_m_s[3]; /* instrument x, y, z DOWN */
    float temp_c;
    uint8_t status;   /* the instrument's error code (0 when the line has none) */
    uint64_t t_us;    /* board time of the line's first byte */
} young_sample_t;

typedef struct {
    char line[YOUNG_LINE_MAX + 1];
    uint8_t len;
    bool overflow;     /* the current line is too long: skip to '\n' */
    uint64_t line_t_us;
    uint32_t lines_ok;
    uint32_t lines_bad; /* malformed, too long or wrong field count */
    uint32_t bytes;
} young_parser_t;

void young_init(young_parser_t *p);

/* Feed len bytes read at board time t_us. Complete samples go to out (at most cap);
 * returns how many. Bytes after the last complete line stay buffered. */
size_t young_feed(young_parser_t *p, const uint8_t *data, size_t len, uint64_t t_us,
                  young_sample_t *out, size_t cap, size_t *consumed);

#endif /* AW_YOUNG81000_H */
