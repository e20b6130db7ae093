/* Helpers shared by the libFuzzer targets: an independent CRC-16/XMODEM, an
 * FNV-1a hash to compare packet sequences, a reader that turns the fuzz input into a
 * recipe of choices (zeros once it runs out), and the check that aborts on a broken
 * invariant with a message (libFuzzer then saves the input as crash-*). */
#ifndef AW_FUZZ_UTIL_H
#define AW_FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#define FUZZ_CHECK(cond)                                                              \
    do {                                                                              \
        if (!(cond)) {                                                                \
            fprintf(stderr, "%s:%d: invariant broken: %s\n", __FILE__, __LINE__, #cond); \
            abort();                                                                  \
        }                                                                             \
    } while (0)

/* CRC-16/XMODEM, poly 0x1021, init 0: a table made here bit by bit (not the parsers'
 * crc16_xmodem.c table). */
static inline uint16_t fuzz_crc_xmodem(const uint8_t *p, size_t n)
{
    static uint16_t table[256];
    static int ready;
    if (!ready) {
        for (unsigned v = 0; v < 256; v++) {
            uint16_t c = (uint16_t)(v << 8);
            for (int b = 0; b < 8; b++) {
                c = (uint16_t)((c & 0x8000u) ? (c << 1) ^ 0x1021u : c << 1);
            }
            table[v] = c;
        }
        ready = 1;
    }
    uint16_t crc = 0;
    for (size_t i = 0; i < n; i++) {
        crc = (uint16_t)((crc << 8) ^ table[((crc >> 8) ^ p[i]) & 0xFFu]);
    }
    return crc;
}

static inline uint64_t fuzz_fnv(uint64_t h, const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        h = (h ^ p[i]) * 0x100000001b3ull;
    }
    return h;
}
#define FUZZ_FNV_INIT 0xcbf29ce484222325ull

typedef struct {
    const uint8_t *data;
    size_t size, at;
} fuzz_reader_t;

static inline uint8_t fuzz_u8(fuzz_reader_t *r)
{
    return r->at < r->size ? r->data[r->at++] : 0u;
}

static inline uint16_t fuzz_u16(fuzz_reader_t *r)
{
    const uint8_t lo = fuzz_u8(r);
    return (uint16_t)(lo | (fuzz_u8(r) << 8));
}

/* A byte of the recipe that is never `sync` (so a built stream has no false starts). */
static inline uint8_t fuzz_not(fuzz_reader_t *r, uint8_t sync)
{
    const uint8_t b = fuzz_u8(r);
    return b == sync ? (uint8_t)(b + 1u) : b;
}

#endif
