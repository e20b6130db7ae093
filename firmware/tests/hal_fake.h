/*
 * hal_fake.h — a scriptable hal_t for C unit tests of drivers and board wiring.
 *
 * Time only moves when the test (or the code under test, through delay_us/idle)
 * moves it. UART output is captured per port; input is fed per port. The TSL1401
 * pins drive a strict chip model that also counts protocol violations (a read
 * with no readout running, a wrong number of clocks). The SPI IMU is the native
 * backend's MPU-9250 register model (hal/native/spi.c), so drivers see the chip's
 * register semantics.
 */
#ifndef AW_HAL_FAKE_H
#define AW_HAL_FAKE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal.h"

#define FAKE_TX_CAP (1u << 20)
#define FAKE_RX_RING 4096u

typedef struct {
    uint64_t now_us;
    /* uart */
    bool port_mapped[HAL_PORT_COUNT];
    uint8_t tx[HAL_PORT_COUNT][FAKE_TX_CAP];
    size_t tx_len[HAL_PORT_COUNT];
    size_t tx_room[HAL_PORT_COUNT]; /* uart_tx_free(); uart_write refuses beyond it */
    hal_port_stats_t stats[HAL_PORT_COUNT];
    /* TSL1401 model: what the arrays show when SI is latched */
    uint16_t scene[HAL_ADC_COUNT][128];
    uint16_t latched[HAL_ADC_COUNT][128];
    int tsl_index;
    bool si, clk;
    uint32_t si_latches;
    uint32_t tsl_violations;
    uint64_t last_latch_us;
    /* capture / pwm / watchdog / reset */
    uint16_t pwm[HAL_PWM_COUNT];
    uint32_t pwm_writes;
    bool watchdog_started;
    uint32_t watchdog_timeout_ms;
    uint32_t watchdog_refreshes;
    uint32_t resets;
    uint8_t config[2048];
} fake_hal_state_t;

extern fake_hal_state_t fake;

/* Resets the fake (everything zero, ports HOST mapped, config erased) and returns it. */
const hal_t *fake_hal_init(void);
void fake_map_port(hal_port_t port, bool mapped);
void fake_uart_feed(hal_port_t port, const uint8_t *data, size_t len);
/* Takes (and clears) what the board wrote to a port. */
size_t fake_uart_take(hal_port_t port, uint8_t *out, size_t cap);
void fake_capture_push(hal_capture_t ch, uint32_t t_us, uint8_t level);
void fake_imu_sample(const float gyro_rad_s[3], const float accel_m_s2[3], const float mag_ut[3]);

#endif /* AW_HAL_FAKE_H */
