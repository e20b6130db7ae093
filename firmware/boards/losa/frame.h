/* The LOSA per-frame entry point: 4 lines -> peaks, slot tracking, exposure control.
 * This is the unit the callgrind bench counts (firmware_losa_frame_instructions). */
#ifndef AW_LOSA_FRAME_H
#define AW_LOSA_FRAME_H

#include <stdint.h>

#include "exposure.h"
#include "peak.h"
#include "slots.h"

#define LOSA_SENSORS 4

typedef struct {
    losa_peak_cfg_t peak;
    losa_slot_cfg_t slot;
    losa_exposure_cfg_t exposure;
} losa_frame_cfg_t;

typedef struct {
    losa_slot_state_t slot[LOSA_SENSORS];
    losa_exposure_state_t exposure[LOSA_SENSORS];
} losa_frame_state_t;

typedef struct {
    float pos_px;          /* unwrapped across slots: raw_px + 128 (slot - 1) */
    float raw_px;          /* within the array, -0.5 .. 127.5 */
    uint16_t peak;         /* raw max pixel (counts) */
    uint16_t background;   /* counts */
    uint32_t exposure_us;  /* integration time this line was taken with */
    uint32_t next_exposure_us; /* to program for the next frame */
    uint8_t slot;          /* 0, 1 (central), 2 */
    uint8_t flags;         /* LOSA_PEAK_* | LOSA_SLOT_* */
} losa_sensor_result_t;

/* Defaults for an ADC of `bits` (8, 10, 12). */
losa_frame_cfg_t losa_frame_default_cfg(unsigned adc_bits);
void losa_frame_init(losa_frame_state_t *st, const losa_frame_cfg_t *cfg, uint32_t initial_exposure_us);

/* One frame: lines[s] was integrated for st->exposure[s].exposure_us. */
void losa_frame_process(losa_frame_state_t *st, const losa_frame_cfg_t *cfg,
                        const uint16_t lines[LOSA_SENSORS][LOSA_PIXELS],
                        losa_sensor_result_t out[LOSA_SENSORS]);

#endif
