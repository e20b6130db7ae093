/*
 * native.h — internals shared by the files of the native (POSIX, SIL) backend.
 * Board code never sees this header; it gets the `hal_t` from native_start().
 *
 * Time: the simulator's clock ("sim time", µs, u64) drives everything. Board time
 * (what micros() returns) is sim time since the last boot, scaled by the clock
 * drift and shifted by the offset given on the command line — so the host's clock
 * mapping has something real to do. Records on the sim channel carry sim time.
 *
 * Interrupts are modelled as records from the simulator applied when the clock
 * reaches their time (sim_chan.c); the board runs board_task() between them.
 * See docs/sim-channel.md.
 */
#ifndef AW_HAL_NATIVE_H
#define AW_HAL_NATIVE_H

#include <setjmp.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal.h"

typedef enum { NATIVE_STEPPED = 1, NATIVE_WALL = 2 } native_mode_t;

/* ---- main.c / hal.c ---- */
/* Parses the command line, opens ports, connects the sim channel and returns the
 * HAL; exits with status 2 (message on stderr) on a usage error. */
const hal_t *native_start(int argc, char **argv, const char *board_name, uint8_t board_id);
/* main() calls setjmp on this right before board_init(): a reset (watchdog,
 * hal->reset(), or one the simulator asks for) longjmps back there. */
extern jmp_buf native_reset_jmp;
/* Performs a reset with this cause: clears the MCU-side state, reports it on the
 * channel, longjmps to native_reset_jmp. */
_Noreturn void native_reboot(hal_reset_cause_t cause);

/* ---- time.c ---- */
typedef struct {
    native_mode_t mode;
    uint64_t now_sim;   /* current simulator time (stepped: advanced by idle) */
    uint64_t boot_sim;  /* simulator time of the last boot */
    double drift;       /* board clock rate error (ppm * 1e-6) */
    uint64_t offset_us; /* board clock at boot */
} native_clock_t;

extern native_clock_t native_clock;

uint64_t native_mono_us(void);               /* CLOCK_MONOTONIC in µs */
uint64_t native_board_us(uint64_t sim_us);   /* sim time -> board micros() */
uint64_t native_sim_us(uint64_t board_us);   /* board micros() -> first sim time reaching it */
uint64_t native_now_sim(void);               /* wall mode reads the clock; stepped returns now */
uint64_t native_micros(void);
void native_delay_us(uint32_t us);
void native_idle(uint64_t until_board_us);

/* ---- sim_chan.c: the channel to hil_sim ---- */
#define NATIVE_CHAN_MAX_PACKET 131072u

bool chan_connect(const char *path, native_mode_t mode, const char *board_name, uint8_t board_id);
bool chan_connected(void);
/* Applies every received record due at or before now_sim; true if any was. */
bool chan_apply_due(uint64_t now_sim);
/* Sim time of the next pending record, UINT64_MAX if none. */
uint64_t chan_next_time(void);
/* Stepped: whether an ADVANCE is being worked on, and its time. */
bool chan_in_step(void);
uint64_t chan_step_end(void);
/* Stepped: drains the ports, sends the outputs and IDLE(now); true when receive
 * bytes arrived from a port fd meanwhile. */
bool chan_end_step(uint64_t now_sim);
/* Stepped: blocks for the next packet and starts its step. Exits the process
 * (status 0) when the simulator closes the channel. */
void chan_step(void);
/* Wall: waits at most timeout_us for a packet (when none is pending) or port
 * bytes; reads the packet. Returns true when an input arrived. */
bool chan_wall_poll(uint64_t timeout_us);
/* Output records (queued, sent at the end of the step or when the buffer fills). */
void chan_emit(uint8_t type, uint8_t chan, uint64_t t_sim, const void *body, size_t len);
void chan_flush(void);

/* ---- uart.c ---- */
bool uart_map(const char *spec, char *err, size_t err_len); /* "ROLE=PATH[@BAUD]" or "ROLE=sim" */
void uart_reset(void);                   /* rings and counters cleared at reboot */
void uart_sim_input(hal_port_t port, const uint8_t *data, size_t len);
/* Sends what the transmit rings may send by now (fds / UART_TX records). */
void uart_service_tx(uint64_t now_sim);
/* Transmit as above, then reads the port fds; true when new rx bytes arrived. */
bool uart_service(uint64_t now_sim);
int uart_poll_fds(int *fds, int max); /* fds to wait on in wall mode */
bool uart_write(hal_port_t port, const uint8_t *data, size_t len);
size_t uart_read(hal_port_t port, uint8_t *buf, size_t cap);
size_t uart_tx_free(hal_port_t port);
void uart_stats(hal_port_t port, hal_port_stats_t *out);

/* ---- gpio.c, adc.c: the TSL1401 arrays behind SI/CLK and the ADC ---- */
void gpio_write(hal_pin_t pin, bool high);
uint16_t adc_read(hal_adc_t ch);
void tsl_emu_reset_pins(void);
/* New irradiance for one array from this sim time on: counts per µs of exposure
 * and a dark level (counts, independent of exposure). */
void tsl_emu_set_line(unsigned sensor, uint64_t t_sim, const float *rate, const float *dark);

/* ---- spi.c: the MPU-9250 behind HAL_SPI_IMU ---- */
bool spi_transfer(hal_spi_t dev, uint32_t max_hz, const uint8_t *tx, uint8_t *rx, size_t len);
void imu_emu_sample(unsigned dev, const float gyro_rad_s[3], const float accel_m_s2[3],
                    const float mag_ut[3], float temp_c);

/* ---- capture.c, pwm.c ---- */
void capture_reset(void);
void capture_sim_edge(hal_capture_t ch, uint64_t t_sim, uint8_t level);
size_t capture_read(hal_capture_t ch, hal_edge_t *out, size_t cap);
uint32_t capture_overruns(hal_capture_t ch);
void pwm_write(hal_pwm_t ch, uint16_t duty);
void pwm_reset(void);

/* ---- watchdog.c, config.c ---- */
void watchdog_start(uint32_t timeout_ms);
void watchdog_refresh(void);
void watchdog_reset(void);
void watchdog_check(uint64_t now_sim); /* reboots when expired */
bool config_open(const char *path, char *err, size_t err_len);
bool config_read(uint32_t offset, void *buf, size_t len);
bool config_write(uint32_t offset, const void *buf, size_t len);

#endif /* AW_HAL_NATIVE_H */
