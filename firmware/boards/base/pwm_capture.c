/* RC PWM capture, see pwm_capture.h. */
#include "pwm_capture.h"

pwm_capture_cfg_t pwm_capture_default_cfg(void)
{
    const pwm_capture_cfg_t cfg = {.min_us = 950, .max_us = 2050, .jump_us = 250, .timeout_us = 50000u};
    return cfg;
}

void pwm_channel_init(pwm_channel_t *ch)
{
    const pwm_channel_t zero = {0};
    *ch = zero;
}

static uint16_t absdiff(uint16_t a, uint16_t b)
{
    return (uint16_t)(a > b ? a - b : b - a);
}

static void accept(pwm_channel_t *ch, uint16_t width)
{
    if (ch->have_width) {
        ch->period_us = ch->rise_us - ch->last_accept_us;
    }
    ch->width_us = width;
    ch->have_width = 1;
    ch->candidate_us = 0;
    ch->last_accept_us = ch->rise_us;
    ch->pulses++;
}

void pwm_channel_edge(pwm_channel_t *ch, const pwm_capture_cfg_t *cfg, uint32_t t_us, int level)
{
    if (level) {
        ch->rise_us = t_us;
        ch->have_rise = 1;
        return;
    }
    if (!ch->have_rise) {
        return; /* falling edge without its rising edge (start-up, or after a spike) */
    }
    ch->have_rise = 0;
    const uint32_t w = t_us - ch->rise_us; /* wrap-safe */
    if (w < cfg->min_us || w > cfg->max_us) {
        ch->glitches++;
        return;
    }
    const uint16_t width = (uint16_t)w;
    if (!ch->have_width || absdiff(width, ch->width_us) <= cfg->jump_us) {
        accept(ch, width);
    } else if (ch->candidate_us && absdiff(width, ch->candidate_us) <= cfg->jump_us) {
        ch->glitches--; /* the held pulse was real: the jump is confirmed */
        accept(ch, width);
    } else {
        ch->candidate_us = width; /* a jump: wait for confirmation */
        ch->glitches++;
    }
}

void pwm_channel_get(const pwm_channel_t *ch, const pwm_capture_cfg_t *cfg, uint32_t now_us, pwm_channel_out_t *out)
{
    out->width_us = ch->width_us;
    out->period_us = ch->period_us;
    out->glitches = ch->glitches;
    out->valid = ch->have_width && (uint32_t)(now_us - ch->last_accept_us) <= cfg->timeout_us;
}
