/* test_hal_mpu9250.c — the MPU-9250 driver against the native register model:
 * configuration, scaling, axes and saturation. */
#include <math.h>
#include <stdio.h>

#include "hal_fake.h"
#include "mpu9250.h"

#define CHECK(cond)                                                                 \
    do {                                                                            \
        if (!(cond)) {                                                              \
            fprintf(stderr, "%s:%d: %s failed\n", __FILE__, __LINE__, #cond);       \
            return 1;                                                               \
        }                                                                           \
    } while (0)

static bool near(float a, float b, float tol) { return fabsf(a - b) <= tol; }

/* A wrong full-scale or byte order turns the marker's attitude into garbage. */
static int test_mpu9250_round_trips_physical_units_within_one_lsb(void)
{
    const hal_t *hal = fake_hal_init();
    mpu9250_t imu;
    CHECK(mpu9250_init(hal, HAL_SPI_IMU, &imu));
    CHECK(fake.now_us >= 100000u); /* waited for the reset to settle */
    const float gyro[3] = {0.5f, -1.25f, 3.0f};
    const float accel[3] = {1.0f, -2.0f, -9.80665f};
    const float mag[3] = {20.0f, -5.0f, 42.0f};
    fake_imu_sample(gyro, accel, mag);
    mpu9250_sample_t s;
    CHECK(mpu9250_read(hal, &imu, &s));
    CHECK(s.fresh && s.mag_valid);
    float g_lsb = 0.0010652644f; /* rad/s per LSB at ±2000 °/s */
    float a_lsb = 0.0047884f;    /* m/s² per LSB at ±16 g */
    for (int i = 0; i < 3; i++) {
        CHECK(near(s.gyro_rad_s[i], gyro[i], g_lsb));
        CHECK(near(s.accel_m_s2[i], accel[i], a_lsb));
        CHECK(near(s.mag_ut[i], mag[i], 0.15f));
    }
    CHECK(near(s.temp_c, 25.0f, 0.01f));
    return 0;
}

/* RAW_DATA_RDY clears on read: the board must be able to tell new from repeated. */
static int test_mpu9250_marks_a_repeated_sample_as_not_fresh(void)
{
    const hal_t *hal = fake_hal_init();
    mpu9250_t imu;
    CHECK(mpu9250_init(hal, HAL_SPI_IMU, &imu));
    const float z[3] = {0, 0, 0};
    fake_imu_sample(z, z, z);
    mpu9250_sample_t s;
    CHECK(mpu9250_read(hal, &imu, &s) && s.fresh);
    CHECK(mpu9250_read(hal, &imu, &s) && !s.fresh);
    return 0;
}

/* Beyond ±2000 °/s the chip saturates; the driver must report the rail, not wrap. */
static int test_mpu9250_saturates_instead_of_wrapping(void)
{
    const hal_t *hal = fake_hal_init();
    mpu9250_t imu;
    CHECK(mpu9250_init(hal, HAL_SPI_IMU, &imu));
    const float gyro[3] = {100.0f, -100.0f, 0.0f}; /* ~5700 °/s */
    const float z[3] = {0, 0, 0};
    const float mag[3] = {0, 0, 9000.0f}; /* beyond the AK8963's ±4912 µT */
    fake_imu_sample(gyro, z, mag);
    mpu9250_sample_t s;
    CHECK(mpu9250_read(hal, &imu, &s));
    CHECK(s.gyro_raw[0] == INT16_MAX && s.gyro_raw[1] == INT16_MIN);
    CHECK(!s.mag_valid);
    return 0;
}

int main(void)
{
    int fails = 0;
    fails += test_mpu9250_round_trips_physical_units_within_one_lsb();
    fails += test_mpu9250_marks_a_repeated_sample_as_not_fresh();
    fails += test_mpu9250_saturates_instead_of_wrapping();
    if (fails) {
        fprintf(stderr, "test_hal_mpu9250: %d failed\n", fails);
        return 1;
    }
    printf("test_hal_mpu9250: ok\n");
    return 0;
}
