/* board_link.c — see board_link.h. */
#include "board_link.h"

#include <string.h>

#define FW_VERSION_MAJOR 0
#define FW_VERSION_MINOR 1
#define FW_VERSION_PATCH 0

static uint32_t load_boot_count(const hal_t *hal)
{
    uint32_t cfg[2];
    uint32_t count = 0;
    if (hal->config_read(0, cfg, sizeof(cfg)) && cfg[0] == BOARD_LINK_CONFIG_MAGIC) {
        count = cfg[1] + 1u;
    }
    cfg[0] = BOARD_LINK_CONFIG_MAGIC;
    cfg[1] = count;
    (void)hal->config_write(0, cfg, sizeof(cfg));
    return count;
}

static void on_frame(void *ctx, const aw_frame_t *f);

void board_link_init(board_link_t *l, const hal_t *hal, uint8_t board_id, hal_port_t port,
                     const uint8_t *ids, uint8_t id_count, board_link_rx_t on_rx, void *ctx)
{
    memset(l, 0, sizeof(*l));
    l->hal = hal;
    l->port = port;
    l->board_id = board_id;
    l->ids = ids;
    l->id_count = id_count;
    l->announce_all = true;
    l->on_rx = on_rx;
    l->ctx = ctx;
    l->boot_count = load_boot_count(hal);
    l->reset_cause = (uint8_t)hal->reset_cause();
    uint64_t now = hal->micros();
    l->next_heartbeat_us = now;
    l->next_schema_us = now + BOARD_LINK_SCHEMA_US;
    aw_decoder_init(&l->dec, on_frame, l);
}

/* Room kept free for the link's own frames: when data saturates the port, the
 * heartbeat that reports the drops still gets through. */
#define CONTROL_RESERVE (AW_WIRE_MAX_HEARTBEAT + AW_WIRE_MAX_SCHEMA_ENTRY + AW_WIRE_MAX_TIME_SYNC_REPLY)

static bool is_control(uint8_t msg_id)
{
    return msg_id == AW_ID_HEARTBEAT || msg_id == AW_ID_SCHEMA_ENTRY ||
           msg_id == AW_ID_TIME_SYNC_REPLY;
}

bool board_link_send(board_link_t *l, uint8_t msg_id, const void *msg, uint32_t board_time_us)
{
    uint8_t wire[AW_MAX_WIRE_SIZE];
    int n = aw_encode_msg(wire, sizeof(wire), msg_id, l->seq[msg_id]++,
                          (uint8_t)(l->board_id & AW_FLAGS_ORIGIN_MASK), board_time_us, msg);
    if (n <= 0) {
        return false;
    }
    if (!is_control(msg_id) && l->hal->uart_tx_free(l->port) < (size_t)n + CONTROL_RESERVE) {
        l->reserve_dropped += (uint32_t)n; /* counted here: the HAL never saw it */
        return false;
    }
    if (!l->hal->uart_write(l->port, wire, (size_t)n)) {
        return false;
    }
    l->frames_sent++;
    l->bytes_sent += (uint32_t)n;
    return true;
}

static void send_schema_entry(board_link_t *l, uint8_t index)
{
    const aw_msg_info_t *info = aw_msg_info(l->ids[index]);
    if (info == NULL) {
        return;
    }
    aw_schema_entry_t e = {
        .msg_id = info->id,
        .def_hash = info->def_hash,
        .entry_index = index,
        .entry_count = l->id_count,
    };
    (void)board_link_send(l, AW_ID_SCHEMA_ENTRY, &e, (uint32_t)l->hal->micros());
}

void board_link_declare_stamps(board_link_t *l, const board_stamp_t *stamps, uint8_t count)
{
    l->stamps = stamps;
    l->stamp_count = count;
}

static void send_stamps(board_link_t *l)
{
    for (uint8_t i = 0; i < l->stamp_count; i++) {
        const board_stamp_t *s = &l->stamps[i];
        aw_stamp_latency_t e = {
            .msg_id = s->msg_id,
            .latency_us = s->latency_us,
            .stamp_event = s->stamp_event,
            .entry_index = i,
            .entry_count = l->stamp_count,
        };
        (void)board_link_send(l, AW_ID_STAMP_LATENCY, &e, (uint32_t)l->hal->micros());
    }
}

static void send_heartbeat(board_link_t *l, uint32_t extra_overruns)
{
    const hal_t *hal = l->hal;
    uint64_t now = hal->micros();
    aw_heartbeat_t hb = {
        .board_id = l->board_id,
        .fw_version_major = FW_VERSION_MAJOR,
        .fw_version_minor = FW_VERSION_MINOR,
        .fw_version_patch = FW_VERSION_PATCH,
        .schema_hash = AW_SCHEMA_HASH,
        .uptime_ms = (uint32_t)(now / 1000u),
        .boot_count = l->boot_count,
        .reset_cause = l->reset_cause,
        .rx_frames_ok = l->dec.counters.frames_ok,
        .rx_crc_error = l->dec.counters.crc_error,
        .rx_unknown_id = l->dec.counters.unknown_id,
        .rx_def_mismatch = l->dec.counters.def_mismatch,
        .rx_cobs_error = l->dec.counters.cobs_error,
        .rx_oversize = l->dec.counters.oversize,
        .rx_bytes_dropped = l->dec.counters.bytes_dropped,
        .buffer_overruns = extra_overruns,
        .task_max_us = l->task_max_us,
        .tx_bytes_dropped = l->reserve_dropped,
    };
    for (int p = 0; p < HAL_PORT_COUNT; p++) {
        hal_port_stats_t st;
        hal->uart_stats((hal_port_t)p, &st);
        hb.buffer_overruns += st.rx_overruns;
        hb.tx_bytes_dropped += st.tx_dropped;
    }
    /* counted before queueing, so the HELLO includes itself */
    hb.frames_sent = l->frames_sent + 1u;
    hb.bytes_sent = l->bytes_sent;
    (void)board_link_send(l, AW_ID_HEARTBEAT, &hb, (uint32_t)now);
    l->task_max_us = 0;
}

static void answer_time_sync(board_link_t *l, const aw_frame_t *f)
{
    aw_time_sync_request_t req;
    if (aw_unpack_msg(AW_ID_TIME_SYNC_REQUEST, &req, f->payload, f->payload_len) < 0) {
        return;
    }
    uint64_t now = l->hal->micros();
    aw_time_sync_reply_t rep = {
        .request_id = req.request_id,
        .host_time_us = req.host_time_us,
        .board_rx_time_us = l->rx_time_us,
        .board_tx_time_us = now,
    };
    (void)board_link_send(l, AW_ID_TIME_SYNC_REPLY, &rep, (uint32_t)now);
}

static void on_frame(void *ctx, const aw_frame_t *f)
{
    board_link_t *l = ctx;
    switch (f->header.msg_id) {
    case AW_ID_SCHEMA_ENTRY: {
        aw_schema_entry_t e;
        if (aw_unpack_msg(AW_ID_SCHEMA_ENTRY, &e, f->payload, f->payload_len) >= 0) {
            aw_decoder_announce(&l->dec, e.msg_id, e.def_hash);
        }
        return;
    }
    case AW_ID_TIME_SYNC_REQUEST:
        answer_time_sync(l, f);
        return;
    default:
        if (l->on_rx != NULL) {
            l->on_rx(l->ctx, f);
        }
        return;
    }
}

uint64_t board_link_poll(board_link_t *l, uint32_t extra_overruns)
{
    const hal_t *hal = l->hal;
    uint8_t buf[128];
    size_t n;
    l->rx_time_us = hal->micros();
    while ((n = hal->uart_read(l->port, buf, sizeof(buf))) > 0) {
        if (l->on_bytes != NULL) {
            l->on_bytes(l->ctx, buf, n);
        }
        (void)aw_decoder_feed(&l->dec, buf, n);
    }
    uint64_t now = hal->micros();
    if (now >= l->next_heartbeat_us) {
        send_heartbeat(l, extra_overruns);
        send_stamps(l);
        l->next_heartbeat_us += BOARD_LINK_HEARTBEAT_US;
        if (l->next_heartbeat_us <= now) {
            l->next_heartbeat_us = now + BOARD_LINK_HEARTBEAT_US;
        }
    }
    if (l->announce_all) {
        for (uint8_t i = 0; i < l->id_count; i++) {
            send_schema_entry(l, i);
        }
        l->announce_all = false;
    } else if (now >= l->next_schema_us && l->id_count > 0) {
        send_schema_entry(l, l->next_entry);
        l->next_entry = (uint8_t)((l->next_entry + 1u) % l->id_count);
        l->next_schema_us += BOARD_LINK_SCHEMA_US;
        if (l->next_schema_us <= now) {
            l->next_schema_us = now + BOARD_LINK_SCHEMA_US;
        }
    }
    return l->next_heartbeat_us < l->next_schema_us ? l->next_heartbeat_us : l->next_schema_us;
}

void board_link_task_begin(board_link_t *l) { l->task_start_us = l->hal->micros(); }

void board_link_task_end(board_link_t *l)
{
    uint64_t took = l->hal->micros() - l->task_start_us;
    uint32_t us = took > UINT32_MAX ? UINT32_MAX : (uint32_t)took;
    if (us > l->task_max_us) {
        l->task_max_us = us;
    }
}
