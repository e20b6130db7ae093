/*
 * hal.h — the only interface board code has to the hardware.
 *
 * Board logic (firmware/boards/<name>/) receives a `const hal_t *` and calls
 * through it; it never includes a backend or vendor header. Two backends fill
 * the table with designated initializers:
 *   hal/teensy32/  MK20DX256 bare metal (registers, interrupts, ring buffers)
 *   hal/native/    POSIX process for SIL: ptys/sim channel, clock from hil_sim
 *
 * Everything is addressed by ROLE, not by peripheral: HAL_PORT_INS, not UART2.
 * Only the backend's pin header (hal/teensy32/board_pins.h) maps roles to pins.
 *
 * Rules every backend keeps:
 *   - nothing blocks except delay_us(), adc_read() (one conversion) and
 *     spi_transfer() (one short transaction);
 *   - interrupt handlers only move bytes/samples into ring buffers; whatever
 *     does not fit is counted (hal_port_stats_t, capture overruns), never silent;
 *   - time is one monotonic microsecond clock since boot (micros()); input
 *     capture timestamps are on the same clock.
 */
#ifndef AW_HAL_H
#define AW_HAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Serial ports by role. A role a board does not use may be left unmapped: writes
 * to it are refused (counted as tx_dropped), reads return 0 bytes. */
typedef enum {
    HAL_PORT_HOST = 0, /* our protocol frames to the host (rover: the XBee to the base) */
    HAL_PORT_INS = 1,  /* VN200 binary output packets (rover, base) */
    HAL_PORT_RTK = 2,  /* Piksi RTK, SBP (rover, base) */
    HAL_PORT_ROVER = 3, /* base only: the XBee link that carries the rover's frames */
    HAL_PORT_ANEMO = 4, /* marker only: the sonic anemometer's ASCII output (Young 81000) */
    HAL_PORT_COUNT
} hal_port_t;

/* Analogue inputs: the four TSL1401 line sensors of the LOSA tracker (AO pins). */
typedef enum {
    HAL_ADC_LINE0 = 0,
    HAL_ADC_LINE1 = 1,
    HAL_ADC_LINE2 = 2,
    HAL_ADC_LINE3 = 3,
    HAL_ADC_COUNT
} hal_adc_t;

/* ADC results are right-aligned 12-bit on every backend. */
#define HAL_ADC_BITS 12
#define HAL_ADC_MAX ((1u << HAL_ADC_BITS) - 1u)

/* Digital outputs/inputs. */
typedef enum {
    HAL_PIN_LINE_SI = 0,  /* TSL1401 SI, shared by the four line sensors */
    HAL_PIN_LINE_CLK = 1, /* TSL1401 CLK, shared */
    HAL_PIN_STATUS_LED = 2,
    HAL_PIN_COUNT
} hal_pin_t;

/* SPI devices (the backend owns chip select and bus setup). */
typedef enum {
    HAL_SPI_IMU = 0, /* MPU-9250 (LOSA, marker) */
    HAL_SPI_COUNT
} hal_spi_t;

/* Input-capture channels: every edge is timestamped by hardware. */
typedef enum {
    HAL_CAPTURE_RC1 = 0, /* base: RC receiver channels 1..5 (PWM pulse widths) */
    HAL_CAPTURE_RC2 = 1,
    HAL_CAPTURE_RC3 = 2,
    HAL_CAPTURE_RC4 = 3,
    HAL_CAPTURE_RC5 = 4,
    HAL_CAPTURE_ROTOR_IR = 5,   /* rover: IR reflection from the two main-rotor blades */
    HAL_CAPTURE_TAIL_SERVO = 6, /* rover: tail-servo PWM from the heading-hold gyro */
    HAL_CAPTURE_COUNT
} hal_capture_t;

/* PWM outputs. */
typedef enum {
    HAL_PWM_LED0 = 0, /* marker: the four IR LED current drivers */
    HAL_PWM_LED1 = 1,
    HAL_PWM_LED2 = 2,
    HAL_PWM_LED3 = 3,
    HAL_PWM_COUNT
} hal_pwm_t;

#define HAL_PWM_FULL 65535u /* pwm_write duty for 100 % */

/* One input-capture edge. t_us is the low 32 bits of micros() at the edge:
 * subtract two of them with unsigned arithmetic (wrap-safe for 71 minutes). */
typedef struct {
    uint32_t t_us;
    uint8_t level; /* 1: rising edge (line now high), 0: falling edge */
} hal_edge_t;

/* Per-port counters since boot. */
typedef struct {
    uint32_t rx_bytes;     /* bytes delivered to the receive ring */
    uint32_t tx_bytes;     /* bytes accepted for transmission */
    uint32_t rx_overruns;  /* bytes lost on receive: ring full or hardware overrun */
    uint32_t rx_errors;    /* framing / noise / parity errors seen by the UART */
    uint32_t tx_dropped;   /* bytes refused by uart_write (ring full or port unmapped) */
} hal_port_stats_t;

/* Values match the heartbeat message's reset_cause enum (protocol/messages). */
typedef enum {
    HAL_RESET_POWER_ON = 0,
    HAL_RESET_WATCHDOG = 1,
    HAL_RESET_SOFTWARE = 2, /* hal->reset() */
    HAL_RESET_BROWNOUT = 3,
    HAL_RESET_EXTERNAL = 4, /* reset pin, or the simulator asking for one */
    HAL_RESET_OTHER = 255
} hal_reset_cause_t;

typedef struct hal {
    const char *target; /* "teensy32" or "native" */

    /* --- time --- */
    uint64_t (*micros)(void); /* µs since boot, monotonic */
    /* Busy-wait (teensy) or advance the simulated clock (native) by at least us. */
    void (*delay_us)(uint32_t us);
    /* Sleep until micros() >= until_us or an input event (byte, edge, sample)
     * arrives, whichever is first; may return early. Called by the target's main
     * between board_task() calls — board code does not need it. */
    void (*idle)(uint64_t until_us);

    /* --- serial ports (non-blocking) --- */
    /* Queue all len bytes or none: returns false (and counts tx_dropped) when the
     * transmit ring lacks room, so a frame is never cut in half. */
    bool (*uart_write)(hal_port_t port, const uint8_t *data, size_t len);
    size_t (*uart_read)(hal_port_t port, uint8_t *buf, size_t cap);
    size_t (*uart_tx_free)(hal_port_t port);
    void (*uart_stats)(hal_port_t port, hal_port_stats_t *out);

    /* --- GPIO + ADC (TSL1401 SI/CLK sequencing is drivers/tsl1401.c) --- */
    void (*gpio_write)(hal_pin_t pin, bool high);
    uint16_t (*adc_read)(hal_adc_t ch); /* one conversion, 0..HAL_ADC_MAX */

    /* --- SPI: one transaction with chip select held; false on a bus error --- */
    bool (*spi_transfer)(hal_spi_t dev, uint32_t max_hz, const uint8_t *tx, uint8_t *rx,
                         size_t len);

    /* --- input capture: edges oldest first; returns the number copied --- */
    size_t (*capture_read)(hal_capture_t ch, hal_edge_t *out, size_t cap);
    uint32_t (*capture_overruns)(hal_capture_t ch); /* edges lost since boot */

    /* --- PWM output: duty 0..HAL_PWM_FULL --- */
    void (*pwm_write)(hal_pwm_t ch, uint16_t duty);

    /* --- watchdog: once started it cannot be stopped; refresh from the task --- */
    void (*watchdog_start)(uint32_t timeout_ms);
    void (*watchdog_refresh)(void);

    /* --- reset and boot information --- */
    void (*reset)(void); /* does not return */
    hal_reset_cause_t (*reset_cause)(void);
    uint32_t (*boot_count)(void); /* resets since power-on (0 on the first boot) */

    /* --- persistent configuration (EEPROM-like, byte addressed) --- */
    uint32_t config_size;
    bool (*config_read)(uint32_t offset, void *buf, size_t len);
    bool (*config_write)(uint32_t offset, const void *buf, size_t len);
} hal_t;

#ifdef __cplusplus
}
#endif

#endif /* AW_HAL_H */
