/* LOSA peak finder: accuracy on clean peaks, saturation, edges, weak lines. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "losa/peak.h"
#include "test_algos.h"

/* Pixel-integrated Gaussian peak (sigma px) at centre c on a flat background. */
static void gauss_line(uint16_t px[LOSA_PIXELS], double c, double sigma, double amp, double bg, double clip)
{
    for (int k = 0; k < LOSA_PIXELS; k++) {
        double s = 0.0;
        for (int j = 0; j < 16; j++) {
            const double u = k - 0.5 + (j + 0.5) / 16.0 - c;
            s += exp(-0.5 * u * u / (sigma * sigma)) / 16.0;
        }
        double v = bg + amp * s;
        v = v > clip ? clip : v;
        px[k] = (uint16_t)lround(v);
    }
}

/* The reference method's weak point: a hard left/right split jumps as the centre
 * crosses a pixel; the ramp must keep the error small at every sub-pixel phase. */
static void test_peak_subpixel_error_small_at_every_phase(void)
{
    const losa_peak_cfg_t cfg = losa_peak_default_cfg(12);
    uint16_t px[LOSA_PIXELS];
    double worst = 0.0;
    for (int i = 0; i <= 40; i++) {
        const double c = 60.0 + i / 40.0;
        gauss_line(px, c, 1.1, 3000.0, 100.0, 4095.0);
        losa_peak_t pk;
        losa_peak_find(&cfg, px, &pk);
        CHECK(pk.flags & LOSA_PEAK_VALID);
        CHECK(!(pk.flags & (LOSA_PEAK_SATURATED | LOSA_PEAK_EDGE | LOSA_PEAK_CENTROID)));
        const double e = fabs(pk.pos_px - c);
        worst = e > worst ? e : worst;
    }
    CHECK(worst < 0.05);
}

/* Estimates must move with the peak (no pixel locking into steps). */
static void test_peak_position_increases_monotonically_with_shift(void)
{
    const losa_peak_cfg_t cfg = losa_peak_default_cfg(12);
    uint16_t px[LOSA_PIXELS];
    float prev = -1.0f;
    for (int i = 0; i <= 100; i++) {
        gauss_line(px, 30.0 + i * 0.01, 1.0, 2000.0, 50.0, 4095.0);
        losa_peak_t pk;
        losa_peak_find(&cfg, px, &pk);
        CHECK(pk.pos_px > prev);
        prev = pk.pos_px;
    }
}

/* A clipped (flat) top has no usable maximum: the flanks must still place it. */
static void test_peak_saturated_flat_top_still_centred(void)
{
    const losa_peak_cfg_t cfg = losa_peak_default_cfg(10);
    uint16_t px[LOSA_PIXELS];
    for (int i = 0; i < 10; i++) {
        const double c = 80.0 + i * 0.1;
        gauss_line(px, c, 1.2, 3000.0, 40.0, 1023.0); /* 3x over full scale */
        losa_peak_t pk;
        losa_peak_find(&cfg, px, &pk);
        CHECK(pk.flags & LOSA_PEAK_VALID);
        CHECK(pk.flags & LOSA_PEAK_SATURATED);
        CHECK_NEAR(pk.pos_px, c, 0.1);
    }
}

/* A peak at the array end clips the window; it must be flagged, stay in range and be
 * found when both flanks are on the array. */
static void test_peak_near_array_end_is_flagged_and_in_range(void)
{
    const losa_peak_cfg_t cfg = losa_peak_default_cfg(12);
    uint16_t px[LOSA_PIXELS];
    gauss_line(px, 1.6, 1.0, 3000.0, 100.0, 4095.0);
    losa_peak_t pk;
    losa_peak_find(&cfg, px, &pk);
    CHECK(pk.flags & LOSA_PEAK_VALID);
    CHECK(pk.flags & LOSA_PEAK_EDGE);
    CHECK_NEAR(pk.pos_px, 1.6, 0.1);

    gauss_line(px, 127.3, 1.0, 3000.0, 100.0, 4095.0);
    losa_peak_find(&cfg, px, &pk);
    CHECK(pk.flags & LOSA_PEAK_EDGE);
    CHECK(pk.pos_px >= 123.0f && pk.pos_px <= 127.5f);
}

/* No light (flat or noise-only line) must not produce a valid peak. */
static void test_peak_flat_line_is_not_valid(void)
{
    const losa_peak_cfg_t cfg = losa_peak_default_cfg(10);
    uint16_t px[LOSA_PIXELS];
    for (int k = 0; k < LOSA_PIXELS; k++) {
        px[k] = (uint16_t)(30 + (k * 7) % 5); /* a few counts of pattern noise */
    }
    losa_peak_t pk;
    losa_peak_find(&cfg, px, &pk);
    CHECK(!(pk.flags & LOSA_PEAK_VALID));
    memset(px, 0, sizeof px);
    losa_peak_find(&cfg, px, &pk);
    CHECK(!(pk.flags & LOSA_PEAK_VALID));
}

/* Out-of-range ADC words (a 16-bit glitch) must be clamped, never overflow the sums. */
static void test_peak_all_pixels_at_16bit_max_does_not_overflow(void)
{
    const losa_peak_cfg_t cfg = losa_peak_default_cfg(12);
    uint16_t px[LOSA_PIXELS];
    for (int k = 0; k < LOSA_PIXELS; k++) {
        px[k] = 0xFFFF;
    }
    losa_peak_t pk;
    losa_peak_find(&cfg, px, &pk);
    CHECK(pk.pos_px >= -0.5f && pk.pos_px <= 127.5f);
    px[64] = 4095;
    for (int k = 0; k < LOSA_PIXELS; k++) {
        px[k] = (uint16_t)((k % 2) ? 0xFFFF : 0);
    }
    losa_peak_find(&cfg, px, &pk);
    CHECK(pk.pos_px >= -0.5f && pk.pos_px <= 127.5f);
}

int main(void)
{
    RUN(test_peak_subpixel_error_small_at_every_phase);
    RUN(test_peak_position_increases_monotonically_with_shift);
    RUN(test_peak_saturated_flat_top_still_centred);
    RUN(test_peak_near_array_end_is_flagged_and_in_range);
    RUN(test_peak_flat_line_is_not_valid);
    RUN(test_peak_all_pixels_at_16bit_max_does_not_overflow);
    return ALGO_TEST_EXIT();
}
