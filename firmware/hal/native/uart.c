/*
 * uart.c — serial ports by role for the native backend.
 *
 * A role is mapped on the command line to either a path (a pty slave the host
 * opens like /dev/ttyACM0; raw mode, non-blocking) or to "sim" (bytes travel on
 * the sim channel as UART / UART_TX records — deterministic in stepped mode).
 * An optional @BAUD throttles transmission to baud/10 bytes per second of board
 * time, so a link budget that does not fit shows up as tx_dropped, as on the
 * real UART. Ring sizes match the teensy32 backend.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <termios.h>
#include <unistd.h>

#include "native.h"
#include "ringbuf.h"
#include "sim_proto.h"

#define RX_RING 1024u
#define TX_RING 4096u
#define SIM_CHUNK 4096u
#define CREDIT_UNIT 10000000ull /* baud * µs / 1e7 = bytes (10 bits per byte) */

typedef enum { PORT_NONE = 0, PORT_FD, PORT_SIM } port_kind_t;

typedef struct {
    port_kind_t kind;
    int fd;
    bool fd_ok; /* last read did not fail (a pty with no host attached returns EIO) */
    uint32_t baud;
    uint64_t credit;   /* bytes * CREDIT_UNIT the line may still send */
    uint64_t last_sim; /* time of the last service */
    ringbuf_t rx;
    ringbuf_t tx;
    uint8_t rx_mem[RX_RING];
    uint8_t tx_mem[TX_RING];
    hal_port_stats_t st;
} port_t;

static port_t ports[HAL_PORT_COUNT];

static const char *const role_names[HAL_PORT_COUNT] = {"host", "ins", "rtk", "rover", "anemo"};

static bool set_raw(int fd)
{
    struct termios t;
    if (tcgetattr(fd, &t) != 0) {
        return false;
    }
    /* what cfmakeraw does, spelled out in POSIX terms: no CR/LF rewriting, no echo */
    t.c_iflag &= (tcflag_t) ~(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL | IXON);
    t.c_oflag &= (tcflag_t)~OPOST;
    t.c_lflag &= (tcflag_t) ~(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
    t.c_cflag &= (tcflag_t) ~(CSIZE | PARENB);
    t.c_cflag |= CS8;
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    return tcsetattr(fd, TCSANOW, &t) == 0;
}

bool uart_map(const char *spec, char *err, size_t err_len)
{
    const char *eq = strchr(spec, '=');
    if (eq == NULL) {
        snprintf(err, err_len, "--port %s: expected ROLE=PATH[@BAUD] or ROLE=sim", spec);
        return false;
    }
    int role = -1;
    for (int i = 0; i < HAL_PORT_COUNT; i++) {
        if (strlen(role_names[i]) == (size_t)(eq - spec) &&
            strncasecmp(spec, role_names[i], (size_t)(eq - spec)) == 0) {
            role = i;
        }
    }
    if (role < 0) {
        snprintf(err, err_len, "--port %s: unknown role (host, ins, rtk, rover, anemo)", spec);
        return false;
    }
    char path[512];
    snprintf(path, sizeof(path), "%s", eq + 1);
    uint32_t baud = 0;
    char *at = strrchr(path, '@');
    if (at != NULL) {
        char *end = NULL;
        unsigned long b = strtoul(at + 1, &end, 10);
        if (end == at + 1 || *end != '\0' || b == 0 || b > 100000000ul) {
            snprintf(err, err_len, "--port %s: bad baud rate '%s'", spec, at + 1);
            return false;
        }
        baud = (uint32_t)b;
        *at = '\0';
    }
    port_t *p = &ports[role];
    if (p->kind != PORT_NONE) {
        snprintf(err, err_len, "--port %s: role given twice", spec);
        return false;
    }
    if (strcmp(path, "sim") == 0) {
        p->kind = PORT_SIM;
    } else {
        int fd = open(path, O_RDWR | O_NOCTTY | O_NONBLOCK);
        if (fd < 0) {
            snprintf(err, err_len, "--port %s: cannot open %s: %s", spec, path, strerror(errno));
            return false;
        }
        if (isatty(fd) && !set_raw(fd)) {
            snprintf(err, err_len, "--port %s: cannot set raw mode on %s", spec, path);
            close(fd);
            return false;
        }
        p->kind = PORT_FD;
        p->fd = fd;
        p->fd_ok = true;
    }
    p->baud = baud;
    ringbuf_init(&p->rx, p->rx_mem, RX_RING, 1);
    ringbuf_init(&p->tx, p->tx_mem, TX_RING, 1);
    return true;
}

void uart_reset(void)
{
    for (int i = 0; i < HAL_PORT_COUNT; i++) {
        port_t *p = &ports[i];
        if (p->kind == PORT_NONE) {
            memset(&p->st, 0, sizeof(p->st));
            continue;
        }
        ringbuf_init(&p->rx, p->rx_mem, RX_RING, 1);
        ringbuf_init(&p->tx, p->tx_mem, TX_RING, 1);
        memset(&p->st, 0, sizeof(p->st));
        p->credit = 0;
    }
}

static void rx_store(port_t *p, const uint8_t *data, size_t len)
{
    size_t stored = ringbuf_write(&p->rx, data, len);
    p->st.rx_bytes += (uint32_t)stored;
}

void uart_sim_input(hal_port_t port, const uint8_t *data, size_t len)
{
    port_t *p = &ports[port];
    if (p->kind != PORT_SIM) {
        /* nothing is wired to this role: the bytes fall on the floor, as on a board */
        return;
    }
    rx_store(p, data, len);
}

/* How many bytes the line may send now; refills with elapsed board time. */
static size_t tx_budget(port_t *p, uint64_t now_sim)
{
    if (p->baud == 0) {
        p->last_sim = now_sim;
        return SIZE_MAX;
    }
    uint64_t dt = now_sim > p->last_sim ? now_sim - p->last_sim : 0;
    p->last_sim = now_sim;
    p->credit += dt * p->baud;
    uint64_t cap = (uint64_t)TX_RING * CREDIT_UNIT;
    if (p->credit > cap) {
        p->credit = cap;
    }
    return (size_t)(p->credit / CREDIT_UNIT);
}

static void tx_spent(port_t *p, size_t n)
{
    if (p->baud != 0) {
        p->credit -= (uint64_t)n * CREDIT_UNIT;
        if (ringbuf_count(&p->tx) == 0) {
            p->credit = 0; /* an idle line does not bank time */
        }
    }
}

static void service_tx(port_t *p, hal_port_t role, uint64_t now_sim)
{
    size_t budget = tx_budget(p, now_sim);
    size_t sent = 0;
    while (sent < budget) {
        size_t run;
        const uint8_t *data = ringbuf_peek_contig(&p->tx, &run);
        if (run == 0) {
            break;
        }
        if (run > budget - sent) {
            run = budget - sent;
        }
        if (p->kind == PORT_SIM) {
            if (run > SIM_CHUNK) {
                run = SIM_CHUNK;
            }
            chan_emit(SIM_UART_TX, (uint8_t)role, now_sim, data, run);
        } else {
            ssize_t n = write(p->fd, data, run);
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
                break; /* the host is not reading: bytes wait in the ring */
            }
            if (n >= 0) {
                run = (size_t)n;
            } /* else: nobody on the line (EIO): the bytes go out into the void */
        }
        ringbuf_consume(&p->tx, run);
        sent += run;
        if (run == 0) {
            break;
        }
    }
    tx_spent(p, sent);
}

static bool service_rx(port_t *p)
{
    bool got = false;
    for (;;) {
        uint8_t buf[1024];
        size_t room = ringbuf_free(&p->rx);
        if (room == 0) {
            return got; /* the rest waits in the kernel until the board reads */
        }
        ssize_t n = read(p->fd, buf, room < sizeof(buf) ? room : sizeof(buf));
        if (n > 0) {
            rx_store(p, buf, (size_t)n);
            p->fd_ok = true;
            got = true;
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            p->fd_ok = true;
        } else {
            p->fd_ok = false; /* EOF or EIO: no host on the other side right now */
        }
        return got;
    }
}

void uart_service_tx(uint64_t now_sim)
{
    for (int i = 0; i < HAL_PORT_COUNT; i++) {
        port_t *p = &ports[i];
        if (p->kind != PORT_NONE && (ringbuf_count(&p->tx) > 0 || p->baud != 0)) {
            service_tx(p, (hal_port_t)i, now_sim);
        }
    }
}

bool uart_service(uint64_t now_sim)
{
    uart_service_tx(now_sim);
    bool got = false;
    for (int i = 0; i < HAL_PORT_COUNT; i++) {
        if (ports[i].kind == PORT_FD) {
            got = service_rx(&ports[i]) || got;
        }
    }
    return got;
}

int uart_poll_fds(int *fds, int max)
{
    int n = 0;
    for (int i = 0; i < HAL_PORT_COUNT && n < max; i++) {
        if (ports[i].kind == PORT_FD && ports[i].fd_ok && ringbuf_free(&ports[i].rx) > 0) {
            fds[n++] = ports[i].fd;
        }
    }
    return n;
}

bool uart_write(hal_port_t port, const uint8_t *data, size_t len)
{
    if ((unsigned)port >= HAL_PORT_COUNT) {
        return false;
    }
    port_t *p = &ports[port];
    if (p->kind == PORT_NONE || !ringbuf_write_all(&p->tx, data, len)) {
        p->st.tx_dropped += (uint32_t)len;
        return false;
    }
    p->st.tx_bytes += (uint32_t)len;
    return true;
}

size_t uart_read(hal_port_t port, uint8_t *buf, size_t cap)
{
    if ((unsigned)port >= HAL_PORT_COUNT || ports[port].kind == PORT_NONE) {
        return 0;
    }
    return ringbuf_read(&ports[port].rx, buf, cap);
}

size_t uart_tx_free(hal_port_t port)
{
    if ((unsigned)port >= HAL_PORT_COUNT || ports[port].kind == PORT_NONE) {
        return 0;
    }
    return ringbuf_free(&ports[port].tx);
}

void uart_stats(hal_port_t port, hal_port_stats_t *out)
{
    memset(out, 0, sizeof(*out));
    if ((unsigned)port >= HAL_PORT_COUNT) {
        return;
    }
    *out = ports[port].st;
    if (ports[port].kind != PORT_NONE) {
        out->rx_overruns = ports[port].rx.overruns;
    }
}
