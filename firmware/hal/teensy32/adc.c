/*
 * adc.c — ADC0, 12-bit single-ended, one polled conversion per call (the TSL1401
 * readout converts 4 x 128 pixels back to back). ADCK = bus / 2 / 2 = 12 MHz,
 * short sample time, high-speed configuration, calibrated at start.
 */
#include "board_pins.h"
#include "regs.h"
#include "teensy32.h"

#if HAS_ADC
static void calibrate(void)
{
    ADC0_SC3 = ADC_SC3_CAL | ADC_SC3_AVGE | ADC_SC3_AVGS(3); /* calibrate with 32 averages */
    while (ADC0_SC3 & ADC_SC3_CAL) {
    }
    if (ADC0_SC3 & ADC_SC3_CALF) {
        return; /* keep the reset gains: uncalibrated, still usable */
    }
    uint32_t sum = ADC0_CLPS + ADC0_CLP(4) + ADC0_CLP(3) + ADC0_CLP(2) + ADC0_CLP(1) + ADC0_CLP(0);
    ADC0_PG = (sum / 2u) | 0x8000u;
    sum = ADC0_CLMS + ADC0_CLM(4) + ADC0_CLM(3) + ADC0_CLM(2) + ADC0_CLM(1) + ADC0_CLM(0);
    ADC0_MG = (sum / 2u) | 0x8000u;
}
#endif

void adc_init(void)
{
#if HAS_ADC
    SIM_SCGC6 |= SIM_SCGC6_ADC0;
    ADC0_CFG1 = ADC_CFG1_ADIV(1) | ADC_CFG1_MODE(1) | ADC_CFG1_ADICLK(1);
    ADC0_CFG2 = ADC_CFG2_MUXSEL | ADC_CFG2_ADHSC;
    ADC0_SC2 = 0; /* software trigger, VREFH/VREFL reference (3.3 V) */
    calibrate();
    ADC0_SC3 = 0; /* single conversions, no averaging */
#endif
}

uint16_t adc_read(hal_adc_t ch)
{
#if HAS_ADC
    if ((unsigned)ch >= HAL_ADC_COUNT) {
        return 0;
    }
    ADC0_SC1A = ADC_SC1_ADCH(adc_channel[ch]);
    while ((ADC0_SC1A & ADC_SC1_COCO) == 0) {
    }
    return (uint16_t)ADC0_RA;
#else
    (void)ch;
    return 0;
#endif
}
