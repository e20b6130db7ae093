/*
 * pwm.c — FTM edge-aligned PWM (the marker's LED current drivers): F_BUS / 2048
 * = 23.4 kHz, 11-bit resolution; the HAL's 16-bit duty is scaled onto MOD + 1.
 */
#include "board_pins.h"
#include "regs.h"
#include "teensy32.h"

#define PWM_MOD 2047u

void pwm_init(void)
{
    bool started[3] = {false, false, false};
    for (int i = 0; i < HAL_PWM_COUNT; i++) {
        const ftm_map_t *m = &pwm_map[i];
        if (m->ftm < 0) {
            continue;
        }
        uint32_t ftm = (uint32_t)m->ftm;
        if (!started[ftm]) {
            if (ftm == 0u) {
                SIM_SCGC6 |= SIM_SCGC6_FTM0;
            } else if (ftm == 1u) {
                SIM_SCGC6 |= SIM_SCGC6_FTM1;
            } else {
                SIM_SCGC3 |= SIM_SCGC3_FTM2;
            }
            FTM_MODE(ftm) = FTM_MODE_WPDIS;
            FTM_SC(ftm) = 0;
            FTM_CNTIN(ftm) = 0;
            FTM_MOD(ftm) = PWM_MOD;
            FTM_CNT(ftm) = 0;
            FTM_SC(ftm) = FTM_SC_CLKS(1) | FTM_SC_PS(0);
            started[ftm] = true;
        }
        FTM_CSC(ftm, m->ch) = FTM_CSC_MSB | FTM_CSC_ELSB; /* high-true pulses */
        FTM_CV(ftm, m->ch) = 0;
        PORT_PCR(m->pin.port, m->pin.bit) = PORT_PCR_MUX(m->alt) | PORT_PCR_DSE;
    }
}

void pwm_write(hal_pwm_t ch, uint16_t duty)
{
    if ((unsigned)ch >= HAL_PWM_COUNT || pwm_map[ch].ftm < 0) {
        return;
    }
    /* CnV > MOD gives 100 %: duty 65535 -> 2048 */
    uint32_t cv = ((uint32_t)duty * (PWM_MOD + 1u) + 32767u) / 65535u;
    FTM_CV((uint32_t)pwm_map[ch].ftm, pwm_map[ch].ch) = cv;
}
