/* watchdog.c — native watchdog: expires on board time, checked whenever the clock
 * moves (idle), and reboots the board like the MK20's WDOG would. */
#include "native.h"

static bool enabled;
static uint64_t timeout_us;
static uint64_t last_refresh;

void watchdog_start(uint32_t timeout_ms)
{
    enabled = true;
    timeout_us = (uint64_t)timeout_ms * 1000u;
    last_refresh = native_micros();
}

void watchdog_refresh(void) { last_refresh = native_micros(); }

void watchdog_reset(void) { enabled = false; }

void watchdog_check(uint64_t now_sim)
{
    if (enabled && native_board_us(now_sim) - last_refresh > timeout_us) {
        native_reboot(HAL_RESET_WATCHDOG);
    }
}
