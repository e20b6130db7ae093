/*
 * spi.c — the native SPI bus: an MPU-9250 register file behind HAL_SPI_IMU.
 *
 * The simulator sends IMU samples in physical units (SIM_IMU, chip axes); they
 * are converted to counts with the full-scale ranges the driver wrote into
 * GYRO_CONFIG / ACCEL_CONFIG, saturate at int16 as on the chip, and appear in the
 * data registers with RAW_DATA_RDY set (cleared when INT_STATUS is read). The
 * magnetometer goes into EXT_SENS_DATA in the AK8963's own axes and byte order,
 * as the MPU's I2C master would leave it.
 */
#include <math.h>
#include <string.h>

#include "mpu9250_regs.h"
#include "native.h"

#define REGS 128u
#define STANDARD_GRAVITY_M_S2 9.80665
#define RAD_TO_DEG 57.29577951308232

static uint8_t regs[REGS];
static bool powered;

static void chip_reset(void)
{
    memset(regs, 0, sizeof(regs));
    regs[MPU9250_PWR_MGMT_1] = 0x01;
    regs[MPU9250_WHO_AM_I] = MPU9250_WHO_AM_I_VALUE;
    powered = true;
}

static int16_t sat16(double v)
{
    if (!(v == v)) { /* NaN */
        return 0;
    }
    if (v >= 32767.0) {
        return INT16_MAX;
    }
    if (v <= -32768.0) {
        return INT16_MIN;
    }
    return (int16_t)lrint(v);
}

static void put_be16(uint8_t reg, int16_t v)
{
    regs[reg] = (uint8_t)((uint16_t)v >> 8);
    regs[reg + 1u] = (uint8_t)((uint16_t)v & 0xFFu);
}

static void put_le16(uint8_t reg, int16_t v)
{
    regs[reg] = (uint8_t)((uint16_t)v & 0xFFu);
    regs[reg + 1u] = (uint8_t)((uint16_t)v >> 8);
}

void imu_emu_sample(unsigned dev, const float gyro_rad_s[3], const float accel_m_s2[3],
                    const float mag_ut[3], float temp_c)
{
    (void)dev;
    if (!powered) {
        chip_reset();
    }
    unsigned gfs = (regs[MPU9250_GYRO_CONFIG] >> MPU9250_FS_SEL_SHIFT) & 3u;
    unsigned afs = (regs[MPU9250_ACCEL_CONFIG] >> MPU9250_FS_SEL_SHIFT) & 3u;
    double g_lsb_per_rad_s = (double)MPU9250_GYRO_LSB_PER_DPS_250 / (double)(1u << gfs) * RAD_TO_DEG;
    double a_lsb_per_m_s2 =
        (double)MPU9250_ACCEL_LSB_PER_G_2 / (double)(1u << afs) / STANDARD_GRAVITY_M_S2;
    for (unsigned i = 0; i < 3; i++) {
        put_be16((uint8_t)(MPU9250_ACCEL_XOUT_H + 2u * i), sat16(accel_m_s2[i] * a_lsb_per_m_s2));
        put_be16((uint8_t)(MPU9250_ACCEL_XOUT_H + 8u + 2u * i),
                 sat16(gyro_rad_s[i] * g_lsb_per_rad_s));
    }
    put_be16(MPU9250_ACCEL_XOUT_H + 6u,
             sat16(((double)temp_c - (double)MPU9250_TEMP_OFFSET_C) * (double)MPU9250_TEMP_LSB_PER_C));
    /* AK8963 axes: x_ak = y_mpu, y_ak = x_mpu, z_ak = -z_mpu; 16-bit, ±4912 µT */
    double ak[3] = {mag_ut[1], mag_ut[0], -(double)mag_ut[2]};
    bool overflow = false;
    for (unsigned i = 0; i < 3; i++) {
        double counts = ak[i] / (double)AK8963_UT_PER_LSB;
        overflow = overflow || fabs(counts) > 32760.0;
        put_le16((uint8_t)(MPU9250_EXT_SENS_DATA_00 + 2u * i), sat16(counts));
    }
    regs[MPU9250_EXT_SENS_DATA_00 + 6u] = (uint8_t)(0x10u | (overflow ? AK8963_ST2_HOFL : 0u));
    regs[MPU9250_INT_STATUS] |= MPU9250_INT_STATUS_RAW_DATA_RDY;
}

bool spi_transfer(hal_spi_t dev, uint32_t max_hz, const uint8_t *tx, uint8_t *rx, size_t len)
{
    (void)max_hz;
    if (dev != HAL_SPI_IMU) {
        return false;
    }
    if (!powered) {
        chip_reset();
    }
    if (len == 0) {
        return true;
    }
    uint8_t reg = tx[0] & 0x7Fu;
    rx[0] = 0;
    if (tx[0] & MPU9250_READ) {
        for (size_t i = 1; i < len; i++) {
            uint8_t r = (uint8_t)((reg + i - 1u) & 0x7Fu);
            rx[i] = regs[r];
            if (r == MPU9250_INT_STATUS) {
                regs[r] &= (uint8_t)~MPU9250_INT_STATUS_RAW_DATA_RDY;
            }
        }
        return true;
    }
    for (size_t i = 1; i < len; i++) {
        uint8_t r = (uint8_t)((reg + i - 1u) & 0x7Fu);
        rx[i] = 0;
        if (r == MPU9250_WHO_AM_I || r == MPU9250_INT_STATUS ||
            (r >= MPU9250_ACCEL_XOUT_H && r < MPU9250_EXT_SENS_DATA_00 + 24u)) {
            continue; /* read-only */
        }
        if (r == MPU9250_PWR_MGMT_1 && (tx[i] & MPU9250_PWR_MGMT_1_H_RESET)) {
            chip_reset();
            continue;
        }
        regs[r] = tx[i];
    }
    return true;
}
