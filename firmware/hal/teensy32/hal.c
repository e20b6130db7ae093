/* hal.c — the Teensy 3.2 backend's hal_t: peripheral start-up, reset cause and
 * the warm-boot counter. */
#include "regs.h"
#include "teensy32.h"

#define NOINIT_MAGIC 0xA1B2C3D4u

/* survive a warm reset (not a power cycle): .noinit is neither loaded nor zeroed */
__attribute__((section(".noinit"))) static uint32_t noinit_magic;
__attribute__((section(".noinit"))) static uint32_t noinit_boots;
static hal_reset_cause_t cause = HAL_RESET_OTHER;

static void read_reset_cause(void)
{
    uint8_t s0 = RCM_SRS0;
    uint8_t s1 = RCM_SRS1;
    if (s0 & RCM_SRS0_WDOG) {
        cause = HAL_RESET_WATCHDOG;
    } else if (s1 & RCM_SRS1_SW) {
        cause = HAL_RESET_SOFTWARE;
    } else if (s0 & RCM_SRS0_POR) {
        cause = HAL_RESET_POWER_ON;
    } else if (s0 & RCM_SRS0_LVD) {
        cause = HAL_RESET_BROWNOUT;
    } else if (s0 & RCM_SRS0_PIN) {
        cause = HAL_RESET_EXTERNAL;
    }
    if (cause == HAL_RESET_POWER_ON || cause == HAL_RESET_BROWNOUT ||
        noinit_magic != NOINIT_MAGIC) {
        noinit_magic = NOINIT_MAGIC;
        noinit_boots = 0;
    } else {
        noinit_boots++;
    }
}

static void software_reset(void)
{
    SCB_AIRCR = SCB_AIRCR_SYSRESETREQ;
    for (;;) {
    }
}

static hal_reset_cause_t reset_cause(void) { return cause; }

static uint32_t boot_count(void) { return noinit_boots; }

static const hal_t teensy_hal = {
    .target = "teensy32",
    .micros = teensy_micros,
    .delay_us = teensy_delay_us,
    .idle = teensy_idle,
    .uart_write = uart_write,
    .uart_read = uart_read,
    .uart_tx_free = uart_tx_free,
    .uart_stats = uart_stats,
    .gpio_write = gpio_write,
    .adc_read = adc_read,
    .spi_transfer = spi_transfer,
    .capture_read = capture_read,
    .capture_overruns = capture_overruns,
    .pwm_write = pwm_write,
    .watchdog_start = watchdog_start,
    .watchdog_refresh = watchdog_refresh,
    .reset = software_reset,
    .reset_cause = reset_cause,
    .boot_count = boot_count,
    .config_size = 2048u,
    .config_read = config_read,
    .config_write = config_write,
};

const hal_t *teensy_hal_init(void)
{
    read_reset_cause();
    gpio_init();
    adc_init();
    spi_init();
    capture_init();
    pwm_init();
    uart_init();
    config_init();
    return &teensy_hal;
}
