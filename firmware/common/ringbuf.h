/*
 * ringbuf.h — single-producer / single-consumer ring buffer for interrupt
 * handlers and the board task (STYLE 4, 5).
 *
 * One side (an ISR, or the native backend's I/O pump) only puts, the other (the
 * board task) only gets. Indices run freely and wrap; the capacity is a power of
 * two so `index & mask` is the slot. Nothing is allocated: the caller gives the
 * storage. A put that does not fit is counted in `overruns`, never silent.
 *
 * Elements are `elem` bytes (1 for UART rings, sizeof(hal_edge_t) for capture
 * rings). The byte helpers (ringbuf_write/read/...) need elem == 1.
 */
#ifndef AW_RINGBUF_H
#define AW_RINGBUF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint8_t *buf;
    uint32_t mask;              /* capacity - 1 */
    uint16_t elem;              /* bytes per element */
    volatile uint32_t head;     /* next slot to write; written by the producer only */
    volatile uint32_t tail;     /* next slot to read; written by the consumer only */
    volatile uint32_t overruns; /* elements the producer could not store */
} ringbuf_t;

/* capacity (in elements) must be a power of two >= 2; storage holds capacity*elem
 * bytes. Returns false (and leaves rb unusable) when the capacity is invalid. */
bool ringbuf_init(ringbuf_t *rb, void *storage, uint32_t capacity, uint16_t elem);

uint32_t ringbuf_capacity(const ringbuf_t *rb);
uint32_t ringbuf_count(const ringbuf_t *rb);
uint32_t ringbuf_free(const ringbuf_t *rb);

/* Producer side. */
bool ringbuf_put(ringbuf_t *rb, const void *elem);                  /* false: full, counted */
size_t ringbuf_write(ringbuf_t *rb, const uint8_t *data, size_t n); /* stores what fits, counts the rest */
bool ringbuf_write_all(ringbuf_t *rb, const uint8_t *data, size_t n); /* all or nothing, not counted */

/* Consumer side. */
bool ringbuf_get(ringbuf_t *rb, void *elem);
size_t ringbuf_read(ringbuf_t *rb, uint8_t *out, size_t cap);
/* Zero-copy draining: the longest contiguous readable run, then consume n of it. */
const uint8_t *ringbuf_peek_contig(const ringbuf_t *rb, size_t *len);
void ringbuf_consume(ringbuf_t *rb, size_t n);
void ringbuf_clear(ringbuf_t *rb); /* drop everything readable (consumer side) */

#endif /* AW_RINGBUF_H */
