/* Integration-time (exposure) control of one TSL1401 array (reference §3.3.1.2).
 *
 * Keeps the peak well inside the ADC range with a hold band (hysteresis):
 *   saturated                      -> halve the exposure
 *   peak above high_permille of FS -> scale towards target_permille
 *   valid peak, contrast below low -> scale towards target, at most x max_step_up
 *   no valid peak                  -> lengthen by 25 % per frame (search)
 *   otherwise                      -> hold
 * bounded to [min_us, max_us]. The hold band contains the 20 %-of-full-scale level
 * that the marker's LED control aims for, so the two loops do not fight: the marker
 * dims the LED, the exposure only moves when the peak leaves the band.
 */
#ifndef AW_LOSA_EXPOSURE_H
#define AW_LOSA_EXPOSURE_H

#include <stdint.h>

#include "peak.h"

typedef struct {
    uint32_t min_us; /* shortest integration time the SI/CLK sequence allows */
    uint32_t max_us; /* longest that still fits the frame period */
    uint16_t low_permille;    /* contrast below this (of full scale): too weak */
    uint16_t high_permille;   /* peak above this: too close to saturation */
    uint16_t target_permille; /* where a correction aims */
    uint16_t max_step_up;     /* largest lengthening factor per frame */
} losa_exposure_cfg_t;

typedef struct {
    uint32_t exposure_us;
    uint32_t saturated_frames; /* counters for the heartbeat */
    uint32_t weak_frames;
} losa_exposure_state_t;

/* Defaults for a 300 Hz frame: 40 us .. 3000 us, band 10 % .. 85 %, target 40 %. */
losa_exposure_cfg_t losa_exposure_default_cfg(void);
void losa_exposure_init(losa_exposure_state_t *st, uint32_t initial_us, const losa_exposure_cfg_t *cfg);

/* One frame's peak (taken with st->exposure_us) -> st->exposure_us for the next. */
uint32_t losa_exposure_update(losa_exposure_state_t *st, const losa_exposure_cfg_t *cfg,
                              const losa_peak_t *pk, uint16_t full_scale);

#endif
