/* mpu9250.c — MPU-9250 over SPI; see mpu9250.h. */
#include "mpu9250.h"

#include "mpu9250_regs.h"

#define GYRO_FS_2000DPS 3u
#define ACCEL_FS_16G 3u
#define STANDARD_GRAVITY_M_S2 9.80665f
#define DEG_TO_RAD 0.017453292519943295f

/* INT_STATUS, 14 bytes accel/temp/gyro, 7 bytes EXT_SENS_DATA (AK8963 HXL..ST2). */
#define BURST_LEN 22u

static bool write_reg(const hal_t *hal, hal_spi_t dev, uint8_t reg, uint8_t value)
{
    uint8_t tx[2] = {reg, value};
    uint8_t rx[2];
    return hal->spi_transfer(dev, MPU9250_SPI_CONFIG_HZ, tx, rx, sizeof(tx));
}

static bool read_reg(const hal_t *hal, hal_spi_t dev, uint8_t reg, uint8_t *value)
{
    uint8_t tx[2] = {(uint8_t)(reg | MPU9250_READ), 0};
    uint8_t rx[2] = {0, 0};
    if (!hal->spi_transfer(dev, MPU9250_SPI_CONFIG_HZ, tx, rx, sizeof(tx))) {
        return false;
    }
    *value = rx[1];
    return true;
}

bool mpu9250_init(const hal_t *hal, hal_spi_t dev, mpu9250_t *st)
{
    st->dev = dev;
    st->gyro_rad_s_per_lsb =
        DEG_TO_RAD / (MPU9250_GYRO_LSB_PER_DPS_250 / (float)(1u << GYRO_FS_2000DPS));
    st->accel_m_s2_per_lsb =
        STANDARD_GRAVITY_M_S2 / (MPU9250_ACCEL_LSB_PER_G_2 / (float)(1u << ACCEL_FS_16G));

    if (!write_reg(hal, dev, MPU9250_PWR_MGMT_1, MPU9250_PWR_MGMT_1_H_RESET)) {
        return false;
    }
    hal->delay_us(100000); /* register reset and start-up */

    uint8_t who = 0;
    if (!read_reg(hal, dev, MPU9250_WHO_AM_I, &who) || who != MPU9250_WHO_AM_I_VALUE) {
        return false;
    }
    static const uint8_t setup[][2] = {
        {MPU9250_PWR_MGMT_1, MPU9250_PWR_MGMT_1_CLKSEL_AUTO},
        {MPU9250_PWR_MGMT_2, 0x00},  /* all axes on */
        {MPU9250_USER_CTRL, MPU9250_USER_CTRL_I2C_MST_EN | MPU9250_USER_CTRL_I2C_IF_DIS},
        {MPU9250_CONFIG, 0x01},      /* gyro DLPF 184 Hz, 1 kHz */
        {MPU9250_SMPLRT_DIV, 0x00},  /* 1 kHz */
        {MPU9250_GYRO_CONFIG, (uint8_t)(GYRO_FS_2000DPS << MPU9250_FS_SEL_SHIFT)},
        {MPU9250_ACCEL_CONFIG, (uint8_t)(ACCEL_FS_16G << MPU9250_FS_SEL_SHIFT)},
        {MPU9250_ACCEL_CONFIG2, 0x01}, /* accel DLPF 184 Hz */
        {MPU9250_INT_PIN_CFG, 0x10},   /* INT_ANYRD_2CLEAR */
        {MPU9250_INT_ENABLE, 0x01},    /* raw data ready */
        {MPU9250_I2C_MST_CTRL, 0x0D},  /* I2C master 400 kHz */
        /* AK8963: continuous 100 Hz, 16-bit (one write through slave 0) */
        {MPU9250_I2C_SLV0_ADDR, AK8963_I2C_ADDR},
        {MPU9250_I2C_SLV0_REG, AK8963_CNTL1},
        {MPU9250_I2C_SLV0_DO, AK8963_CNTL1_16BIT_100HZ},
        {MPU9250_I2C_SLV0_CTRL, 0x81},
    };
    for (unsigned i = 0; i < sizeof(setup) / sizeof(setup[0]); i++) {
        if (!write_reg(hal, dev, setup[i][0], setup[i][1])) {
            return false;
        }
    }
    hal->delay_us(10000);
    /* then keep reading HXL..ST2 (7 bytes) into EXT_SENS_DATA_00.. */
    static const uint8_t slv0_read[][2] = {
        {MPU9250_I2C_SLV0_ADDR, (uint8_t)(0x80u | AK8963_I2C_ADDR)},
        {MPU9250_I2C_SLV0_REG, AK8963_HXL},
        {MPU9250_I2C_SLV0_CTRL, 0x87},
    };
    for (unsigned i = 0; i < sizeof(slv0_read) / sizeof(slv0_read[0]); i++) {
        if (!write_reg(hal, dev, slv0_read[i][0], slv0_read[i][1])) {
            return false;
        }
    }
    return true;
}

static int16_t be16(const uint8_t *p) { return (int16_t)(uint16_t)((unsigned)p[0] << 8 | p[1]); }

static int16_t le16(const uint8_t *p) { return (int16_t)(uint16_t)((unsigned)p[1] << 8 | p[0]); }

bool mpu9250_read(const hal_t *hal, const mpu9250_t *st, mpu9250_sample_t *out)
{
    uint8_t tx[1 + BURST_LEN] = {(uint8_t)(MPU9250_INT_STATUS | MPU9250_READ)};
    uint8_t rx[1 + BURST_LEN] = {0};
    if (!hal->spi_transfer(st->dev, MPU9250_SPI_READ_HZ, tx, rx, sizeof(tx))) {
        return false;
    }
    const uint8_t *r = &rx[1];
    out->fresh = (r[0] & MPU9250_INT_STATUS_RAW_DATA_RDY) != 0;
    for (unsigned i = 0; i < 3; i++) {
        out->accel_raw[i] = be16(&r[1 + 2 * i]);
        out->gyro_raw[i] = be16(&r[9 + 2 * i]);
    }
    out->temp_raw = be16(&r[7]);
    /* AK8963 little-endian HX, HY, HZ, then ST2; remap to the chip frame */
    int16_t hx = le16(&r[15]);
    int16_t hy = le16(&r[17]);
    int16_t hz = le16(&r[19]);
    out->mag_raw[0] = hy;
    out->mag_raw[1] = hx;
    out->mag_raw[2] = (int16_t)(hz == INT16_MIN ? INT16_MAX : -hz);
    out->mag_valid = (r[21] & AK8963_ST2_HOFL) == 0;

    for (unsigned i = 0; i < 3; i++) {
        out->accel_m_s2[i] = (float)out->accel_raw[i] * st->accel_m_s2_per_lsb;
        out->gyro_rad_s[i] = (float)out->gyro_raw[i] * st->gyro_rad_s_per_lsb;
        out->mag_ut[i] = (float)out->mag_raw[i] * AK8963_UT_PER_LSB;
    }
    out->temp_c = (float)out->temp_raw / MPU9250_TEMP_LSB_PER_C + MPU9250_TEMP_OFFSET_C;
    return true;
}
