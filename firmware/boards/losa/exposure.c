/* Exposure control, see exposure.h. All integer: exposure (< 2^17 us) x counts
 * (< 2^12) stays below 2^32. */
#include "exposure.h"

losa_exposure_cfg_t losa_exposure_default_cfg(void)
{
    const losa_exposure_cfg_t cfg = {
        .min_us = 40,
        .max_us = 3000,
        .low_permille = 100,
        .high_permille = 850,
        .target_permille = 400,
        .max_step_up = 2,
    };
    return cfg;
}

static uint32_t clamp_us(uint32_t t, const losa_exposure_cfg_t *cfg)
{
    return t < cfg->min_us ? cfg->min_us : (t > cfg->max_us ? cfg->max_us : t);
}

void losa_exposure_init(losa_exposure_state_t *st, uint32_t initial_us, const losa_exposure_cfg_t *cfg)
{
    st->exposure_us = clamp_us(initial_us, cfg);
    st->saturated_frames = 0;
    st->weak_frames = 0;
}

uint32_t losa_exposure_update(losa_exposure_state_t *st, const losa_exposure_cfg_t *cfg,
                              const losa_peak_t *pk, uint16_t full_scale)
{
    const uint32_t fs = full_scale ? full_scale : 1u;
    const uint32_t target = fs * cfg->target_permille / 1000u;
    const uint32_t high = fs * cfg->high_permille / 1000u;
    const uint32_t low = fs * cfg->low_permille / 1000u;
    const uint32_t contrast = pk->peak > pk->background ? (uint32_t)(pk->peak - pk->background) : 0u;
    uint32_t t = st->exposure_us;

    if (pk->flags & LOSA_PEAK_SATURATED) {
        st->saturated_frames++;
        t /= 2u;
    } else if (!(pk->flags & LOSA_PEAK_VALID)) {
        st->weak_frames++;
        t += t / 4u + 1u;
    } else if (pk->peak > high) {
        /* The background scales with exposure too: aim the raw peak at the target. */
        t = (uint32_t)((uint64_t)t * target / pk->peak);
    } else if (contrast < low) {
        st->weak_frames++;
        uint64_t up = (uint64_t)t * target / (contrast ? contrast : 1u);
        const uint64_t cap = (uint64_t)t * cfg->max_step_up;
        t = (uint32_t)(up > cap ? cap : up);
    }
    st->exposure_us = clamp_us(t, cfg);
    return st->exposure_us;
}
