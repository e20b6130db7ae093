/*
 * mpu9250.h — MPU-9250 9-axis IMU over SPI (LOSA and marker boards; reference
 * §3.3.1.4: "an InvenSense MPU9250 9DOF IMU").
 *
 * Configuration: gyro ±2000 °/s, accel ±16 g, DLPF 184 Hz, 1 kHz internal sample
 * rate; the AK8963 magnetometer is read by the MPU's I2C master (16-bit, 100 Hz)
 * into EXT_SENS_DATA, so one 22-byte SPI burst returns everything. The board reads
 * on its own schedule (the marker at 450 Hz) and gets the latest sample.
 *
 * Axes: everything is returned in the accel/gyro chip frame; the magnetometer is
 * remapped from the AK8963's axes (x_mpu = y_ak, y_mpu = x_ak, z_mpu = -z_ak).
 * The sensitivity adjustment (ASA fuse values) is not applied.
 */
#ifndef AW_MPU9250_H
#define AW_MPU9250_H

#include <stdbool.h>
#include <stdint.h>

#include "hal.h"

/* SPI clocks: every register at 1 MHz, sensor/interrupt registers up to 20 MHz. */
#define MPU9250_SPI_CONFIG_HZ 1000000u
#define MPU9250_SPI_READ_HZ 8000000u

typedef struct {
    hal_spi_t dev;
    float gyro_rad_s_per_lsb;
    float accel_m_s2_per_lsb;
} mpu9250_t;

typedef struct {
    int16_t accel_raw[3]; /* chip frame, counts */
    int16_t gyro_raw[3];
    int16_t mag_raw[3];   /* chip frame (remapped), counts */
    int16_t temp_raw;
    float accel_m_s2[3];
    float gyro_rad_s[3];
    float mag_ut[3];
    float temp_c;
    bool fresh;      /* a new sample since the last read (RAW_DATA_RDY) */
    bool mag_valid;  /* the AK8963 reported no overflow */
} mpu9250_sample_t;

/* Resets and configures the chip; false when WHO_AM_I is wrong or SPI fails.
 * Takes about 110 ms (reset settle time, via hal->delay_us). */
bool mpu9250_init(const hal_t *hal, hal_spi_t dev, mpu9250_t *st);

/* One burst read of the latest sample; false on an SPI error. */
bool mpu9250_read(const hal_t *hal, const mpu9250_t *st, mpu9250_sample_t *out);

#endif /* AW_MPU9250_H */
