/*
 * mpu9250_regs.h — the MPU-9250 registers and values our driver uses (InvenSense
 * MPU-9250 register map rev 1.6; AK8963 datasheet). Shared by the driver and the
 * native backend's chip emulation so both read the same map.
 */
#ifndef AW_MPU9250_REGS_H
#define AW_MPU9250_REGS_H

#define MPU9250_READ 0x80u /* first SPI byte: register | READ for a read */

#define MPU9250_SMPLRT_DIV 0x19u
#define MPU9250_CONFIG 0x1Au
#define MPU9250_GYRO_CONFIG 0x1Bu   /* bits 4:3 GYRO_FS_SEL: 250/500/1000/2000 dps */
#define MPU9250_ACCEL_CONFIG 0x1Cu  /* bits 4:3 ACCEL_FS_SEL: 2/4/8/16 g */
#define MPU9250_ACCEL_CONFIG2 0x1Du
#define MPU9250_I2C_MST_CTRL 0x24u
#define MPU9250_I2C_SLV0_ADDR 0x25u
#define MPU9250_I2C_SLV0_REG 0x26u
#define MPU9250_I2C_SLV0_CTRL 0x27u
#define MPU9250_INT_PIN_CFG 0x37u
#define MPU9250_INT_ENABLE 0x38u
#define MPU9250_INT_STATUS 0x3Au    /* bit 0 RAW_DATA_RDY_INT */
#define MPU9250_ACCEL_XOUT_H 0x3Bu  /* 0x3B..0x48: accel xyz, temp, gyro xyz, big endian */
#define MPU9250_EXT_SENS_DATA_00 0x49u /* AK8963 HXL..HZH, ST2 as read by the I2C master */
#define MPU9250_I2C_SLV0_DO 0x63u
#define MPU9250_USER_CTRL 0x6Au
#define MPU9250_PWR_MGMT_1 0x6Bu
#define MPU9250_PWR_MGMT_2 0x6Cu
#define MPU9250_WHO_AM_I 0x75u

#define MPU9250_WHO_AM_I_VALUE 0x71u
#define MPU9250_PWR_MGMT_1_H_RESET 0x80u
#define MPU9250_PWR_MGMT_1_CLKSEL_AUTO 0x01u
#define MPU9250_USER_CTRL_I2C_MST_EN 0x20u
#define MPU9250_USER_CTRL_I2C_IF_DIS 0x10u
#define MPU9250_INT_STATUS_RAW_DATA_RDY 0x01u
#define MPU9250_FS_SEL_SHIFT 3u

#define AK8963_I2C_ADDR 0x0Cu
#define AK8963_HXL 0x03u
#define AK8963_CNTL1 0x0Au
#define AK8963_CNTL1_16BIT_100HZ 0x16u
#define AK8963_ST2_HOFL 0x08u /* magnetic overflow */

/* Sensitivities. */
#define MPU9250_GYRO_LSB_PER_DPS_250 131.0f   /* halves with each FS_SEL step */
#define MPU9250_ACCEL_LSB_PER_G_2 16384.0f    /* halves with each FS_SEL step */
#define MPU9250_TEMP_LSB_PER_C 333.87f        /* T = raw / 333.87 + 21 °C */
#define MPU9250_TEMP_OFFSET_C 21.0f
#define AK8963_UT_PER_LSB 0.15f               /* 16-bit output */

#endif /* AW_MPU9250_REGS_H */
