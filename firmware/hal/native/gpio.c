/*
 * gpio.c — digital outputs of the native backend, and the TSL1401 chip model
 * behind SI and CLK (the ADC side is adc.c).
 *
 * The four arrays are modelled as the datasheet describes them: a CLK rising edge
 * with SI high latches the charge integrated since the previous latch (plus the
 * dark level), clears it, and puts pixel 1 on AO; every further rising edge moves
 * AO to the next pixel; the 129th ends the readout. The simulator sends irradiance
 * (SIM_LINE: counts per µs of exposure, dark counts); charge is integrated piece
 * by piece between irradiance changes, so the exposure the board chooses — the
 * time between SI latches — scales the signal and saturation happens where the
 * board's exposure control put it.
 */
#include <math.h>
#include <string.h>

#include "native.h"
#include "tsl1401_model.h"

tsl_model_t tsl_model;

static void integrate_to(uint64_t t_sim)
{
    tsl_model_t *m = &tsl_model;
    if (t_sim <= m->charge_t) {
        return;
    }
    float dt = (float)(t_sim - m->charge_t);
    for (unsigned s = 0; s < HAL_ADC_COUNT; s++) {
        for (unsigned i = 0; i < TSL_MODEL_PIXELS; i++) {
            m->charge[s][i] += m->rate[s][i] * dt;
        }
    }
    m->charge_t = t_sim;
}

static uint16_t quantize(float v)
{
    if (!(v > 0.0f)) { /* also NaN */
        return 0;
    }
    if (v >= (float)HAL_ADC_MAX) {
        return (uint16_t)HAL_ADC_MAX;
    }
    return (uint16_t)lrintf(v);
}

void tsl_emu_set_line(unsigned sensor, uint64_t t_sim, const float *rate, const float *dark)
{
    tsl_model_t *m = &tsl_model;
    integrate_to(t_sim);
    for (unsigned i = 0; i < TSL_MODEL_PIXELS; i++) {
        m->rate[sensor][i] = rate[i] > 0.0f ? rate[i] : 0.0f; /* also NaN -> 0 */
        m->dark[sensor][i] = dark[i];
    }
}

static void clk_rising(void)
{
    tsl_model_t *m = &tsl_model;
    if (m->si) {
        integrate_to(native_now_sim());
        for (unsigned s = 0; s < HAL_ADC_COUNT; s++) {
            for (unsigned i = 0; i < TSL_MODEL_PIXELS; i++) {
                m->latched[s][i] = quantize(m->dark[s][i] + m->charge[s][i]);
                m->charge[s][i] = 0.0f;
            }
        }
        m->index = 0;
        m->latches++;
    } else if (m->index >= 0) {
        m->index++;
        if (m->index >= (int)TSL_MODEL_PIXELS) {
            m->index = -1; /* the 129th edge: AO goes quiet */
        }
    }
}

void tsl_emu_reset_pins(void)
{
    tsl_model.si = false;
    tsl_model.clk = false;
    tsl_model.index = -1;
    tsl_model.status_led = false;
}

void gpio_write(hal_pin_t pin, bool high)
{
    tsl_model_t *m = &tsl_model;
    switch (pin) {
    case HAL_PIN_LINE_SI:
        m->si = high;
        break;
    case HAL_PIN_LINE_CLK:
        if (high && !m->clk) {
            clk_rising();
        }
        m->clk = high;
        break;
    case HAL_PIN_STATUS_LED:
        m->status_led = high;
        break;
    default:
        break;
    }
}
