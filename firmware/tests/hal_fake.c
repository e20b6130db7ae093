/* hal_fake.c — see hal_fake.h. */
#include "hal_fake.h"

#include <string.h>

#include "ringbuf.h"

/* the native backend's MPU-9250 model (hal/native/spi.c) */
bool spi_transfer(hal_spi_t dev, uint32_t max_hz, const uint8_t *tx, uint8_t *rx, size_t len);
void imu_emu_sample(unsigned dev, const float gyro_rad_s[3], const float accel_m_s2[3],
                    const float mag_ut[3], float temp_c);

fake_hal_state_t fake;

static ringbuf_t rx_ring[HAL_PORT_COUNT];
static uint8_t rx_mem[HAL_PORT_COUNT][FAKE_RX_RING];
static ringbuf_t cap_ring[HAL_CAPTURE_COUNT];
static hal_edge_t cap_mem[HAL_CAPTURE_COUNT][64];

static uint64_t f_micros(void) { return fake.now_us; }

static void f_delay_us(uint32_t us) { fake.now_us += us; }

static void f_idle(uint64_t until)
{
    fake.now_us = until > fake.now_us ? until : fake.now_us + 1u;
}

static bool f_uart_write(hal_port_t port, const uint8_t *data, size_t len)
{
    if (!fake.port_mapped[port] || len > fake.tx_room[port] ||
        fake.tx_len[port] + len > FAKE_TX_CAP) {
        fake.stats[port].tx_dropped += (uint32_t)len;
        return false;
    }
    memcpy(&fake.tx[port][fake.tx_len[port]], data, len);
    fake.tx_len[port] += len;
    fake.stats[port].tx_bytes += (uint32_t)len;
    return true;
}

static size_t f_uart_read(hal_port_t port, uint8_t *buf, size_t cap)
{
    return ringbuf_read(&rx_ring[port], buf, cap);
}

static size_t f_uart_tx_free(hal_port_t port) { return fake.port_mapped[port] ? fake.tx_room[port] : 0; }

static void f_uart_stats(hal_port_t port, hal_port_stats_t *out)
{
    *out = fake.stats[port];
    out->rx_overruns = rx_ring[port].overruns;
}

static void f_gpio_write(hal_pin_t pin, bool high)
{
    if (pin == HAL_PIN_LINE_SI) {
        fake.si = high;
        return;
    }
    if (pin != HAL_PIN_LINE_CLK) {
        return;
    }
    if (high && !fake.clk) {
        if (fake.si) {
            if (fake.tsl_index >= 0) {
                fake.tsl_violations++; /* SI while a readout runs: datasheet forbids */
            }
            memcpy(fake.latched, fake.scene, sizeof(fake.latched));
            fake.tsl_index = 0;
            fake.si_latches++;
            fake.last_latch_us = fake.now_us;
        } else if (fake.tsl_index >= 0) {
            fake.tsl_index++;
            if (fake.tsl_index >= 128) {
                fake.tsl_index = -1;
            }
        }
    }
    fake.clk = high;
}

static uint16_t f_adc_read(hal_adc_t ch)
{
    if (fake.tsl_index < 0) {
        fake.tsl_violations++; /* converting while AO carries nothing */
        return 0;
    }
    return fake.latched[ch][fake.tsl_index];
}

static size_t f_capture_read(hal_capture_t ch, hal_edge_t *out, size_t cap)
{
    size_t n = 0;
    while (n < cap && ringbuf_get(&cap_ring[ch], &out[n])) {
        n++;
    }
    return n;
}

static uint32_t f_capture_overruns(hal_capture_t ch) { return cap_ring[ch].overruns; }

static void f_pwm_write(hal_pwm_t ch, uint16_t duty)
{
    fake.pwm[ch] = duty;
    fake.pwm_writes++;
}

static void f_watchdog_start(uint32_t timeout_ms)
{
    fake.watchdog_started = true;
    fake.watchdog_timeout_ms = timeout_ms;
}

static void f_watchdog_refresh(void) { fake.watchdog_refreshes++; }

static void f_reset(void) { fake.resets++; }

static hal_reset_cause_t f_reset_cause(void) { return HAL_RESET_POWER_ON; }

static uint32_t f_boot_count(void) { return 0; }

static bool f_config_read(uint32_t offset, void *buf, size_t len)
{
    if (offset > sizeof(fake.config) || len > sizeof(fake.config) - offset) {
        return false;
    }
    memcpy(buf, &fake.config[offset], len);
    return true;
}

static bool f_config_write(uint32_t offset, const void *buf, size_t len)
{
    if (offset > sizeof(fake.config) || len > sizeof(fake.config) - offset) {
        return false;
    }
    memcpy(&fake.config[offset], buf, len);
    return true;
}

static const hal_t fake_hal = {
    .target = "fake",
    .micros = f_micros,
    .delay_us = f_delay_us,
    .idle = f_idle,
    .uart_write = f_uart_write,
    .uart_read = f_uart_read,
    .uart_tx_free = f_uart_tx_free,
    .uart_stats = f_uart_stats,
    .gpio_write = f_gpio_write,
    .adc_read = f_adc_read,
    .spi_transfer = spi_transfer,
    .capture_read = f_capture_read,
    .capture_overruns = f_capture_overruns,
    .pwm_write = f_pwm_write,
    .watchdog_start = f_watchdog_start,
    .watchdog_refresh = f_watchdog_refresh,
    .reset = f_reset,
    .reset_cause = f_reset_cause,
    .boot_count = f_boot_count,
    .config_size = sizeof(fake.config),
    .config_read = f_config_read,
    .config_write = f_config_write,
};

const hal_t *fake_hal_init(void)
{
    memset(&fake, 0, sizeof(fake));
    fake.tsl_index = -1;
    memset(fake.config, 0xFF, sizeof(fake.config));
    for (unsigned p = 0; p < HAL_PORT_COUNT; p++) {
        ringbuf_init(&rx_ring[p], rx_mem[p], FAKE_RX_RING, 1);
        fake.tx_room[p] = FAKE_TX_CAP;
    }
    fake.port_mapped[HAL_PORT_HOST] = true;
    for (unsigned c = 0; c < HAL_CAPTURE_COUNT; c++) {
        ringbuf_init(&cap_ring[c], cap_mem[c], 64, (uint16_t)sizeof(hal_edge_t));
    }
    return &fake_hal;
}

void fake_map_port(hal_port_t port, bool mapped) { fake.port_mapped[port] = mapped; }

void fake_uart_feed(hal_port_t port, const uint8_t *data, size_t len)
{
    (void)ringbuf_write(&rx_ring[port], data, len);
}

size_t fake_uart_take(hal_port_t port, uint8_t *out, size_t cap)
{
    size_t n = fake.tx_len[port] < cap ? fake.tx_len[port] : cap;
    memcpy(out, fake.tx[port], n);
    memmove(fake.tx[port], &fake.tx[port][n], fake.tx_len[port] - n);
    fake.tx_len[port] -= n;
    return n;
}

void fake_capture_push(hal_capture_t ch, uint32_t t_us, uint8_t level)
{
    hal_edge_t e = {.t_us = t_us, .level = level};
    (void)ringbuf_put(&cap_ring[ch], &e);
}

void fake_imu_sample(const float gyro_rad_s[3], const float accel_m_s2[3], const float mag_ut[3])
{
    imu_emu_sample(0, gyro_rad_s, accel_m_s2, mag_ut, 25.0f);
}
