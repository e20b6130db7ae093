/* tsl1401_model.h — state of the native TSL1401 model (gpio.c, adc.c). */
#ifndef AW_TSL1401_MODEL_H
#define AW_TSL1401_MODEL_H

#include <stdbool.h>
#include <stdint.h>

#include "hal.h"

#define TSL_MODEL_PIXELS 128u

typedef struct {
    float rate[HAL_ADC_COUNT][TSL_MODEL_PIXELS];   /* counts per µs of exposure */
    float dark[HAL_ADC_COUNT][TSL_MODEL_PIXELS];   /* counts, any exposure */
    float charge[HAL_ADC_COUNT][TSL_MODEL_PIXELS]; /* counts integrated since the last latch */
    uint64_t charge_t;                             /* sim time charge is integrated up to */
    uint16_t latched[HAL_ADC_COUNT][TSL_MODEL_PIXELS];
    int index;       /* pixel on AO, -1 when no readout runs */
    bool si;
    bool clk;
    bool status_led;
    uint32_t latches; /* SI latches since start (for tests) */
} tsl_model_t;

extern tsl_model_t tsl_model;

#endif /* AW_TSL1401_MODEL_H */
