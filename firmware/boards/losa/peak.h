/* Sub-pixel peak finder for one 128-pixel TSL1401 line (reference §3.3.1.5).
 *
 * Method (the reference's, made continuous in the sub-pixel phase):
 *   1. background = mean of the pixels outside the peak window; the maximum pixel
 *      (or the middle of a saturated run) picks the window, +-3 pixels around it;
 *   2. weighted-mean centre c of the background-subtracted window (weights = intensity);
 *   3. the window is split at c into a left and a right group. A pixel within one pixel
 *      of c belongs to both groups in proportion to its distance from c (a 2-pixel
 *      ramp): a hard split makes the estimate jump whenever c crosses a pixel centre,
 *      which alone costs 0.05-0.2 px RMS on simulated peaks;
 *   4. each group is fitted with a weighted least-squares line (weights = intensity x
 *      group membership; saturated pixels are clipped, not on the flank: weight 0);
 *   5. peak = intersection of the two lines.
 * A clipped (saturated) top is different: its flanks are short and curved, and their
 * lines meet far above the data. There the peak is the midpoint of the two flanks'
 * crossings of one level (half-way up the lower unclipped flank pixel), interpolated
 * between the pixels that straddle it. When a method cannot apply (a flank missing at
 * the array end, degenerate fit) the weighted mean is used and flagged.
 * Integer sums (int64) over the window; only the final 2x2 solves are float.
 *
 * Coordinates: pixel k covers [k - 0.5, k + 0.5], so positions run from -0.5 to 127.5.
 * Inputs must be <= 4095 (12-bit ADC) — larger values are clamped.
 */
#ifndef AW_LOSA_PEAK_H
#define AW_LOSA_PEAK_H

#include <stdint.h>

#define LOSA_PIXELS 128
#define LOSA_PEAK_HALF_WINDOW 3
#define LOSA_PIXEL_MAX 4095u

/* losa_peak_t.flags */
#define LOSA_PEAK_VALID 0x01u     /* a peak above min_contrast was found */
#define LOSA_PEAK_SATURATED 0x02u /* at least one window pixel at/above sat_level */
#define LOSA_PEAK_EDGE 0x04u      /* window clipped by an array end (peak within 3 px) */
#define LOSA_PEAK_CENTROID 0x08u  /* line fit ill-conditioned: position = weighted mean */

typedef struct {
    uint16_t full_scale;   /* ADC full scale: 255, 1023 or 4095 */
    uint16_t sat_level;    /* pixels >= this are clipped (usually full_scale) */
    uint16_t min_contrast; /* peak - background below this: no valid peak (counts) */
} losa_peak_cfg_t;

typedef struct {
    float pos_px;        /* sub-pixel centre, raw (within this array), -0.5 .. 127.5 */
    uint16_t peak;       /* maximum raw pixel value in the window */
    uint16_t background; /* background level subtracted (counts) */
    uint8_t flags;       /* LOSA_PEAK_* */
    uint8_t max_index;   /* the pixel the window was centred on */
} losa_peak_t;

/* Defaults for an ADC of `bits` (8, 10 or 12): saturation at full scale, weak-peak
 * threshold 5 % of full scale. */
losa_peak_cfg_t losa_peak_default_cfg(unsigned bits);

/* Find the peak of one line. Always fills *out; check out->flags & LOSA_PEAK_VALID. */
void losa_peak_find(const losa_peak_cfg_t *cfg, const uint16_t px[LOSA_PIXELS], losa_peak_t *out);

#endif
