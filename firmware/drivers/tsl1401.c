/* tsl1401.c — SI/CLK sequencing for TSL1401 arrays; see tsl1401.h. */
#include "tsl1401.h"

/* SI high across one CLK rising edge: the chip latches it, ends the running
 * integration and starts the next; pixel 1 is on AO afterwards. */
static void latch_si(const hal_t *hal, tsl1401_t *st)
{
    hal->gpio_write(HAL_PIN_LINE_SI, true);
    hal->gpio_write(HAL_PIN_LINE_CLK, true);
    uint64_t now = hal->micros();
    hal->gpio_write(HAL_PIN_LINE_SI, false);
    uint64_t exposure = now - st->last_si_us;
    st->exposure_us = exposure > UINT32_MAX ? UINT32_MAX : (uint32_t)exposure;
    st->last_si_us = now;
}

static void clock_pulse(const hal_t *hal)
{
    hal->gpio_write(HAL_PIN_LINE_CLK, false);
    hal->gpio_write(HAL_PIN_LINE_CLK, true);
}

void tsl1401_init(const hal_t *hal, tsl1401_t *st)
{
    hal->gpio_write(HAL_PIN_LINE_SI, false);
    hal->gpio_write(HAL_PIN_LINE_CLK, false);
    st->last_si_us = hal->micros();
    st->exposure_us = 0;
    tsl1401_flush(hal, st);
}

void tsl1401_flush(const hal_t *hal, tsl1401_t *st)
{
    latch_si(hal, st);
    /* 128 more rising edges: the last is the 129th, which ends the readout. */
    for (unsigned px = 0; px < TSL1401_PIXELS; px++) {
        clock_pulse(hal);
    }
    hal->gpio_write(HAL_PIN_LINE_CLK, false);
}

uint32_t tsl1401_read(const hal_t *hal, tsl1401_t *st, uint16_t lines[][TSL1401_PIXELS],
                      unsigned n_sensors)
{
    if (n_sensors > TSL1401_MAX_SENSORS) {
        n_sensors = TSL1401_MAX_SENSORS;
    }
    latch_si(hal, st);
    for (unsigned px = 0; px < TSL1401_PIXELS; px++) {
        /* all arrays hold pixel px on AO now; convert them one after another */
        for (unsigned s = 0; s < n_sensors; s++) {
            lines[s][px] = hal->adc_read((hal_adc_t)(HAL_ADC_LINE0 + s));
        }
        clock_pulse(hal);
    }
    hal->gpio_write(HAL_PIN_LINE_CLK, false);
    return st->exposure_us;
}
