/*
 * board_link.h — what every board does on its protocol link, in one place:
 * frames out (per-message sequence numbers, origin board in the flags), the HELLO
 * heartbeat with counters at 1 Hz followed by the board's stamp_latency entries, the
 * schema_entry round robin (all entries at boot, then one every 250 ms), host frames in (streaming decoder), time-sync
 * replies, and a persistent boot counter.
 *
 * Board-specific host frames (losa_raw_request, marker_command) go to the board's
 * handler. Uses only the HAL and the protocol code (aw_frame.h, aw_messages.h).
 */
#ifndef AW_BOARD_LINK_H
#define AW_BOARD_LINK_H

#include <stdbool.h>
#include <stdint.h>

#include "aw_frame.h"
#include "aw_messages.h"
#include "hal.h"

#define BOARD_LINK_HEARTBEAT_US 1000000u
#define BOARD_LINK_SCHEMA_US 250000u
/* Persistent config layout used by the link: [0..3] magic, [4..7] boot count. */
#define BOARD_LINK_CONFIG_MAGIC 0x43425741u /* "AWBC" */

/* What one message's board_time_us marks and how long after the sample instant of its
 * data that is, from the board's own constants (sent as stamp_latency entries). */
typedef struct {
    uint8_t msg_id;
    uint8_t stamp_event; /* AW_STAMP_LATENCY_STAMP_EVENT_* */
    uint32_t latency_us;
} board_stamp_t;

typedef void (*board_link_rx_t)(void *ctx, const aw_frame_t *frame);
typedef void (*board_link_tap_t)(void *ctx, const uint8_t *data, size_t len);

typedef struct {
    const hal_t *hal;
    hal_port_t port;
    uint8_t board_id;
    const uint8_t *ids; /* message ids this board sends or receives (its schema) */
    uint8_t id_count;
    uint8_t next_entry;
    bool announce_all;  /* send every schema entry on the next poll (boot) */
    const board_stamp_t *stamps; /* declared after every heartbeat (stamp_latency) */
    uint8_t stamp_count;
    uint8_t seq[256];   /* next sequence number per msg_id */
    uint32_t frames_sent;
    uint32_t bytes_sent;
    uint32_t reserve_dropped; /* bytes of data frames held back to keep room for control */
    uint32_t boot_count;
    uint8_t reset_cause;
    uint64_t next_heartbeat_us;
    uint64_t next_schema_us;
    uint64_t task_start_us;
    uint32_t task_max_us;
    uint64_t rx_time_us; /* when the bytes being decoded were read */
    board_link_rx_t on_rx;
    board_link_tap_t on_bytes; /* optional: every byte read from the port (base relay) */
    void *ctx;
    aw_decoder_t dec;
} board_link_t;

/* Sets up the link; bumps the persistent boot counter. The first poll sends the
 * HELLO and every schema entry. */
void board_link_init(board_link_t *l, const hal_t *hal, uint8_t board_id, hal_port_t port,
                     const uint8_t *ids, uint8_t id_count, board_link_rx_t on_rx, void *ctx);

/* The board's stamp declarations (a static table): one stamp_latency entry each after
 * every heartbeat, the first right after the HELLO. */
void board_link_declare_stamps(board_link_t *l, const board_stamp_t *stamps, uint8_t count);

/* Encodes and queues one message (msg points to its aw_<name>_t). False when the
 * port's transmit ring had no room (the bytes are counted in the heartbeat's
 * tx_bytes_dropped; the sequence number still advances, so the host sees the gap).
 * Data frames leave room for the heartbeat, schema entries and time-sync replies,
 * so those get through a saturated link. */
bool board_link_send(board_link_t *l, uint8_t msg_id, const void *msg, uint32_t board_time_us);

/* Reads and decodes host frames, answers time sync, sends heartbeat/schema when
 * due. extra_overruns: the board's own lost samples (capture rings, parsers) for
 * the heartbeat's buffer_overruns. Returns the link's next deadline (µs). */
uint64_t board_link_poll(board_link_t *l, uint32_t extra_overruns);

/* The k-th tick of a rate_hz schedule that started at t0 (µs): no rounding builds up. */
static inline uint64_t board_tick_us(uint64_t t0, uint32_t k, uint32_t rate_hz)
{
    return t0 + ((uint64_t)k * 1000000u + rate_hz - 1u) / rate_hz;
}

/* True when tick *k is due at now; then *k moves past now (ticks missed while the
 * board was busy are skipped, not bunched). */
static inline bool board_tick_due(uint64_t t0, uint32_t *k, uint32_t rate_hz, uint64_t now)
{
    if (now < board_tick_us(t0, *k, rate_hz)) {
        return false;
    }
    do {
        (*k)++;
    } while (board_tick_us(t0, *k, rate_hz) <= now);
    return true;
}

/* Brackets one board_task() pass for the heartbeat's task_max_us. */
void board_link_task_begin(board_link_t *l);
void board_link_task_end(board_link_t *l);

#endif /* AW_BOARD_LINK_H */
