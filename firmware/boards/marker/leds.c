/* LED geometry table, see leds.h. */
#include "leds.h"

/* 2 sqrt(2) / 3 = 0.9428090416, 1/3 = 0.3333333333 */
const float marker_led_dir[MARKER_LEDS][3] = {
    {0.0f, 0.0f, -1.0f},
    {0.9428090416f, 0.0f, 0.3333333333f},
    {-0.4714045208f, 0.8164965809f, 0.3333333333f},
    {-0.4714045208f, -0.8164965809f, 0.3333333333f},
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
