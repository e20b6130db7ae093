/*
 * capture.c — FTM input capture of both edges (RC PWM, rotor IR, tail servo).
 *
 * Every FTM that carries a capture channel free-runs at F_BUS / 16 = 3 MHz over
 * 16 bits (21.8 ms). The ISR only timestamps: it converts the captured count to
 * the micros() clock by subtracting the ticks elapsed since the edge (CNT - CnV,
 * far below one counter period), reads the pin level after the edge, and queues
 * the edge (STYLE 4). Pulse-width logic runs in the board task.
 */
#include "board_pins.h"
#include "regs.h"
#include "ringbuf.h"
#include "teensy32.h"

#define EDGE_RING 64u
#define TICKS_PER_US 3u
#define CAPTURE_PRIORITY 48u /* above the UARTs: a late capture misplaces an edge */

static ringbuf_t rings[HAL_CAPTURE_COUNT];
static hal_edge_t mem[HAL_CAPTURE_COUNT][EDGE_RING];

static void gate_and_irq(uint32_t ftm)
{
    static const uint32_t irq[3] = {IRQ_FTM0, IRQ_FTM1, IRQ_FTM2};
    if (ftm == 0u) {
        SIM_SCGC6 |= SIM_SCGC6_FTM0;
    } else if (ftm == 1u) {
        SIM_SCGC6 |= SIM_SCGC6_FTM1;
    } else {
        SIM_SCGC3 |= SIM_SCGC3_FTM2;
    }
    FTM_MODE(ftm) = FTM_MODE_WPDIS;
    FTM_SC(ftm) = 0;
    FTM_CNTIN(ftm) = 0;
    FTM_MOD(ftm) = 0xFFFFu;
    FTM_CNT(ftm) = 0;
    FTM_SC(ftm) = FTM_SC_CLKS(1) | FTM_SC_PS(4);
    nvic_enable(irq[ftm], CAPTURE_PRIORITY);
}

void capture_init(void)
{
    bool started[3] = {false, false, false};
    for (int i = 0; i < HAL_CAPTURE_COUNT; i++) {
        ringbuf_init(&rings[i], mem[i], EDGE_RING, (uint16_t)sizeof(hal_edge_t));
        const ftm_map_t *m = &capture_map[i];
        if (m->ftm < 0) {
            continue;
        }
        uint32_t ftm = (uint32_t)m->ftm;
        if (!started[ftm]) {
            gate_and_irq(ftm);
            started[ftm] = true;
        }
        PORT_PCR(m->pin.port, m->pin.bit) = PORT_PCR_MUX(m->alt);
        FTM_CSC(ftm, m->ch) = FTM_CSC_CHIE | FTM_CSC_ELSA | FTM_CSC_ELSB; /* both edges */
    }
}

static void ftm_isr(uint32_t ftm)
{
    for (int i = 0; i < HAL_CAPTURE_COUNT; i++) {
        const ftm_map_t *m = &capture_map[i];
        if (m->ftm != (int8_t)ftm || (FTM_CSC(ftm, m->ch) & FTM_CSC_CHF) == 0) {
            continue;
        }
        uint16_t cv = (uint16_t)FTM_CV(ftm, m->ch);
        FTM_CSC(ftm, m->ch) &= ~FTM_CSC_CHF;
        uint32_t now_us = (uint32_t)teensy_micros();
        uint16_t ticks_since = (uint16_t)((uint16_t)FTM_CNT(ftm) - cv);
        hal_edge_t e = {
            .t_us = now_us - ticks_since / TICKS_PER_US,
            .level = (GPIO_PDIR(m->pin.port) >> m->pin.bit) & 1u,
        };
        (void)ringbuf_put(&rings[i], &e); /* a full ring counts the loss */
        teensy_event();
    }
}

void ftm0_isr(void) { ftm_isr(0); }
void ftm1_isr(void) { ftm_isr(1); }
void ftm2_isr(void) { ftm_isr(2); }

size_t capture_read(hal_capture_t ch, hal_edge_t *out, size_t cap)
{
    if ((unsigned)ch >= HAL_CAPTURE_COUNT) {
        return 0;
    }
    size_t n = 0;
    while (n < cap && ringbuf_get(&rings[ch], &out[n])) {
        n++;
    }
    return n;
}

uint32_t capture_overruns(hal_capture_t ch)
{
    return (unsigned)ch < HAL_CAPTURE_COUNT ? rings[ch].overruns : 0u;
}
