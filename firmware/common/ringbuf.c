/* ringbuf.c — see ringbuf.h. */
#include "ringbuf.h"

#include <string.h>

/* Orders the slot write before the index store that publishes it (and the index
 * load before the slot read). A compiler barrier is enough on a single core
 * (Cortex-M4 executes in order); the native backend is single-threaded. */
#define RB_BARRIER() __atomic_signal_fence(__ATOMIC_SEQ_CST)

bool ringbuf_init(ringbuf_t *rb, void *storage, uint32_t capacity, uint16_t elem)
{
    memset(rb, 0, sizeof(*rb));
    if (storage == NULL || elem == 0 || capacity < 2 || (capacity & (capacity - 1u)) != 0) {
        return false;
    }
    rb->buf = storage;
    rb->mask = capacity - 1u;
    rb->elem = elem;
    return true;
}

uint32_t ringbuf_capacity(const ringbuf_t *rb) { return rb->mask + 1u; }

uint32_t ringbuf_count(const ringbuf_t *rb) { return rb->head - rb->tail; }

uint32_t ringbuf_free(const ringbuf_t *rb) { return ringbuf_capacity(rb) - ringbuf_count(rb); }

bool ringbuf_put(ringbuf_t *rb, const void *elem)
{
    uint32_t head = rb->head;
    if (head - rb->tail > rb->mask) {
        rb->overruns++;
        return false;
    }
    memcpy(&rb->buf[(size_t)(head & rb->mask) * rb->elem], elem, rb->elem);
    RB_BARRIER();
    rb->head = head + 1u;
    return true;
}

static size_t copy_in(ringbuf_t *rb, const uint8_t *data, size_t n)
{
    uint32_t head = rb->head;
    size_t room = ringbuf_capacity(rb) - (size_t)(head - rb->tail);
    if (n > room) {
        n = room;
    }
    size_t at = head & rb->mask;
    size_t first = ringbuf_capacity(rb) - at;
    if (first > n) {
        first = n;
    }
    memcpy(&rb->buf[at], data, first);
    memcpy(&rb->buf[0], data + first, n - first);
    RB_BARRIER();
    rb->head = head + (uint32_t)n;
    return n;
}

size_t ringbuf_write(ringbuf_t *rb, const uint8_t *data, size_t n)
{
    size_t done = copy_in(rb, data, n);
    rb->overruns += (uint32_t)(n - done);
    return done;
}

bool ringbuf_write_all(ringbuf_t *rb, const uint8_t *data, size_t n)
{
    if (n > ringbuf_free(rb)) {
        return false;
    }
    copy_in(rb, data, n);
    return true;
}

bool ringbuf_get(ringbuf_t *rb, void *elem)
{
    uint32_t tail = rb->tail;
    if (rb->head == tail) {
        return false;
    }
    RB_BARRIER();
    memcpy(elem, &rb->buf[(size_t)(tail & rb->mask) * rb->elem], rb->elem);
    RB_BARRIER();
    rb->tail = tail + 1u;
    return true;
}

const uint8_t *ringbuf_peek_contig(const ringbuf_t *rb, size_t *len)
{
    uint32_t tail = rb->tail;
    size_t avail = (size_t)(rb->head - tail);
    size_t at = tail & rb->mask;
    size_t first = ringbuf_capacity(rb) - at;
    RB_BARRIER();
    *len = avail < first ? avail : first;
    return &rb->buf[at];
}

void ringbuf_consume(ringbuf_t *rb, size_t n)
{
    size_t avail = ringbuf_count(rb);
    if (n > avail) {
        n = avail;
    }
    RB_BARRIER();
    rb->tail += (uint32_t)n;
}

size_t ringbuf_read(ringbuf_t *rb, uint8_t *out, size_t cap)
{
    size_t done = 0;
    while (done < cap) {
        size_t run;
        const uint8_t *p = ringbuf_peek_contig(rb, &run);
        if (run == 0) {
            break;
        }
        if (run > cap - done) {
            run = cap - done;
        }
        memcpy(out + done, p, run);
        ringbuf_consume(rb, run);
        done += run;
    }
    return done;
}

void ringbuf_clear(ringbuf_t *rb)
{
    RB_BARRIER();
    rb->tail = rb->head;
}
