/* RC PWM pulse-width capture (base: 5 pilot channels; rover: the tail servo).
 *
 * Input: edge timestamps per channel (us, free-running uint32_t, wrap-safe) with the
 * pin level after the edge. Width = falling - rising. A pulse is accepted when
 *   - its width is within [min_us, max_us] (nominal 1000-2000 us; default 950-2050
 *     for trims/end points), and
 *   - it is within jump_us of the last accepted width, or a second pulse confirms the
 *     jump (a single outlier is never accepted; a real stick step costs one frame).
 * Everything else is a glitch (counted; a held jump stops counting once confirmed). A channel is valid while accepted pulses
 * keep arriving within timeout_us (the RC frame rate must be >= 45 Hz: 22.2 ms;
 * default timeout 50 ms, i.e. two lost frames tolerated).
 */
#ifndef AW_PWM_CAPTURE_H
#define AW_PWM_CAPTURE_H

#include <stdint.h>

typedef struct {
    uint16_t min_us;
    uint16_t max_us;
    uint16_t jump_us;
    uint32_t timeout_us;
} pwm_capture_cfg_t;

typedef struct {
    uint32_t rise_us;
    uint32_t last_accept_us;   /* rising edge of the last accepted pulse */
    uint32_t period_us;        /* rising-to-rising of the last two accepted pulses */
    uint16_t width_us;         /* last accepted width */
    uint16_t candidate_us;     /* a jump waiting for confirmation, 0 = none */
    uint8_t have_rise;
    uint8_t have_width;
    uint32_t pulses;           /* accepted */
    uint32_t glitches;
} pwm_channel_t;

typedef struct {
    uint16_t width_us;  /* last accepted width (0 before the first) */
    uint8_t valid;
    uint32_t period_us; /* frame period measured on this channel */
    uint32_t glitches;
} pwm_channel_out_t;

pwm_capture_cfg_t pwm_capture_default_cfg(void);
void pwm_channel_init(pwm_channel_t *ch);
/* An edge at t_us; level = 1 after a rising edge, 0 after a falling one. */
void pwm_channel_edge(pwm_channel_t *ch, const pwm_capture_cfg_t *cfg, uint32_t t_us, int level);
void pwm_channel_get(const pwm_channel_t *ch, const pwm_capture_cfg_t *cfg, uint32_t now_us, pwm_channel_out_t *out);

#endif
