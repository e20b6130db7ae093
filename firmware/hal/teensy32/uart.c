/*
 * uart.c — UART0/1/2, interrupt driven: the ISR moves received bytes into the
 * rx ring and feeds the transmitter from the tx ring; everything else happens in
 * the board task (STYLE 4). Roles map to UARTs in board_pins.h.
 *
 * UART0 and UART1 run from the system clock (96 MHz), UART2 from the bus clock
 * (48 MHz); baud divisor = clock / (16 * baud) with a 1/32 fine adjust (BRFA).
 */
#include <string.h>

#include "board_pins.h"
#include "regs.h"
#include "ringbuf.h"
#include "teensy32.h"

#define RX_RING 1024u
#define TX_RING 4096u
#define UART_PRIORITY 64u

typedef struct {
    ringbuf_t rx, tx;
    uint8_t rx_mem[RX_RING];
    uint8_t tx_mem[TX_RING];
    volatile uint32_t hw_overruns;
    volatile uint32_t rx_errors;
    volatile uint32_t rx_bytes;
    hal_port_stats_t st; /* task-side counters */
} uart_port_t;

/* storage per hardware UART (three on the MK20DX256), not per role */
static uart_port_t uarts[3];
static hal_port_stats_t unmapped_stats[HAL_PORT_COUNT]; /* refused writes to unwired roles */

static void configure(const uart_map_t *m)
{
    uint32_t n = (uint32_t)m->uart;
    static const uint32_t gate[3] = {SIM_SCGC4_UART0, SIM_SCGC4_UART1, SIM_SCGC4_UART2};
    SIM_SCGC4 |= gate[n];
    PORT_PCR(m->rx.port, m->rx.bit) = PORT_PCR_MUX(3) | PORT_PCR_PE | PORT_PCR_PS;
    PORT_PCR(m->tx.port, m->tx.bit) = PORT_PCR_MUX(3) | PORT_PCR_DSE | PORT_PCR_SRE;
    uint32_t clock = n < 2u ? F_CPU : F_BUS;
    uint32_t div32 = (2u * clock + m->baud / 2u) / m->baud; /* clock*32/(16*baud) */
    uint32_t sbr = div32 >> 5;
    UART_BDH(n) = (uint8_t)((sbr >> 8) & 0x1Fu);
    UART_BDL(n) = (uint8_t)(sbr & 0xFFu);
    UART_C4(n) = (uint8_t)(div32 & 0x1Fu);
    UART_C1(n) = 0; /* 8N1 */
    UART_C2(n) = UART_C2_TE | UART_C2_RE | UART_C2_RIE;
    static const uint32_t irq[3] = {IRQ_UART0_STATUS, IRQ_UART1_STATUS, IRQ_UART2_STATUS};
    nvic_enable(irq[n], UART_PRIORITY);
}

void uart_init(void)
{
    for (int n = 0; n < 3; n++) {
        ringbuf_init(&uarts[n].rx, uarts[n].rx_mem, RX_RING, 1);
        ringbuf_init(&uarts[n].tx, uarts[n].tx_mem, TX_RING, 1);
    }
    for (int role = 0; role < HAL_PORT_COUNT; role++) {
        if (uart_map[role].uart >= 0) {
            configure(&uart_map[role]);
        }
    }
}

static void uart_isr(uint32_t n)
{
    uart_port_t *p = &uarts[n];
    uint8_t s1 = UART_S1(n);
    if (s1 & (UART_S1_RDRF | UART_S1_OR | UART_S1_NF | UART_S1_FE | UART_S1_PF)) {
        uint8_t d = UART_D(n); /* reading S1 then D clears the flags */
        if (s1 & UART_S1_OR) {
            p->hw_overruns++;
        }
        if (s1 & (UART_S1_NF | UART_S1_FE | UART_S1_PF)) {
            p->rx_errors++;
        }
        if (s1 & UART_S1_RDRF) {
            if (ringbuf_put(&p->rx, &d)) { /* a full ring counts the loss */
                p->rx_bytes++;
            }
            teensy_event();
        }
    }
    if ((UART_C2(n) & UART_C2_TIE) && (s1 & UART_S1_TDRE)) {
        uint8_t b;
        if (ringbuf_get(&p->tx, &b)) {
            UART_D(n) = b;
        } else {
            UART_C2(n) = (uint8_t)(UART_C2(n) & ~UART_C2_TIE);
        }
    }
}

void uart0_status_isr(void) { uart_isr(0); }
void uart1_status_isr(void) { uart_isr(1); }
void uart2_status_isr(void) { uart_isr(2); }

/* the UART behind a role, NULL when the role is not wired on this board */
static uart_port_t *port_of(hal_port_t port)
{
    if ((unsigned)port >= HAL_PORT_COUNT || uart_map[port].uart < 0) {
        return NULL;
    }
    return &uarts[uart_map[port].uart];
}

bool uart_write(hal_port_t port, const uint8_t *data, size_t len)
{
    uart_port_t *p = port_of(port);
    if (p == NULL) {
        if ((unsigned)port < HAL_PORT_COUNT) {
            unmapped_stats[port].tx_dropped += (uint32_t)len;
        }
        return false;
    }
    if (!ringbuf_write_all(&p->tx, data, len)) {
        p->st.tx_dropped += (uint32_t)len;
        return false;
    }
    p->st.tx_bytes += (uint32_t)len;
    uint32_t n = (uint32_t)uart_map[port].uart;
    uint32_t primask = irq_save();
    UART_C2(n) = (uint8_t)(UART_C2(n) | UART_C2_TIE);
    irq_restore(primask);
    return true;
}

size_t uart_read(hal_port_t port, uint8_t *buf, size_t cap)
{
    uart_port_t *p = port_of(port);
    return p != NULL ? ringbuf_read(&p->rx, buf, cap) : 0u;
}

size_t uart_tx_free(hal_port_t port)
{
    uart_port_t *p = port_of(port);
    return p != NULL ? ringbuf_free(&p->tx) : 0u;
}

void uart_stats(hal_port_t port, hal_port_stats_t *out)
{
    memset(out, 0, sizeof(*out));
    if ((unsigned)port >= HAL_PORT_COUNT) {
        return;
    }
    uart_port_t *p = port_of(port);
    if (p == NULL) {
        *out = unmapped_stats[port];
        return;
    }
    *out = p->st;
    out->rx_overruns = p->rx.overruns + p->hw_overruns;
    out->rx_errors = p->rx_errors;
    out->rx_bytes = p->rx_bytes;
}
