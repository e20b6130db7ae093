/* LOSA per-frame processing, see frame.h. */
#include "frame.h"

losa_frame_cfg_t losa_frame_default_cfg(unsigned adc_bits)
{
    const losa_frame_cfg_t cfg = {
        .peak = losa_peak_default_cfg(adc_bits),
        .slot = losa_slot_default_cfg(),
        .exposure = losa_exposure_default_cfg(),
    };
    return cfg;
}

void losa_frame_init(losa_frame_state_t *st, const losa_frame_cfg_t *cfg, uint32_t initial_exposure_us)
{
    for (int s = 0; s < LOSA_SENSORS; s++) {
        losa_slot_init(&st->slot[s]);
        losa_exposure_init(&st->exposure[s], initial_exposure_us, &cfg->exposure);
    }
}

void losa_frame_process(losa_frame_state_t *st, const losa_frame_cfg_t *cfg,
                        const uint16_t lines[LOSA_SENSORS][LOSA_PIXELS],
                        losa_sensor_result_t out[LOSA_SENSORS])
{
    for (int s = 0; s < LOSA_SENSORS; s++) {
        losa_peak_t pk;
        losa_peak_find(&cfg->peak, lines[s], &pk);
        losa_sensor_result_t *r = &out[s];
        r->raw_px = pk.pos_px;
        r->peak = pk.peak;
        r->background = pk.background;
        r->flags = (uint8_t)(pk.flags | losa_slot_update(&st->slot[s], &cfg->slot, &pk, &r->slot, &r->pos_px));
        r->exposure_us = st->exposure[s].exposure_us;
        r->next_exposure_us =
            losa_exposure_update(&st->exposure[s], &cfg->exposure, &pk, cfg->peak.full_scale);
    }
}
