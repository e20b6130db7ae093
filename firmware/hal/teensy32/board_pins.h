/*
 * board_pins.h — the one place that maps HAL roles to Teensy 3.2 pins, per board
 * (STYLE 3). Compiled with exactly one of PINS_LOSA / _MARKER / _ROVER / _BASE.
 *
 * Teensy pin -> MK20DX256 pad used below:
 *   0 PTB16 UART0_RX   1 PTB17 UART0_TX   2 PTD0   3 PTA12 FTM1_CH0  4 PTA13 FTM1_CH1
 *   5 PTD7 FTM0_CH7    6 PTD4 FTM0_CH4    7 PTD2 UART2_RX  8 PTD3 UART2_TX
 *   9 PTC3 UART1_RX   10 PTC4 UART1_TX   11 PTC6 SPI0_SOUT 12 PTC7 SPI0_SIN
 *  13 PTC5 SPI0_SCK / on-board LED       16 PTB0 ADC0_SE8  17 PTB1 ADC0_SE9
 *  18 PTB3 ADC0_SE13  19 PTB2 ADC0_SE12  20 PTD5 FTM0_CH5  21 PTD6 FTM0_CH6
 *  22 PTC1 FTM0_CH0   23 PTC2 FTM0_CH1
 *
 * The host link of every board is a UART (via an FTDI adapter or an XBee);
 * the bare-metal USB CDC stack is not implemented.
 */
#ifndef AW_TEENSY32_BOARD_PINS_H
#define AW_TEENSY32_BOARD_PINS_H

#include <stdint.h>

#include "hal.h"

enum { PA = 0, PB = 1, PC = 2, PD = 3, PE = 4 };

typedef struct {
    uint8_t port; /* PA..PE */
    uint8_t bit;
} pin_t;

typedef struct {
    int8_t uart;   /* 0..2, -1: role not wired on this board */
    uint32_t baud;
    pin_t rx, tx;  /* both mux ALT3 */
} uart_map_t;

typedef struct {
    int8_t ftm;    /* 0..2, -1: not wired */
    uint8_t ch;
    pin_t pin;
    uint8_t alt;   /* PORT mux alternative of the FTM function on this pad */
} ftm_map_t;

typedef struct {
    bool wired;
    pin_t pin;
} gpio_map_t;

#define NO_UART {-1, 0, {0, 0}, {0, 0}}
#define NO_FTM {-1, 0, {0, 0}, 0}
#define UART0_PINS_0_1(baud) {0, (baud), {PB, 16}, {PB, 17}} /* RX pin 0, TX pin 1 */
#define UART1_PINS_9_10(baud) {1, (baud), {PC, 3}, {PC, 4}}  /* RX pin 9, TX pin 10 */
#define UART2_PINS_7_8(baud) {2, (baud), {PD, 2}, {PD, 3}}   /* RX pin 7, TX pin 8 */

/* SPI0 on pins 13 (SCK, PTC5), 11 (MOSI, PTC6), 12 (MISO, PTC7), all ALT2;
 * the IMU's chip select is a plain GPIO. */
#define IMU_CS_PIN {PC, 4} /* pin 10 */

#if defined(PINS_LOSA)
/* LOSA tracker: 4 x TSL1401 (shared SI/CLK, one ADC input each), MPU-9250, host UART. */
static const uart_map_t uart_map[HAL_PORT_COUNT] = {
    [HAL_PORT_HOST] = UART0_PINS_0_1(460800),
    [HAL_PORT_INS] = NO_UART,
    [HAL_PORT_RTK] = NO_UART,
    [HAL_PORT_ROVER] = NO_UART,
    [HAL_PORT_ANEMO] = NO_UART,
};
static const gpio_map_t gpio_map[HAL_PIN_COUNT] = {
    [HAL_PIN_LINE_SI] = {true, {PD, 0}},  /* pin 2 */
    [HAL_PIN_LINE_CLK] = {true, {PA, 12}}, /* pin 3 */
    [HAL_PIN_STATUS_LED] = {false, {0, 0}}, /* pin 13 is SPI SCK here */
};
/* ADC0 single-ended channels of the four arrays' AO: pins 16, 17, 18, 19 */
static const uint8_t adc_channel[HAL_ADC_COUNT] = {8, 9, 13, 12};
#define HAS_ADC 1
#define HAS_SPI_IMU 1
static const ftm_map_t capture_map[HAL_CAPTURE_COUNT] = {
    NO_FTM, NO_FTM, NO_FTM, NO_FTM, NO_FTM, NO_FTM, NO_FTM};
static const ftm_map_t pwm_map[HAL_PWM_COUNT] = {NO_FTM, NO_FTM, NO_FTM, NO_FTM};

#elif defined(PINS_MARKER)
/* Active marker: MPU-9250, four IR LED drivers on PWM, XBee Wi-Fi on the host UART,
 * the carried anemometer's serial output on UART2 (RX pin 7; TX pin 8 unused). */
static const uart_map_t uart_map[HAL_PORT_COUNT] = {
    [HAL_PORT_HOST] = UART0_PINS_0_1(460800),
    [HAL_PORT_INS] = NO_UART,
    [HAL_PORT_RTK] = NO_UART,
    [HAL_PORT_ROVER] = NO_UART,
    [HAL_PORT_ANEMO] = UART2_PINS_7_8(38400), /* Young 81000 RS-232 via a MAX3232 */
};
static const gpio_map_t gpio_map[HAL_PIN_COUNT] = {
    [HAL_PIN_LINE_SI] = {false, {0, 0}},
    [HAL_PIN_LINE_CLK] = {false, {0, 0}},
    [HAL_PIN_STATUS_LED] = {false, {0, 0}}, /* pin 13 is SPI SCK here */
};
static const uint8_t adc_channel[HAL_ADC_COUNT] = {0, 0, 0, 0};
#define HAS_ADC 0
#define HAS_SPI_IMU 1
static const ftm_map_t capture_map[HAL_CAPTURE_COUNT] = {
    NO_FTM, NO_FTM, NO_FTM, NO_FTM, NO_FTM, NO_FTM, NO_FTM};
static const ftm_map_t pwm_map[HAL_PWM_COUNT] = {
    [HAL_PWM_LED0] = {0, 4, {PD, 4}, 4}, /* pin 6, FTM0_CH4 */
    [HAL_PWM_LED1] = {0, 5, {PD, 5}, 4}, /* pin 20, FTM0_CH5 */
    [HAL_PWM_LED2] = {0, 6, {PD, 6}, 4}, /* pin 21, FTM0_CH6 */
    [HAL_PWM_LED3] = {0, 7, {PD, 7}, 4}, /* pin 5, FTM0_CH7 */
};

#elif defined(PINS_ROVER)
/* Rover (helicopter): XBee to the base, Piksi, VN200, rotor IR and tail-servo capture. */
static const uart_map_t uart_map[HAL_PORT_COUNT] = {
    [HAL_PORT_HOST] = UART0_PINS_0_1(460800), /* XBee Wi-Fi module */
    [HAL_PORT_INS] = UART2_PINS_7_8(921600),  /* VN200 UART1 (binary output 1) */
    [HAL_PORT_RTK] = UART1_PINS_9_10(115200), /* Piksi UART0 (SBP) */
    [HAL_PORT_ROVER] = NO_UART,
    [HAL_PORT_ANEMO] = NO_UART,
};
static const gpio_map_t gpio_map[HAL_PIN_COUNT] = {
    [HAL_PIN_LINE_SI] = {false, {0, 0}},
    [HAL_PIN_LINE_CLK] = {false, {0, 0}},
    [HAL_PIN_STATUS_LED] = {true, {PC, 5}}, /* pin 13, on-board LED */
};
static const uint8_t adc_channel[HAL_ADC_COUNT] = {0, 0, 0, 0};
#define HAS_ADC 0
#define HAS_SPI_IMU 0
static const ftm_map_t capture_map[HAL_CAPTURE_COUNT] = {
    NO_FTM, NO_FTM, NO_FTM, NO_FTM, NO_FTM,
    [HAL_CAPTURE_ROTOR_IR] = {1, 0, {PA, 12}, 3},   /* pin 3, FTM1_CH0 */
    [HAL_CAPTURE_TAIL_SERVO] = {1, 1, {PA, 13}, 3}, /* pin 4, FTM1_CH1 */
};
static const ftm_map_t pwm_map[HAL_PWM_COUNT] = {NO_FTM, NO_FTM, NO_FTM, NO_FTM};

#elif defined(PINS_BASE)
/* Base (ship): laptop UART, XBee from the rover, VN200, five RC PWM inputs.
 * The MK20DX256VLH7 has three UARTs: the base's Piksi (HAL_PORT_RTK) needs a fourth
 * serial link (the USB CDC host link would free UART0) and is not wired here. */
static const uart_map_t uart_map[HAL_PORT_COUNT] = {
    [HAL_PORT_HOST] = UART0_PINS_0_1(921600),  /* FTDI to the laptop */
    [HAL_PORT_INS] = UART2_PINS_7_8(921600),   /* VN200 */
    [HAL_PORT_RTK] = NO_UART,
    [HAL_PORT_ROVER] = UART1_PINS_9_10(460800), /* XBee Wi-Fi from the rover */
    [HAL_PORT_ANEMO] = NO_UART,
};
static const gpio_map_t gpio_map[HAL_PIN_COUNT] = {
    [HAL_PIN_LINE_SI] = {false, {0, 0}},
    [HAL_PIN_LINE_CLK] = {false, {0, 0}},
    [HAL_PIN_STATUS_LED] = {true, {PC, 5}}, /* pin 13, on-board LED */
};
static const uint8_t adc_channel[HAL_ADC_COUNT] = {0, 0, 0, 0};
#define HAS_ADC 0
#define HAS_SPI_IMU 0
static const ftm_map_t capture_map[HAL_CAPTURE_COUNT] = {
    [HAL_CAPTURE_RC1] = {0, 0, {PC, 1}, 4}, /* pin 22, FTM0_CH0: aileron */
    [HAL_CAPTURE_RC2] = {0, 1, {PC, 2}, 4}, /* pin 23, FTM0_CH1: elevator */
    [HAL_CAPTURE_RC3] = {0, 4, {PD, 4}, 4}, /* pin 6, FTM0_CH4: collective */
    [HAL_CAPTURE_RC4] = {0, 5, {PD, 5}, 4}, /* pin 20, FTM0_CH5: rudder */
    [HAL_CAPTURE_RC5] = {0, 6, {PD, 6}, 4}, /* pin 21, FTM0_CH6: aux / gyro gain */
    NO_FTM, NO_FTM,
};
static const ftm_map_t pwm_map[HAL_PWM_COUNT] = {NO_FTM, NO_FTM, NO_FTM, NO_FTM};

#else
#error "define one of PINS_LOSA, PINS_MARKER, PINS_ROVER, PINS_BASE"
#endif

#endif /* AW_TEENSY32_BOARD_PINS_H */
