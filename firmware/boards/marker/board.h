/*
 * board.h (marker) — the active marker's wiring (reference §3.3.1.4): MPU-9250 at
 * 450 Hz into F2's marker logic (attitude, calibration, LED choice and intensity),
 * the four LED drivers on PWM, host feedback (marker_command) in, IMU + attitude
 * out at 120 Hz. During wind mapping (§3.4) the marker rides with a sonic anemometer:
 * its ASCII lines (HAL_PORT_ANEMO, young81000.h) are forwarded as `anemometer` frames
 * as they complete, stamped with the line's first byte.
 */
#ifndef AW_BOARD_MARKER_H
#define AW_BOARD_MARKER_H

#include <stdint.h>

#include "board_link.h"
#include "hal.h"
#include "marker_logic.h"
#include "mpu9250.h"
#include "young81000.h"

#define BOARD_NAME "marker"
#define BOARD_ID AW_BOARD_MARKER

#define MARKER_IMU_HZ 450u
#define MARKER_OUTPUT_HZ 120u
#define MARKER_WATCHDOG_MS 500u

typedef struct {
    board_link_t link;
    mpu9250_t imu;
    bool imu_ok;
    marker_cfg_t cfg;
    marker_state_t logic;
    mpu9250_sample_t last; /* the latest IMU sample (sent at 120 Hz) */
    uint64_t t0_us;
    uint32_t imu_k;        /* IMU samples scheduled since t0 */
    uint32_t out_k;        /* outputs scheduled since t0 */
    uint32_t imu_errors;
    uint32_t commands;     /* marker_command frames applied */
    young_parser_t anemo;  /* the carried anemometer's lines */
    uint32_t anemo_sent;   /* anemometer frames queued to the host */
} marker_board_t;

extern marker_board_t marker_board; /* for tests */

void board_init(const hal_t *hal);
uint64_t board_task(const hal_t *hal);

#endif /* AW_BOARD_MARKER_H */
