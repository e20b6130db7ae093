/* adc.c — the native ADC: each input is one TSL1401 array's AO (model in gpio.c). */
#include "native.h"
#include "tsl1401_model.h"

uint16_t adc_read(hal_adc_t ch)
{
    if ((unsigned)ch >= HAL_ADC_COUNT || tsl_model.index < 0) {
        return 0; /* no readout running: AO is high impedance, the ADC reads ~0 */
    }
    return tsl_model.latched[ch][tsl_model.index];
}
