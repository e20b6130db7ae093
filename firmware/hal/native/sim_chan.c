/*
 * sim_chan.c — the channel to hil_sim (docs/sim-channel.md): receive input
 * records and apply them when the clock reaches them ("interrupts"), send output
 * records, and the stepped-mode handshake (ADVANCE -> ... -> IDLE).
 */
#include <errno.h>
#include <sys/select.h>
#include <time.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "native.h"
#include "sim_proto.h"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the sim channel layout is little endian; this backend assumes a little-endian host"
#endif

static int sock = -1;
static uint8_t rx_buf[SIM_MAX_PACKET];
static size_t rx_len;
static size_t rx_pos;
static uint8_t tx_buf[SIM_MAX_PACKET];
static size_t tx_len;
static bool in_step;
static uint64_t step_end;
static uint32_t bad_records;

static uint16_t rd16(const uint8_t *p) { return (uint16_t)(p[0] | (unsigned)p[1] << 8); }

static uint64_t rd64(const uint8_t *p)
{
    uint64_t v;
    memcpy(&v, p, sizeof(v));
    return v;
}

static void wr_header(uint8_t *p, uint8_t type, uint8_t ch, uint16_t len, uint64_t t)
{
    p[0] = type;
    p[1] = ch;
    memcpy(&p[2], &len, sizeof(len));
    memset(&p[4], 0, 4);
    memcpy(&p[8], &t, sizeof(t));
}

static _Noreturn void channel_closed(void)
{
    /* the simulator went away: a SIL board has nothing left to do */
    exit(0);
}

bool chan_connected(void) { return sock >= 0; }

bool chan_connect(const char *path, native_mode_t mode, const char *board_name, uint8_t board_id)
{
    struct sockaddr_un addr;
    if (strlen(path) >= sizeof(addr.sun_path)) {
        fprintf(stderr, "--sim %s: path longer than %zu bytes\n", path, sizeof(addr.sun_path) - 1);
        return false;
    }
    sock = socket(AF_UNIX, SOCK_SEQPACKET, 0);
    if (sock < 0) {
        perror("socket");
        return false;
    }
    memset(&addr, 0, sizeof(addr));
    addr.sun_family = AF_UNIX;
    memcpy(addr.sun_path, path, strlen(path) + 1);
    if (connect(sock, (const struct sockaddr *)&addr, sizeof(addr)) != 0) {
        fprintf(stderr, "--sim %s: cannot connect: %s\n", path, strerror(errno));
        close(sock);
        sock = -1;
        return false;
    }
    int buf = 4 * (int)SIM_MAX_PACKET;
    (void)setsockopt(sock, SOL_SOCKET, SO_SNDBUF, &buf, sizeof(buf));
    (void)setsockopt(sock, SOL_SOCKET, SO_RCVBUF, &buf, sizeof(buf));

    uint8_t hello[SIM_HELLO_BODY] = {0};
    uint32_t magic = SIM_MAGIC;
    uint16_t version = SIM_VERSION;
    memcpy(&hello[0], &magic, 4);
    memcpy(&hello[4], &version, 2);
    hello[6] = (uint8_t)mode;
    hello[7] = board_id;
    strncpy((char *)&hello[8], board_name, 15);
    chan_emit(SIM_HELLO, 0, native_now_sim(), hello, sizeof(hello));
    chan_flush();
    return true;
}

/* Inputs due at t are applied when the clock reaches t; in stepped mode nothing
 * is later than the step's end. */
static uint64_t due_time(const uint8_t *rec)
{
    uint64_t t = rd64(&rec[8]);
    return (in_step && t > step_end) ? step_end : t;
}

uint64_t chan_next_time(void) { return rx_pos < rx_len ? due_time(&rx_buf[rx_pos]) : UINT64_MAX; }

static void bad_record(const char *why, uint8_t type)
{
    if (bad_records++ < 10) {
        fprintf(stderr, "sim channel: record type 0x%02x ignored: %s\n", type, why);
    }
}

static void apply(const uint8_t *rec, size_t len, uint64_t now)
{
    uint8_t type = rec[0];
    uint8_t ch = rec[1];
    const uint8_t *body = &rec[SIM_HEADER_LEN];
    size_t blen = len - SIM_HEADER_LEN;
    switch (type) {
    case SIM_LINE: {
        if (blen != SIM_LINE_BODY || ch >= HAL_ADC_COUNT) {
            bad_record("LINE needs chan < 4 and 1024 body bytes", type);
            return;
        }
        float rate[128];
        float dark[128];
        memcpy(rate, body, sizeof(rate));
        memcpy(dark, body + sizeof(rate), sizeof(dark));
        tsl_emu_set_line(ch, now, rate, dark);
        return;
    }
    case SIM_IMU: {
        if (blen != SIM_IMU_BODY || ch != 0) {
            bad_record("IMU needs chan 0 and 40 body bytes", type);
            return;
        }
        float v[10];
        memcpy(v, body, sizeof(v));
        imu_emu_sample(ch, &v[0], &v[3], &v[6], v[9]);
        return;
    }
    case SIM_EDGE:
        if (blen != SIM_EDGE_BODY || ch >= HAL_CAPTURE_COUNT) {
            bad_record("EDGE needs chan < 7 and 8 body bytes", type);
            return;
        }
        capture_sim_edge((hal_capture_t)ch, now, body[0] ? 1u : 0u);
        return;
    case SIM_UART:
        if (ch >= HAL_PORT_COUNT) {
            bad_record("UART needs chan < 4", type);
            return;
        }
        uart_sim_input((hal_port_t)ch, body, blen);
        return;
    case SIM_RESET:
        native_reboot(HAL_RESET_EXTERNAL);
    case SIM_ADVANCE:
        return; /* wall mode: there is nothing to advance */
    default:
        bad_record("unknown type", type);
        return;
    }
}

bool chan_apply_due(uint64_t now)
{
    bool applied = false;
    while (rx_pos < rx_len && due_time(&rx_buf[rx_pos]) <= now) {
        const uint8_t *rec = &rx_buf[rx_pos];
        size_t len = rd16(&rec[2]);
        rx_pos += len; /* before applying: a RESET does not come back */
        apply(rec, len, now);
        applied = true;
    }
    return applied;
}

/* Checks the framing of a received packet; returns the offset of its last record
 * (or 0 for an empty/invalid packet, with rx_len set to 0). */
static size_t validate_packet(size_t n)
{
    size_t pos = 0;
    size_t last = 0;
    while (pos + SIM_HEADER_LEN <= n) {
        size_t len = rd16(&rx_buf[pos + 2]);
        if (len < SIM_HEADER_LEN || pos + len > n) {
            break;
        }
        last = pos;
        pos += len;
    }
    if (pos != n) {
        fprintf(stderr, "sim channel: malformed packet (%zu of %zu bytes are whole records)\n",
                pos, n);
        n = pos;
    }
    rx_len = n;
    rx_pos = 0;
    return last;
}

bool chan_in_step(void) { return in_step; }

uint64_t chan_step_end(void) { return step_end; }

void chan_step(void)
{
    for (;;) {
        ssize_t n = recv(sock, rx_buf, sizeof(rx_buf), 0);
        if (n == 0) {
            channel_closed();
        }
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            perror("sim channel recv");
            exit(1);
        }
        size_t last = validate_packet((size_t)n);
        if (rx_len == 0 || rx_buf[last] != SIM_ADVANCE) {
            fprintf(stderr, "sim channel: a stepped packet must end with ADVANCE\n");
            exit(3);
        }
        uint64_t t = rd64(&rx_buf[last + 8]);
        uint64_t now = native_clock.now_sim;
        step_end = t > now ? t : now;
        rx_len = last;
        in_step = true;
        return;
    }
}

bool chan_end_step(uint64_t now)
{
    bool rx = uart_service(now);
    chan_emit(SIM_IDLE, 0, now, NULL, 0);
    chan_flush();
    in_step = false;
    rx_len = rx_pos = 0;
    return rx;
}

bool chan_wall_poll(uint64_t timeout_us)
{
    /* pselect, not poll: µs timeouts keep sub-millisecond deadlines (exposure) */
    fd_set rd;
    FD_ZERO(&rd);
    int maxfd = -1;
    bool want_packet = sock >= 0 && rx_pos >= rx_len;
    if (want_packet) {
        FD_SET(sock, &rd);
        maxfd = sock;
    }
    int port_fds[HAL_PORT_COUNT];
    int nports = uart_poll_fds(port_fds, HAL_PORT_COUNT);
    for (int i = 0; i < nports; i++) {
        FD_SET(port_fds[i], &rd);
        maxfd = port_fds[i] > maxfd ? port_fds[i] : maxfd;
    }
    struct timespec ts = {.tv_sec = (time_t)(timeout_us / 1000000u),
                          .tv_nsec = (long)(timeout_us % 1000000u) * 1000L};
    int r = pselect(maxfd + 1, &rd, NULL, NULL, &ts, NULL);
    if (r <= 0) {
        return false;
    }
    if (want_packet && FD_ISSET(sock, &rd)) {
        ssize_t got = recv(sock, rx_buf, sizeof(rx_buf), MSG_DONTWAIT);
        if (got == 0) {
            channel_closed();
        }
        if (got > 0) {
            (void)validate_packet((size_t)got);
        }
    }
    return true;
}

void chan_flush(void)
{
    if (tx_len == 0 || sock < 0) {
        tx_len = 0;
        return;
    }
    for (;;) {
        ssize_t n = send(sock, tx_buf, tx_len, MSG_NOSIGNAL);
        if (n >= 0) {
            break;
        }
        if (errno == EINTR) {
            continue;
        }
        channel_closed(); /* EPIPE / ECONNRESET: the simulator is gone */
    }
    tx_len = 0;
}

void chan_emit(uint8_t type, uint8_t ch, uint64_t t_sim, const void *body, size_t len)
{
    if (sock < 0) {
        return;
    }
    if (len > SIM_MAX_PACKET - SIM_HEADER_LEN || len > UINT16_MAX - SIM_HEADER_LEN) {
        len = UINT16_MAX - SIM_HEADER_LEN; /* callers chunk; this only guards */
    }
    if (tx_len + SIM_HEADER_LEN + len > sizeof(tx_buf)) {
        chan_flush();
    }
    wr_header(&tx_buf[tx_len], type, ch, (uint16_t)(SIM_HEADER_LEN + len), t_sim);
    if (len > 0) {
        memcpy(&tx_buf[tx_len + SIM_HEADER_LEN], body, len);
    }
    tx_len += SIM_HEADER_LEN + len;
}
