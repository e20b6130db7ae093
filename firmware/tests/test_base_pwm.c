/* RC PWM capture (base pilot inputs, rover tail servo) and SBUS decoding. */
#include <stdint.h>
#include <string.h>

#include "base/pwm_capture.h"
#include "base/sbus.h"
#include "test_algos.h"

#define FRAME_US 20000u /* 50 Hz RC frame */

static void pulse(pwm_channel_t *ch, const pwm_capture_cfg_t *cfg, uint32_t t, uint32_t width)
{
    pwm_channel_edge(ch, cfg, t, 1);
    pwm_channel_edge(ch, cfg, t + width, 0);
}

/* Width and frame period straight from the edge timestamps, across a timer wrap. */
static void test_pwm_width_and_period_across_timer_wrap(void)
{
    const pwm_capture_cfg_t cfg = pwm_capture_default_cfg();
    pwm_channel_t ch;
    pwm_channel_init(&ch);
    uint32_t t = 0xFFFFFFFFu - 30000u;
    for (int i = 0; i < 5; i++) {
        pulse(&ch, &cfg, t, 1500);
        t += FRAME_US;
    }
    pwm_channel_out_t out;
    pwm_channel_get(&ch, &cfg, t, &out);
    CHECK(out.valid);
    CHECK(out.width_us == 1500);
    CHECK(out.period_us == FRAME_US);
    CHECK(out.glitches == 0);
}

/* Out-of-range pulses and one-frame outliers are glitches; real steps are followed
 * one frame late. */
static void test_pwm_rejects_out_of_range_and_single_outlier(void)
{
    const pwm_capture_cfg_t cfg = pwm_capture_default_cfg();
    pwm_channel_t ch;
    pwm_channel_init(&ch);
    uint32_t t = 0;
    pwm_channel_out_t out;
    pulse(&ch, &cfg, t += FRAME_US, 1200);
    pulse(&ch, &cfg, t += FRAME_US, 300); /* noise spike */
    pulse(&ch, &cfg, t += FRAME_US, 2600); /* out of range */
    pwm_channel_get(&ch, &cfg, t, &out);
    CHECK(out.width_us == 1200 && out.glitches == 2);
    pulse(&ch, &cfg, t += FRAME_US, 1900); /* single outlier */
    pulse(&ch, &cfg, t += FRAME_US, 1210);
    pwm_channel_get(&ch, &cfg, t, &out);
    CHECK(out.width_us == 1210 && out.glitches == 3);
    pulse(&ch, &cfg, t += FRAME_US, 1900); /* a real stick step */
    pwm_channel_get(&ch, &cfg, t, &out);
    CHECK(out.width_us == 1210);
    pulse(&ch, &cfg, t += FRAME_US, 1905);
    pwm_channel_get(&ch, &cfg, t, &out);
    CHECK(out.width_us == 1905 && out.glitches == 3);
}

/* A receiver that stops (failsafe, unplugged) must show invalid within the timeout. */
static void test_pwm_invalid_after_timeout(void)
{
    const pwm_capture_cfg_t cfg = pwm_capture_default_cfg();
    pwm_channel_t ch;
    pwm_channel_init(&ch);
    pwm_channel_out_t out;
    pwm_channel_get(&ch, &cfg, 0, &out);
    CHECK(!out.valid); /* nothing seen yet */
    pulse(&ch, &cfg, 1000, 1500);
    pwm_channel_get(&ch, &cfg, 1000 + cfg.timeout_us, &out);
    CHECK(out.valid);
    pwm_channel_get(&ch, &cfg, 1001 + cfg.timeout_us, &out);
    CHECK(!out.valid);
}

/* A falling edge without a rising one (start-up mid-pulse) must not make a width. */
static void test_pwm_falling_edge_without_rise_ignored(void)
{
    const pwm_capture_cfg_t cfg = pwm_capture_default_cfg();
    pwm_channel_t ch;
    pwm_channel_init(&ch);
    pwm_channel_edge(&ch, &cfg, 500, 0);
    CHECK(!ch.have_width && ch.glitches == 0);
}

/* The reference SBUS frame from shared/peers/README.md. */
static void test_sbus_decodes_reference_frame(void)
{
    uint8_t f[SBUS_FRAME_LEN] = {0x0F, 0x4C, 0x1C, 0x5F, 0x32, 0x34, 0x38, 0xDD, 0x89, 0x83, 0x0F, 0x7C};
    const uint16_t want[8] = {1562, 1496, 1000, 1531, 1806, 2006, 1495, 1495};
    sbus_frame_t fr;
    CHECK(sbus_decode(f, &fr));
    for (int i = 0; i < 8; i++) {
        CHECK(fr.width_us[i] == want[i]);
    }
    for (int i = 8; i < SBUS_CHANNELS; i++) {
        CHECK(fr.width_us[i] == 875);
    }
    CHECK(fr.flags == 0);
    /* stream: garbage, then the frame byte by byte */
    sbus_parser_t p;
    sbus_parser_init(&p);
    int got = 0;
    const uint8_t junk[3] = {0x12, 0x0F, 0x33};
    for (int i = 0; i < 3; i++) {
        got += sbus_parser_feed(&p, junk[i], &fr);
    }
    sbus_parser_gap(&p);
    for (unsigned i = 0; i < SBUS_FRAME_LEN; i++) {
        got += sbus_parser_feed(&p, f[i], &fr);
    }
    CHECK(got == 1 && fr.width_us[0] == 1562);
}

int main(void)
{
    RUN(test_pwm_width_and_period_across_timer_wrap);
    RUN(test_pwm_rejects_out_of_range_and_single_outlier);
    RUN(test_pwm_invalid_after_timeout);
    RUN(test_pwm_falling_edge_without_rise_ignored);
    RUN(test_sbus_decodes_reference_frame);
    return ALGO_TEST_EXIT();
}
