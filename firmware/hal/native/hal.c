/*
 * hal.c — the native backend's hal_t, its command line, and resets.
 *
 *   build/native/<board> [--sim SOCKET] [--stepped | --wall]
 *                        [--port ROLE=PATH[@BAUD] | --port ROLE=sim[@BAUD] ...]
 *                        [--clock-drift-ppm PPM] [--clock-offset-us US]
 *                        [--start-us US] [--config FILE]
 *
 * See docs/sim-channel.md for the channel and the stepping rules.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "native.h"
#include "sim_proto.h"

jmp_buf native_reset_jmp;

static uint32_t boots;
static hal_reset_cause_t last_cause = HAL_RESET_POWER_ON;

static void emit_boot(void)
{
    uint8_t body[SIM_BOOT_BODY] = {(uint8_t)last_cause, 0, 0, 0};
    memcpy(&body[4], &boots, sizeof(boots));
    chan_emit(SIM_BOOT, 0, native_clock.now_sim, body, sizeof(body));
    if (native_clock.mode == NATIVE_WALL) {
        chan_flush();
    }
}

_Noreturn void native_reboot(hal_reset_cause_t cause)
{
    boots++;
    last_cause = cause;
    native_clock.boot_sim = native_now_sim();
    /* the MCU and its peripherals restart; the sensors and the host do not */
    uart_reset();
    capture_reset();
    tsl_emu_reset_pins();
    pwm_reset();
    watchdog_reset();
    emit_boot();
    longjmp(native_reset_jmp, 1);
}

static void software_reset(void) { native_reboot(HAL_RESET_SOFTWARE); }

static hal_reset_cause_t reset_cause(void) { return last_cause; }

static uint32_t boot_count(void) { return boots; }

static const hal_t native_hal = {
    .target = "native",
    .micros = native_micros,
    .delay_us = native_delay_us,
    .idle = native_idle,
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

static _Noreturn void usage(const char *prog, const char *problem)
{
    if (problem != NULL) {
        fprintf(stderr, "%s: %s\n", prog, problem);
    }
    fprintf(stderr,
            "usage: %s [--sim SOCKET] [--stepped | --wall]\n"
            "          [--port ROLE=PATH[@BAUD] | --port ROLE=sim[@BAUD] ...]\n"
            "          [--clock-drift-ppm PPM] [--clock-offset-us US] [--start-us US]\n"
            "          [--config FILE]\n"
            "  ROLE: host, ins, rtk, rover, anemo. Stepped mode (the default with --sim) needs --sim.\n",
            prog);
    exit(2);
}

static double parse_double(const char *prog, const char *opt, const char *text)
{
    char *end = NULL;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || !(v > -1e6 && v < 1e6)) {
        char msg[256];
        snprintf(msg, sizeof(msg), "%s %s: not a number in (-1e6, 1e6)", opt, text);
        usage(prog, msg);
    }
    return v;
}

static uint64_t parse_u64(const char *prog, const char *opt, const char *text)
{
    char *end = NULL;
    unsigned long long v = strtoull(text, &end, 10);
    if (end == text || *end != '\0' || text[0] == '-') {
        char msg[256];
        snprintf(msg, sizeof(msg), "%s %s: not a non-negative integer", opt, text);
        usage(prog, msg);
    }
    return (uint64_t)v;
}

const hal_t *native_start(int argc, char **argv, const char *board_name, uint8_t board_id)
{
    const char *prog = argc > 0 ? argv[0] : board_name;
    const char *sim_path = NULL;
    const char *config_path = NULL;
    int mode = 0;
    double drift_ppm = 0.0;
    uint64_t offset_us = 0;
    uint64_t start_us = 0;
    char err[600];

    capture_reset();
    tsl_emu_reset_pins();
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(prog, NULL);
        } else if (strcmp(a, "--stepped") == 0) {
            mode = NATIVE_STEPPED;
        } else if (strcmp(a, "--wall") == 0) {
            mode = NATIVE_WALL;
        } else if (val == NULL) {
            char msg[256];
            snprintf(msg, sizeof(msg), "%s: missing value or unknown option", a);
            usage(prog, msg);
        } else if (strcmp(a, "--sim") == 0) {
            sim_path = val;
            i++;
        } else if (strcmp(a, "--port") == 0) {
            if (!uart_map(val, err, sizeof(err))) {
                usage(prog, err);
            }
            i++;
        } else if (strcmp(a, "--clock-drift-ppm") == 0) {
            drift_ppm = parse_double(prog, a, val);
            i++;
        } else if (strcmp(a, "--clock-offset-us") == 0) {
            offset_us = parse_u64(prog, a, val);
            i++;
        } else if (strcmp(a, "--start-us") == 0) {
            start_us = parse_u64(prog, a, val);
            i++;
        } else if (strcmp(a, "--config") == 0) {
            config_path = val;
            i++;
        } else {
            char msg[256];
            snprintf(msg, sizeof(msg), "unknown option %s", a);
            usage(prog, msg);
        }
    }
    if (mode == 0) {
        mode = sim_path != NULL ? NATIVE_STEPPED : NATIVE_WALL;
    }
    if (mode == NATIVE_STEPPED && sim_path == NULL) {
        usage(prog, "--stepped needs --sim SOCKET (the simulator drives the clock)");
    }
    if (config_path != NULL && !config_open(config_path, err, sizeof(err))) {
        usage(prog, err);
    }

    native_clock.mode = (native_mode_t)mode;
    native_clock.drift = drift_ppm * 1e-6;
    native_clock.offset_us = offset_us;
    native_clock.now_sim = mode == NATIVE_STEPPED ? start_us : native_mono_us();
    native_clock.boot_sim = native_clock.now_sim;

    if (sim_path != NULL && !chan_connect(sim_path, (native_mode_t)mode, board_name, board_id)) {
        exit(2);
    }
    emit_boot();
    return &native_hal;
}
