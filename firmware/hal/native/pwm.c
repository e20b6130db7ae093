/* pwm.c — native PWM outputs: every change is reported to the simulator (SIM_PWM). */
#include "native.h"
#include "sim_proto.h"

static uint16_t duty_now[HAL_PWM_COUNT];

void pwm_write(hal_pwm_t ch, uint16_t duty)
{
    if ((unsigned)ch >= HAL_PWM_COUNT || duty_now[ch] == duty) {
        return;
    }
    duty_now[ch] = duty;
    uint8_t body[SIM_PWM_BODY] = {(uint8_t)(duty & 0xFFu), (uint8_t)(duty >> 8), 0, 0};
    chan_emit(SIM_PWM, (uint8_t)ch, native_now_sim(), body, sizeof(body));
}

void pwm_reset(void)
{
    for (unsigned i = 0; i < HAL_PWM_COUNT; i++) {
        pwm_write((hal_pwm_t)i, 0); /* pins return to their reset state: off */
    }
}
