/* Rotor speed from IR blade reflections. */
#include <math.h>
#include <stdint.h>

#include "rover/rotor_speed.h"
#include "test_algos.h"

#define M_PI_VALUE 3.14159265358979323846

#define OMEGA 150.0 /* rad/s, ~1430 rpm */

static uint32_t half_rev_us(double omega)
{
    return (uint32_t)lround(M_PI_VALUE / omega * 1e6);
}

/* Steady rotor: Omega = pi / dt, across a timer wrap. */
static void test_rotor_speed_steady_across_timer_wrap(void)
{
    const rotor_speed_cfg_t cfg = rotor_speed_default_cfg();
    rotor_speed_t st;
    rotor_speed_init(&st);
    uint32_t t = 0xFFFF0000u;
    for (int i = 0; i < 20; i++) {
        rotor_speed_pulse(&st, &cfg, t);
        t += half_rev_us(OMEGA);
    }
    rotor_speed_out_t out;
    rotor_speed_get(&st, &cfg, t - 1000, &out);
    CHECK(out.valid);
    CHECK_NEAR(out.speed_rad_s, OMEGA, 0.05);
    CHECK(out.glitches == 0 && out.missed == 0);
}

/* Unequal blade spacing (182 deg / 178 deg) must average out over a revolution. */
static void test_rotor_speed_cancels_unequal_blade_spacing(void)
{
    const rotor_speed_cfg_t cfg = rotor_speed_default_cfg();
    rotor_speed_t st;
    rotor_speed_init(&st);
    const double rev = 2.0 * M_PI_VALUE / OMEGA * 1e6;
    double t = 1000.0;
    for (int i = 0; i < 21; i++) {
        rotor_speed_pulse(&st, &cfg, (uint32_t)lround(t));
        t += rev * ((i % 2) ? 178.0 : 182.0) / 360.0;
    }
    rotor_speed_out_t out;
    rotor_speed_get(&st, &cfg, (uint32_t)lround(t) - 1000, &out);
    CHECK_NEAR(out.speed_rad_s, OMEGA, 0.05);
}

/* A missed reflection doubles one interval: it must be counted, not read as half speed. */
static void test_rotor_speed_missed_pulse_not_read_as_half_speed(void)
{
    const rotor_speed_cfg_t cfg = rotor_speed_default_cfg();
    rotor_speed_t st;
    rotor_speed_init(&st);
    uint32_t t = 5000;
    for (int i = 0; i < 30; i++) {
        if (i != 15) {
            rotor_speed_pulse(&st, &cfg, t);
        }
        t += half_rev_us(OMEGA);
        rotor_speed_out_t out;
        rotor_speed_get(&st, &cfg, t - half_rev_us(OMEGA), &out);
        if (i > 3) {
            CHECK(out.valid);
            CHECK_NEAR(out.speed_rad_s, OMEGA, 0.1);
        }
    }
    CHECK(st.missed == 1);
}

/* A spurious reflection between blades must be ignored. */
static void test_rotor_speed_rejects_glitch_pulse(void)
{
    const rotor_speed_cfg_t cfg = rotor_speed_default_cfg();
    rotor_speed_t st;
    rotor_speed_init(&st);
    uint32_t t = 5000;
    for (int i = 0; i < 20; i++) {
        rotor_speed_pulse(&st, &cfg, t);
        if (i == 10) {
            rotor_speed_pulse(&st, &cfg, t + 3000); /* 3 ms after a blade */
        }
        t += half_rev_us(OMEGA);
    }
    rotor_speed_out_t out;
    rotor_speed_get(&st, &cfg, t - 2000, &out);
    CHECK_NEAR(out.speed_rad_s, OMEGA, 0.05);
    CHECK(st.glitches == 1);
}

/* An estimate that started on a missed pulse (2x interval) must recover. */
static void test_rotor_speed_recovers_from_estimate_started_on_missed_pulse(void)
{
    const rotor_speed_cfg_t cfg = rotor_speed_default_cfg();
    rotor_speed_t st;
    rotor_speed_init(&st);
    const uint32_t h = half_rev_us(OMEGA);
    uint32_t t = 0;
    rotor_speed_pulse(&st, &cfg, t);
    t += 2 * h; /* first interval spans a missed pulse */
    for (int i = 0; i < 20; i++) {
        rotor_speed_pulse(&st, &cfg, t);
        t += h;
    }
    rotor_speed_out_t out;
    rotor_speed_get(&st, &cfg, t - h, &out);
    CHECK(out.valid);
    CHECK_NEAR(out.speed_rad_s, OMEGA, 0.1);
}

/* No pulses for longer than max_interval: the rotor has stopped, not frozen at speed. */
static void test_rotor_speed_invalid_when_pulses_stop(void)
{
    const rotor_speed_cfg_t cfg = rotor_speed_default_cfg();
    rotor_speed_t st;
    rotor_speed_init(&st);
    uint32_t t = 0;
    for (int i = 0; i < 10; i++) {
        rotor_speed_pulse(&st, &cfg, t);
        t += half_rev_us(OMEGA);
    }
    rotor_speed_out_t out;
    rotor_speed_get(&st, &cfg, t + cfg.max_interval_us, &out);
    CHECK(!out.valid);
    CHECK(out.speed_rad_s == 0.0f);
}

int main(void)
{
    RUN(test_rotor_speed_steady_across_timer_wrap);
    RUN(test_rotor_speed_cancels_unequal_blade_spacing);
    RUN(test_rotor_speed_missed_pulse_not_read_as_half_speed);
    RUN(test_rotor_speed_rejects_glitch_pulse);
    RUN(test_rotor_speed_recovers_from_estimate_started_on_missed_pulse);
    RUN(test_rotor_speed_invalid_when_pulses_stop);
    return ALGO_TEST_EXIT();
}
