/*
 * board.h (LOSA) — the LOSA tracker's wiring (reference §3.3.1): four TSL1401
 * arrays read together, F2's per-frame processing (peaks, slots, exposure), the
 * MPU-9250, and the protocol link to the host.
 *
 * Timing: a frame every LOSA_FRAME_PERIOD_US (320 Hz). When the exposure the
 * control asks for is shorter than the period, the arrays are flushed at the frame
 * start and read `exposure` later; otherwise they are read at the frame start and
 * integrate for a whole period. The four arrays share SI, so they share one
 * exposure: the shortest any sensor with a valid peak asks for (no saturation
 * anywhere), or the longest asked for when no sensor sees a peak (search).
 */
#ifndef AW_BOARD_LOSA_H
#define AW_BOARD_LOSA_H

#include <stdint.h>

#include "board_link.h"
#include "frame.h"
#include "hal.h"
#include "mpu9250.h"
#include "tsl1401.h"

#define BOARD_NAME "losa"
#define BOARD_ID AW_BOARD_LOSA

#define LOSA_FRAME_PERIOD_US 3125u /* 320 Hz */
#define LOSA_IMU_HZ 100u
#define LOSA_INITIAL_EXPOSURE_US 1000u
#define LOSA_WATCHDOG_MS 500u

typedef struct {
    board_link_t link;
    tsl1401_t tsl;
    mpu9250_t imu;
    bool imu_ok;
    losa_frame_cfg_t cfg;
    losa_frame_state_t frame;
    uint16_t lines[LOSA_SENSORS][LOSA_PIXELS];
    uint32_t exposure_us;   /* the shared exposure programmed for the next read */
    uint32_t prev_exposure_us;
    bool read_pending;      /* flushed (or waiting to read at the frame start) */
    uint64_t next_frame_us;
    uint64_t next_read_us;
    uint64_t t0_us;
    uint32_t imu_k;         /* IMU reads scheduled since t0 */
    uint32_t frames;
    /* raw lines on request */
    uint8_t raw_mask;
    uint16_t raw_remaining; /* per selected sensor; 65535 = until stopped */
    uint8_t raw_decimation;
    uint32_t raw_skipped;   /* raw lines not sent: no room on the link */
} losa_board_t;

extern losa_board_t losa_board; /* for tests */

void board_init(const hal_t *hal);
uint64_t board_task(const hal_t *hal);

#endif /* AW_BOARD_LOSA_H */
