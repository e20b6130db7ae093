/*
 * tsl1401.h — TSL1401 128-pixel linear sensor arrays sharing SI and CLK.
 *
 * The LOSA tracker wires four arrays to one SI and one CLK line and one ADC input
 * each (HAL_ADC_LINE0..3), so all four integrate over the same window and are
 * read out pixel by pixel together (reference §3.3.1).
 *
 * Chip behaviour the sequencing relies on (TSL1401 datasheet): SI is latched on a
 * CLK rising edge; that edge ends the previous integration, starts the next one
 * and puts pixel 1 on AO; each further rising edge advances one pixel; the 129th
 * rising edge ends the readout. The exposure of a line is therefore the time
 * between two SI latches (on silicon, minus the 18 clocks after SI before charge
 * transfer completes — a few tens of µs at our clock rate).
 *
 * Two calls give any exposure shorter than the frame period:
 *     tsl1401_flush()  at t0          — clocks the array out without converting
 *     tsl1401_read()   at t0 + e      — converts the lines integrated over e
 */
#ifndef AW_TSL1401_H
#define AW_TSL1401_H

#include <stdint.h>

#include "hal.h"

#define TSL1401_PIXELS 128
#define TSL1401_MAX_SENSORS HAL_ADC_COUNT

typedef struct {
    uint64_t last_si_us;    /* micros() at the last SI latch */
    uint32_t exposure_us;   /* integration time of the lines last read */
} tsl1401_t;

/* Puts SI/CLK low and flushes once so the next read has a defined exposure. */
void tsl1401_init(const hal_t *hal, tsl1401_t *st);

/* Ends the running integration and starts a new one without converting. */
void tsl1401_flush(const hal_t *hal, tsl1401_t *st);

/* Latches and converts n_sensors lines (sensor s on HAL_ADC_LINE0 + s) into
 * lines[s][0..127]; starts the next integration. Returns the exposure in µs of
 * the lines read (time since the previous SI latch, saturating at UINT32_MAX). */
uint32_t tsl1401_read(const hal_t *hal, tsl1401_t *st, uint16_t lines[][TSL1401_PIXELS],
                      unsigned n_sensors);

#endif /* AW_TSL1401_H */
