/* teensy32.h — internals shared by the files of the Teensy 3.2 backend. */
#ifndef AW_TEENSY32_H
#define AW_TEENSY32_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal.h"

const hal_t *teensy_hal_init(void);

/* time.c */
void teensy_time_init(void);
uint64_t teensy_micros(void);
void teensy_delay_us(uint32_t us);
void teensy_idle(uint64_t until_us);
void teensy_event(void); /* an ISR queued something: wake idle() */

/* uart.c */
void uart_init(void);
bool uart_write(hal_port_t port, const uint8_t *data, size_t len);
size_t uart_read(hal_port_t port, uint8_t *buf, size_t cap);
size_t uart_tx_free(hal_port_t port);
void uart_stats(hal_port_t port, hal_port_stats_t *out);

/* gpio.c, adc.c, spi.c */
void gpio_init(void);
void gpio_write(hal_pin_t pin, bool high);
void adc_init(void);
uint16_t adc_read(hal_adc_t ch);
void spi_init(void);
bool spi_transfer(hal_spi_t dev, uint32_t max_hz, const uint8_t *tx, uint8_t *rx, size_t len);

/* capture.c, pwm.c */
void capture_init(void);
size_t capture_read(hal_capture_t ch, hal_edge_t *out, size_t cap);
uint32_t capture_overruns(hal_capture_t ch);
void pwm_init(void);
void pwm_write(hal_pwm_t ch, uint16_t duty);

/* watchdog.c, config.c */
void watchdog_start(uint32_t timeout_ms);
void watchdog_refresh(void);
void config_init(void);
bool config_read(uint32_t offset, void *buf, size_t len);
bool config_write(uint32_t offset, const void *buf, size_t len);

#endif /* AW_TEENSY32_H */
