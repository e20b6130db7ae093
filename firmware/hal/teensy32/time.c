/*
 * time.c — the µs clock on SysTick: a 1 kHz tick counts milliseconds, the
 * down-counter gives the µs within the millisecond (F_CPU / 1e6 cycles per µs).
 */
#include "regs.h"
#include "teensy32.h"

#define CYCLES_PER_MS (F_CPU / 1000u)
#define CYCLES_PER_US (F_CPU / 1000000u)

static volatile uint64_t ms_count;
static volatile bool event_pending;

void systick_isr(void) { ms_count++; }

void teensy_time_init(void)
{
    SYST_RVR = CYCLES_PER_MS - 1u;
    SYST_CVR = 0;
    SYST_CSR = SYST_CSR_CLKSOURCE | SYST_CSR_TICKINT | SYST_CSR_ENABLE;
    /* SysTick above every peripheral interrupt: micros() inside an ISR stays right */
    SCB_SHPR3 = (SCB_SHPR3 & 0x00FFFFFFu) | (32u << 24);
}

uint64_t teensy_micros(void)
{
    uint32_t primask = irq_save();
    uint32_t current = SYST_CVR;
    uint64_t ms = ms_count;
    uint32_t pending = SCB_ICSR & SCB_ICSR_PENDSTSET;
    irq_restore(primask);
    /* the counter wrapped after we masked interrupts but before we read it */
    if (pending && current > 50u) {
        ms++;
    }
    return ms * 1000u + (CYCLES_PER_MS - 1u - current) / CYCLES_PER_US;
}

void teensy_delay_us(uint32_t us)
{
    uint64_t until = teensy_micros() + us;
    while (teensy_micros() < until) {
    }
}

void teensy_event(void) { event_pending = true; }

/* Sleeps with WFI while the deadline is more than a tick away (SysTick wakes us
 * every ms), spins for the last millisecond so sub-ms deadlines (exposure) hold.
 * The event flag is tested with interrupts masked and WFI still wakes on a pending
 * one, so an ISR between the test and the WFI cannot leave us asleep. */
void teensy_idle(uint64_t until_us)
{
    for (;;) {
        uint64_t now = teensy_micros();
        if (now >= until_us) {
            return;
        }
        uint32_t primask = irq_save();
        bool event = event_pending;
        event_pending = false;
        if (!event && until_us - now > 1100u) {
            __asm__ volatile("wfi");
        }
        irq_restore(primask); /* a pending interrupt runs here */
        if (event) {
            return;
        }
    }
}
