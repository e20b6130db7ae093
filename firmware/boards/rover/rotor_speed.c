/* Rotor speed from blade reflections, see rotor_speed.h. */
#include "rotor_speed.h"

rotor_speed_cfg_t rotor_speed_default_cfg(void)
{
    const rotor_speed_cfg_t cfg = {.min_interval_us = 2000u, .max_interval_us = 200000u};
    return cfg;
}

void rotor_speed_init(rotor_speed_t *st)
{
    const rotor_speed_t zero = {0};
    *st = zero;
}

static void restart(rotor_speed_t *st)
{
    st->estimate_us = 0;
    st->prev_interval_us = 0;
    st->interval_us = 0;
    st->agreed = 0;
    st->outliers_in_row = 0;
}

static void accept(rotor_speed_t *st, uint32_t dt)
{
    /* agree: within 20 % of the previous interval */
    st->agreed = st->interval_us != 0 && dt * 5u < st->interval_us * 6u && dt * 6u > st->interval_us * 5u;
    st->prev_interval_us = st->interval_us;
    st->interval_us = dt;
    /* estimate: first-order low-pass, 1/4 per half revolution */
    st->estimate_us = st->estimate_us ? st->estimate_us - st->estimate_us / 4u + dt / 4u : dt;
    st->outliers_in_row = 0;
}

void rotor_speed_pulse(rotor_speed_t *st, const rotor_speed_cfg_t *cfg, uint32_t t_us)
{
    st->pulses++;
    if (!st->have_pulse) {
        st->have_pulse = 1;
        st->last_pulse_us = t_us;
        return;
    }
    const uint32_t dt = t_us - st->last_pulse_us; /* wrap-safe */
    if (dt > cfg->max_interval_us) {
        st->last_pulse_us = t_us;
        st->have_early = 0;
        restart(st);
        return;
    }
    /* dt, estimate <= max_interval_us: the products below cannot overflow */
    if (dt < cfg->min_interval_us) {
        st->glitches++;
        return;
    }
    if (st->estimate_us && dt * 10u < st->estimate_us * 7u) {
        st->glitches++; /* early: ignored, the next pulse is measured from the last good one */
        st->early_us = t_us;
        st->have_early = 1;
        return;
    }
    const uint32_t prev_pulse = st->last_pulse_us;
    st->last_pulse_us = t_us;
    if (!st->estimate_us) {
        accept(st, dt);
        return;
    }
    /* An "early" pulse right in the middle of this interval was a blade: the estimate
     * locked on twice the real interval (it started across a missed pulse). */
    if (st->have_early) {
        st->have_early = 0;
        const uint32_t first = st->early_us - prev_pulse;
        const uint32_t gap = first * 2u > dt ? first * 2u - dt : dt - first * 2u;
        if (gap * 5u < dt) {
            st->glitches--;
            restart(st);
            accept(st, first);
            accept(st, dt - first);
            return;
        }
    }
    /* nearest whole number of half revolutions, within 20 % */
    const uint32_t est = st->estimate_us;
    const uint32_t k = (dt + est / 2u) / est;
    const uint32_t lo = k * est - k * est / 5u;
    const uint32_t hi = k * est + k * est / 5u;
    if (k >= 1u && k <= 3u && dt >= lo && dt <= hi) {
        st->missed += k - 1u;
        accept(st, dt / k);
        return;
    }
    st->glitches++; /* outlier */
    if (++st->outliers_in_row >= 3u) {
        restart(st);
        accept(st, dt);
    }
}

void rotor_speed_get(const rotor_speed_t *st, const rotor_speed_cfg_t *cfg, uint32_t now_us, rotor_speed_out_t *out)
{
    out->interval_us = st->interval_us;
    out->pulses = st->pulses;
    out->glitches = st->glitches;
    out->missed = st->missed;
    out->valid = st->have_pulse && st->agreed && (uint32_t)(now_us - st->last_pulse_us) <= cfg->max_interval_us;
    if (!out->valid) {
        out->speed_rad_s = 0.0f;
        return;
    }
    /* Omega = 2 pi / (dt_k + dt_k-1): two half revolutions */
    const uint32_t rev_us = st->interval_us + (st->prev_interval_us ? st->prev_interval_us : st->interval_us);
    out->speed_rad_s = 6.283185307f * 1e6f / (float)rev_us;
}
