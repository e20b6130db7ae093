/* Sub-pixel peak finder, see peak.h for the method. */
#include "peak.h"

/* A saturated run longer than this is treated as this long (keeps |x| <= 8 and every
 * int64 sum below 2^61). */
#define MAX_SAT_RUN 10
#define Q8 256

typedef struct {
    int64_t sw, sx, sy, sxx, sxy;
} wls_sums_t;

losa_peak_cfg_t losa_peak_default_cfg(unsigned bits)
{
    if (bits < 8u) {
        bits = 8u;
    }
    if (bits > 12u) {
        bits = 12u;
    }
    const uint16_t fs = (uint16_t)((1u << bits) - 1u);
    const losa_peak_cfg_t cfg = {
        .full_scale = fs,
        .sat_level = fs,
        .min_contrast = (uint16_t)(fs / 20u),
    };
    return cfg;
}

static uint16_t clamp_px(uint16_t v)
{
    return v > LOSA_PIXEL_MAX ? (uint16_t)LOSA_PIXEL_MAX : v;
}

static void wls_add(wls_sums_t *s, int32_t x, int64_t w, int64_t y)
{
    s->sw += w;
    s->sx += w * x;
    s->sy += w * y;
    s->sxx += w * x * x;
    s->sxy += w * x * y;
}

/* Weighted least-squares line y = a + m x. Returns 0 when fewer than two distinct x
 * carry weight, or when the slope has the wrong sign for this flank. */
static int wls_line(const wls_sums_t *s, int rising, float *m, float *a)
{
    const int64_t d = s->sw * s->sxx - s->sx * s->sx;
    const int64_t n = s->sw * s->sxy - s->sx * s->sy;
    if (d <= 0 || (rising ? n <= 0 : n >= 0)) {
        return 0;
    }
    *m = (float)n / (float)d;
    *a = ((float)s->sy - *m * (float)s->sx) / (float)s->sw;
    return 1;
}

/* Intersection of the left (rising) and right (falling) WLS lines, x relative to the
 * window centre; 0 when either fit is degenerate. */
static int lines_intersection(const wls_sums_t *left, const wls_sums_t *right, float *xs)
{
    float m1, a1, m2, a2;
    if (!wls_line(left, 1, &m1, &a1) || !wls_line(right, 0, &m2, &a2)) {
        return 0;
    }
    *xs = (a2 - a1) / (m1 - m2); /* m1 > 0 > m2 */
    return 1;
}

/* A clipped peak: its flanks' lines would have to be extrapolated far above the data
 * (poorly conditioned on curved flanks, ~0.5 px errors). Instead: the midpoint of the
 * two flanks' crossings of one level, half-way between the background and the lower of
 * the two unclipped pixels next to the run, each crossing interpolated between the two
 * pixels that straddle it. Returns 0 when a flank is missing (run at the array end or
 * capped). Absolute pixel coordinates. */
static int saturated_centre(const uint16_t px[LOSA_PIXELS], int run_lo, int run_hi, uint16_t sat, uint16_t bg,
                            float *xs)
{
    if (run_lo == 0 || run_hi == LOSA_PIXELS - 1) {
        return 0;
    }
    const uint16_t lt = clamp_px(px[run_lo - 1]);
    const uint16_t rt = clamp_px(px[run_hi + 1]);
    const uint16_t top = lt < rt ? lt : rt;
    if (lt >= sat || rt >= sat || top <= bg) {
        return 0;
    }
    const float level = (float)bg + 0.5f * (float)(top - bg);
    int k = run_lo - 1;
    while (k > 0 && (float)clamp_px(px[k]) >= level) {
        k--;
    }
    const float yl0 = (float)clamp_px(px[k]);
    const float yl1 = (float)clamp_px(px[k + 1]);
    if (yl0 >= level) {
        return 0;
    }
    const float xl = (float)k + (level - yl0) / (yl1 - yl0);
    k = run_hi + 1;
    while (k < LOSA_PIXELS - 1 && (float)clamp_px(px[k]) >= level) {
        k++;
    }
    const float yr0 = (float)clamp_px(px[k]);
    const float yr1 = (float)clamp_px(px[k - 1]);
    if (yr0 >= level) {
        return 0;
    }
    const float xr = (float)k - (level - yr0) / (yr1 - yr0);
    *xs = 0.5f * (xl + xr);
    return 1;
}

void losa_peak_find(const losa_peak_cfg_t *cfg, const uint16_t px[LOSA_PIXELS], losa_peak_t *out)
{
    const uint16_t sat = cfg->sat_level ? clamp_px(cfg->sat_level) : 1u;

    /* Pass 1 (integer): maximum, first index of it, total for the background. */
    uint32_t total = 0;
    uint16_t vmax = 0;
    int imax = 0;
    for (int k = 0; k < LOSA_PIXELS; k++) {
        const uint16_t v = clamp_px(px[k]);
        total += v;
        if (v > vmax) {
            vmax = v;
            imax = k;
        }
    }

    /* Window: +-3 around the maximum, or around the middle of a saturated run. */
    int run_lo = imax;
    int run_hi = imax;
    if (vmax >= sat) {
        while (run_lo > 0 && clamp_px(px[run_lo - 1]) >= sat && imax - run_lo < MAX_SAT_RUN / 2) {
            run_lo--;
        }
        while (run_hi < LOSA_PIXELS - 1 && clamp_px(px[run_hi + 1]) >= sat &&
               run_hi - run_lo < MAX_SAT_RUN) {
            run_hi++;
        }
    }
    const int centre = (run_lo + run_hi) / 2;
    int lo = run_lo - LOSA_PEAK_HALF_WINDOW;
    int hi = run_hi + LOSA_PEAK_HALF_WINDOW;
    uint8_t flags = 0;
    if (lo < 0) {
        lo = 0;
        flags |= LOSA_PEAK_EDGE;
    }
    if (hi > LOSA_PIXELS - 1) {
        hi = LOSA_PIXELS - 1;
        flags |= LOSA_PEAK_EDGE;
    }

    uint32_t wsum = 0;
    for (int k = lo; k <= hi; k++) {
        const uint16_t v = clamp_px(px[k]);
        wsum += v;
        if (v >= sat) {
            flags |= LOSA_PEAK_SATURATED;
        }
    }
    const uint32_t n_out = (uint32_t)(LOSA_PIXELS - (hi - lo + 1));
    const uint16_t bg = (uint16_t)((total - wsum + n_out / 2u) / n_out);

    out->peak = vmax;
    out->background = bg;
    out->max_index = (uint8_t)centre;
    out->pos_px = (float)centre;
    if (vmax <= bg || (uint16_t)(vmax - bg) < cfg->min_contrast) {
        out->flags = flags; /* no valid peak */
        return;
    }
    flags |= LOSA_PEAK_VALID;

    /* Weighted-mean centre, Q8 relative to `centre`. */
    int32_t sy0 = 0;
    int32_t sxy0 = 0;
    for (int k = lo; k <= hi; k++) {
        const uint16_t v = clamp_px(px[k]);
        const int32_t y = v > bg ? (int32_t)(v - bg) : 0;
        sy0 += y;
        sxy0 += (k - centre) * y;
    }
    const int32_t c_q8 = (sxy0 * Q8) / sy0; /* sy0 >= vmax - bg > 0 */

    /* Left/right groups with the 2-pixel membership ramp around c, WLS sums. */
    wls_sums_t left = {0, 0, 0, 0, 0};
    wls_sums_t right = {0, 0, 0, 0, 0};
    for (int k = lo; k <= hi; k++) {
        const uint16_t v = clamp_px(px[k]);
        if (v >= sat || v <= bg) {
            continue; /* clipped top or pure background: not on a flank */
        }
        const int32_t x = k - centre;
        const int64_t y = (int64_t)(v - bg);
        int32_t m_left = Q8 / 2 - (x * Q8 - c_q8) / 2;
        m_left = m_left < 0 ? 0 : (m_left > Q8 ? Q8 : m_left);
        wls_add(&left, x, y * m_left, y);
        wls_add(&right, x, y * (Q8 - m_left), y);
    }

    float pos = 0.0f;
    int ok;
    if (flags & LOSA_PEAK_SATURATED) {
        ok = saturated_centre(px, run_lo, run_hi, sat, bg, &pos);
    } else {
        ok = lines_intersection(&left, &right, &pos);
        pos += (float)centre;
    }
    if (ok && pos >= (float)lo - 0.5f && pos <= (float)hi + 0.5f) {
        out->pos_px = pos;
        out->flags = flags;
        return;
    }
    out->pos_px = (float)centre + (float)c_q8 / (float)Q8;
    out->flags = flags | LOSA_PEAK_CENTROID;
}
