/* Main-rotor speed from IR reflection timestamps (reference §5.2): an IR beam under the
 * rotor sees each of the two blades once per revolution, so consecutive reflections
 * are half a revolution apart and Omega = pi / dt.
 *
 * Input: the input-capture timestamp (us, free-running uint32_t; differences are
 * wrap-safe) of every reflection. Filtering against the running interval estimate:
 *   dt < min_interval_us or dt < 0.7 x estimate  -> glitch: ignored, the next pulse is
 *                                                  measured from the last good one
 *   dt ~ k x estimate (k = 2, 3, within 20 %)   -> k - 1 missed pulses, dt / k used
 *   dt > max_interval_us                        -> rotor stopped/lost: restart
 *   otherwise far from the estimate             -> outlier
 * Three outliers in a row mean the rate really changed: the estimate restarts from
 * it. An "early" pulse that splits the next interval in half means the estimate locked
 * on twice the real interval (it started across a missed pulse): it is halved.
 * Speed is reported from the mean of the last two accepted half-revolution intervals,
 * which cancels the blades' unequal spacing. It is valid once two consecutive
 * intervals agree and until no pulse arrives for max_interval_us.
 */
#ifndef AW_ROTOR_SPEED_H
#define AW_ROTOR_SPEED_H

#include <stdint.h>

typedef struct {
    uint32_t min_interval_us; /* shorter: glitch (2000 us = 1570 rad/s) */
    uint32_t max_interval_us; /* longer: stopped (200000 us = 15.7 rad/s) */
} rotor_speed_cfg_t;

typedef struct {
    uint32_t last_pulse_us;
    uint32_t estimate_us;      /* running half-revolution interval, 0 = none */
    uint32_t prev_interval_us; /* last two accepted intervals */
    uint32_t interval_us;
    uint8_t have_pulse;
    uint8_t agreed;            /* two consecutive intervals agreed */
    uint8_t outliers_in_row;
    uint8_t have_early;
    uint32_t early_us;         /* last pulse rejected as early */
    uint32_t pulses;           /* counters */
    uint32_t glitches;
    uint32_t missed;
} rotor_speed_t;

typedef struct {
    float speed_rad_s;      /* 0 when not valid */
    uint32_t interval_us;   /* last accepted half-revolution interval */
    uint32_t pulses, glitches, missed;
    uint8_t valid;
} rotor_speed_out_t;

rotor_speed_cfg_t rotor_speed_default_cfg(void);
void rotor_speed_init(rotor_speed_t *st);
void rotor_speed_pulse(rotor_speed_t *st, const rotor_speed_cfg_t *cfg, uint32_t t_us);
void rotor_speed_get(const rotor_speed_t *st, const rotor_speed_cfg_t *cfg, uint32_t now_us, rotor_speed_out_t *out);

#endif
