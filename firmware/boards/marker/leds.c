/* LED geometry table, see leds.h. */
#include "leds.h"

/* 1 / sqrt(3) = 0.5773502692; the host's airwake.tracking.marker.LED_DIRECTIONS_BODY and
 * the simulator's optics use the same table (tests/tracking/test_marker_geometry.py). */
const float marker_led_dir[MARKER_LEDS][3] = {
    {0.5773502692f, 0.5773502692f, 0.5773502692f},
    {0.5773502692f, -0.5773502692f, -0.5773502692f},
    {-0.5773502692f, 0.5773502692f, -0.5773502692f},
    {-0.5773502692f, -0.5773502692f, 0.5773502692f},
};

unsigned marker_led_facing(const float v_body[3])
{
    unsigned best = 0;
    float best_dot = 0.0f;
    for (unsigned k = 0; k < MARKER_LEDS; k++) {
        const float *d = marker_led_dir[k];
        const float dot = d[0] * v_body[0] + d[1] * v_body[1] + d[2] * v_body[2];
        if (k == 0 || dot > best_dot) {
            best = k;
            best_dot = dot;
        }
    }
    return best;
}
