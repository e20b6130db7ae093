/* LOSA slot tracking and exposure control, and the per-frame entry point. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "losa/frame.h"
#include "test_algos.h"

static losa_peak_t peak_at(float pos, int valid)
{
    losa_peak_t pk = {pos, 800, 40, (uint8_t)(valid ? LOSA_PEAK_VALID : 0), 0};
    return pk;
}

/* The image leaving the high end re-enters at the low end through the next slot:
 * the unwrapped position must continue smoothly (+128), not jump back. */
static void test_slot_unwraps_when_peak_leaves_high_end(void)
{
    const losa_slot_cfg_t cfg = losa_slot_default_cfg();
    losa_slot_state_t st;
    losa_slot_init(&st);
    uint8_t slot;
    float u;
    for (float x = 100.0f; x < 255.0f; x += 3.7f) { /* unwrapped truth: central, then slot 2 */
        const float raw = x < 127.5f ? x : x - 128.0f;
        const losa_peak_t pk = peak_at(raw, 1);
        losa_slot_update(&st, &cfg, &pk, &slot, &u);
        CHECK_NEAR(u, x, 1e-3);
        CHECK(slot == (x < 127.5f ? 1 : 2));
    }
}

/* Moving down through the low end must step the slot the other way. */
static void test_slot_unwraps_when_peak_leaves_low_end(void)
{
    const losa_slot_cfg_t cfg = losa_slot_default_cfg();
    losa_slot_state_t st;
    losa_slot_init(&st);
    uint8_t slot = 9;
    float u = 0.0f;
    const losa_peak_t a = peak_at(2.0f, 1);
    losa_slot_update(&st, &cfg, &a, &slot, &u);
    CHECK(slot == LOSA_SLOT_CENTRAL);
    const losa_peak_t b = peak_at(126.0f, 1);
    const uint8_t flags = losa_slot_update(&st, &cfg, &b, &slot, &u);
    CHECK(flags & LOSA_SLOT_CHANGED);
    CHECK(slot == 0);
    CHECK_NEAR(u, -2.0, 1e-4);
}

/* There are only three slots: a fourth wrap is flagged and the slot stays put. */
static void test_slot_does_not_go_beyond_outer_slot(void)
{
    const losa_slot_cfg_t cfg = losa_slot_default_cfg();
    losa_slot_state_t st;
    losa_slot_init(&st);
    uint8_t slot;
    float u;
    uint8_t flags = 0;
    const float path[] = {100.0f, 126.0f, 1.0f, 60.0f, 110.0f, 126.0f, 1.0f}; /* upwards, two wraps */
    for (unsigned i = 0; i < sizeof path / sizeof path[0]; i++) {
        const losa_peak_t pk = peak_at(path[i], 1);
        flags = losa_slot_update(&st, &cfg, &pk, &slot, &u);
    }
    CHECK(slot == 2);
    CHECK(flags & LOSA_SLOT_OUT_OF_RANGE);
}

/* A short dropout (the peak crossing the array end) must keep the slot; a long loss
 * must fall back to the central slot, the reference's assumption. */
static void test_slot_holds_short_loss_and_resets_after_long_loss(void)
{
    const losa_slot_cfg_t cfg = losa_slot_default_cfg();
    losa_slot_state_t st;
    losa_slot_init(&st);
    uint8_t slot;
    float u;
    const losa_peak_t hi = peak_at(126.5f, 1);
    const losa_peak_t lost = peak_at(0.0f, 0);
    const losa_peak_t lo = peak_at(0.8f, 1);
    losa_slot_update(&st, &cfg, &hi, &slot, &u);
    for (int i = 0; i < 5; i++) {
        losa_slot_update(&st, &cfg, &lost, &slot, &u);
        CHECK_NEAR(u, 126.5, 1e-4);
    }
    losa_slot_update(&st, &cfg, &lo, &slot, &u);
    CHECK(slot == 2);
    CHECK_NEAR(u, 128.8, 1e-4);
    uint8_t flags = 0;
    for (int i = 0; i <= cfg.lost_reset_frames; i++) {
        flags |= losa_slot_update(&st, &cfg, &lost, &slot, &u);
    }
    CHECK(flags & LOSA_SLOT_RESET);
    CHECK(slot == LOSA_SLOT_CENTRAL);
}

static uint32_t expo(losa_exposure_state_t *st, const losa_exposure_cfg_t *cfg, uint16_t peak, uint16_t bg,
                     unsigned flags)
{
    const losa_peak_t pk = {64.0f, peak, bg, (uint8_t)flags, 64};
    return losa_exposure_update(st, cfg, &pk, 1023);
}

/* Saturation must shorten, weak peaks lengthen, the band in between hold, and the
 * result must stay within the configured bounds whatever happens. */
static void test_exposure_shortens_on_saturation_lengthens_when_weak_holds_in_band(void)
{
    const losa_exposure_cfg_t cfg = losa_exposure_default_cfg();
    losa_exposure_state_t st;
    losa_exposure_init(&st, 1000, &cfg);
    CHECK(expo(&st, &cfg, 1023, 40, LOSA_PEAK_VALID | LOSA_PEAK_SATURATED) == 500);
    CHECK(expo(&st, &cfg, 400, 40, LOSA_PEAK_VALID) == 500); /* in band */
    const uint32_t up = expo(&st, &cfg, 80, 40, LOSA_PEAK_VALID);
    CHECK(up == 1000); /* wants 10x, limited to max_step_up */
    const uint32_t down = expo(&st, &cfg, 950, 40, LOSA_PEAK_VALID);
    CHECK(down == 1000u * 409u / 950u); /* aims the peak at the 40 % target */
    for (int i = 0; i < 100; i++) {
        expo(&st, &cfg, 0, 0, 0);
    }
    CHECK(st.exposure_us == cfg.max_us);
    for (int i = 0; i < 100; i++) {
        expo(&st, &cfg, 1023, 40, LOSA_PEAK_VALID | LOSA_PEAK_SATURATED);
    }
    CHECK(st.exposure_us == cfg.min_us);
}

/* Closed loop through the frame entry point: a sensor whose signal scales with
 * exposure must leave saturation and settle inside the band on every sensor. */
static void test_frame_exposure_loop_settles_inside_band(void)
{
    const losa_frame_cfg_t cfg = losa_frame_default_cfg(10);
    losa_frame_state_t st;
    losa_frame_init(&st, &cfg, 3000);
    static uint16_t lines[LOSA_SENSORS][LOSA_PIXELS];
    losa_sensor_result_t out[LOSA_SENSORS];
    const double gain[LOSA_SENSORS] = {2.0, 0.5, 0.1, 0.001}; /* counts per us at the peak */
    for (int frame = 0; frame < 60; frame++) {
        for (int s = 0; s < LOSA_SENSORS; s++) {
            const double t = st.exposure[s].exposure_us;
            for (int k = 0; k < LOSA_PIXELS; k++) {
                const double u = k - (40.3 + 10 * s);
                double v = 20.0 + gain[s] * t * exp(-0.5 * u * u);
                lines[s][k] = (uint16_t)(v > 1023.0 ? 1023.0 : v);
            }
        }
        losa_frame_process(&st, &cfg, (const uint16_t(*)[LOSA_PIXELS])lines, out);
    }
    for (int s = 0; s < 3; s++) {
        CHECK(out[s].flags & LOSA_PEAK_VALID);
        CHECK(!(out[s].flags & LOSA_PEAK_SATURATED));
        CHECK(out[s].peak > 1023 / 10 && out[s].peak < 1023 * 85 / 100);
        CHECK_NEAR(out[s].pos_px, 40.3 + 10 * s, 0.05);
        CHECK(out[s].slot == LOSA_SLOT_CENTRAL);
    }
    /* too weak even at the longest exposure: no peak, exposure pinned at max */
    CHECK(!(out[3].flags & LOSA_PEAK_VALID));
    CHECK(out[3].next_exposure_us == cfg.exposure.max_us);
}

int main(void)
{
    RUN(test_slot_unwraps_when_peak_leaves_high_end);
    RUN(test_slot_unwraps_when_peak_leaves_low_end);
    RUN(test_slot_does_not_go_beyond_outer_slot);
    RUN(test_slot_holds_short_loss_and_resets_after_long_loss);
    RUN(test_exposure_shortens_on_saturation_lengthens_when_weak_holds_in_band);
    RUN(test_frame_exposure_loop_settles_inside_band);
    return ALGO_TEST_EXIT();
}
