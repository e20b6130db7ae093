/*
 * watchdog.c — the MK20 WDOG on its 1 kHz LPO clock: a timeout in ms is the
 * count. Reconfiguration needs the unlock sequence and must follow it within the
 * 256-bus-cycle window; a refresh is two writes within 20 bus cycles — both with
 * interrupts masked.
 */
#include "regs.h"
#include "teensy32.h"

void watchdog_start(uint32_t timeout_ms)
{
    if (timeout_ms < 4u) {
        timeout_ms = 4u;
    }
    uint32_t primask = irq_save();
    WDOG_UNLOCK = WDOG_UNLOCK_SEQ1;
    WDOG_UNLOCK = WDOG_UNLOCK_SEQ2;
    __asm__ volatile("nop");
    __asm__ volatile("nop");
    WDOG_TOVALH = (uint16_t)(timeout_ms >> 16);
    WDOG_TOVALL = (uint16_t)(timeout_ms & 0xFFFFu);
    WDOG_PRESC = 0; /* LPO / 1 */
    WDOG_STCTRLH = WDOG_STCTRLH_ALLOWUPDATE | WDOG_STCTRLH_WDOGEN | WDOG_STCTRLH_STOPEN |
                   WDOG_STCTRLH_WAITEN;
    irq_restore(primask);
}

void watchdog_refresh(void)
{
    uint32_t primask = irq_save();
    WDOG_REFRESH = WDOG_REFRESH_SEQ1;
    WDOG_REFRESH = WDOG_REFRESH_SEQ2;
    irq_restore(primask);
}
