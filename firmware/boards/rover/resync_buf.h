/* Receive buffer helpers shared by the byte-stream parsers (VN200, SBP): drop bytes
 * from the front, and hunt for the next sync byte in what is already buffered, so a
 * frame hidden inside a false start is found again (rescan instead of discard). */
#ifndef AW_RESYNC_BUF_H
#define AW_RESYNC_BUF_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

static inline void resync_discard(uint8_t *buf, size_t *n, size_t k)
{
    memmove(buf, buf + k, *n - k);
    *n -= k;
}

/* Drop everything before the next `sync` byte; returns how many bytes were dropped. */
static inline uint32_t resync_hunt(uint8_t *buf, size_t *n, uint8_t sync)
{
    size_t k = 0;
    while (k < *n && buf[k] != sync) {
        k++;
    }
    resync_discard(buf, n, k);
    return (uint32_t)k;
}

/* How many `sync` bytes follow the front byte (candidates for a rescan). */
static inline uint16_t resync_count(const uint8_t *buf, size_t n, uint8_t sync)
{
    uint16_t c = 0;
    for (size_t k = 1; k < n; k++) {
        c = (uint16_t)(c + (buf[k] == sync));
    }
    return c;
}

#endif
