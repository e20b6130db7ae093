/*
 * spi.c — SPI0 master for the IMU: mode 3 (CPOL = CPHA = 1, the MPU-9250's),
 * 8-bit frames, chip select on a GPIO held for the whole transaction. The clock
 * is the fastest F_BUS / PBR / BR not above the caller's max_hz.
 */
#include "board_pins.h"
#include "regs.h"
#include "teensy32.h"

#define SPI_TIMEOUT_SPINS 100000u

#if HAS_SPI_IMU
static const pin_t imu_cs = IMU_CS_PIN;
static uint32_t current_hz;

static uint32_t ctar_for(uint32_t max_hz)
{
    static const uint8_t pbr[4] = {2, 3, 5, 7};
    static const uint16_t br[8] = {2, 4, 6, 8, 16, 32, 64, 128};
    uint32_t best = SPI_CTAR_PBR(3) | SPI_CTAR_BR(7);
    uint32_t best_hz = 0;
    for (uint32_t i = 0; i < 4; i++) {
        for (uint32_t j = 0; j < 8; j++) {
            uint32_t hz = F_BUS / pbr[i] / br[j];
            if (hz <= max_hz && hz > best_hz) {
                best_hz = hz;
                best = SPI_CTAR_PBR(i) | SPI_CTAR_BR(j);
            }
        }
    }
    return SPI_CTAR_FMSZ(7) | SPI_CTAR_CPOL | SPI_CTAR_CPHA | best;
}
#endif

void spi_init(void)
{
#if HAS_SPI_IMU
    SIM_SCGC6 |= SIM_SCGC6_SPI0;
    PORT_PCR(PC, 5) = PORT_PCR_MUX(2) | PORT_PCR_DSE; /* pin 13 SCK */
    PORT_PCR(PC, 6) = PORT_PCR_MUX(2) | PORT_PCR_DSE; /* pin 11 MOSI */
    PORT_PCR(PC, 7) = PORT_PCR_MUX(2);                /* pin 12 MISO */
    PORT_PCR(imu_cs.port, imu_cs.bit) = PORT_PCR_MUX(1) | PORT_PCR_DSE;
    GPIO_PSOR(imu_cs.port) = 1u << imu_cs.bit; /* deselected */
    GPIO_PDDR(imu_cs.port) |= 1u << imu_cs.bit;
    SPI0_MCR = SPI_MCR_MSTR | SPI_MCR_PCSIS(0x1F) | SPI_MCR_CLR_TXF | SPI_MCR_CLR_RXF |
               SPI_MCR_HALT;
    current_hz = 1000000u;
    SPI0_CTAR0 = ctar_for(current_hz);
    SPI0_MCR &= ~SPI_MCR_HALT;
#endif
}

bool spi_transfer(hal_spi_t dev, uint32_t max_hz, const uint8_t *tx, uint8_t *rx, size_t len)
{
#if HAS_SPI_IMU
    if (dev != HAL_SPI_IMU) {
        return false;
    }
    if (max_hz != current_hz) {
        SPI0_MCR |= SPI_MCR_HALT;
        SPI0_CTAR0 = ctar_for(max_hz);
        SPI0_MCR = (SPI0_MCR & ~SPI_MCR_HALT) | SPI_MCR_CLR_TXF | SPI_MCR_CLR_RXF;
        current_hz = max_hz;
    }
    bool ok = true;
    GPIO_PCOR(imu_cs.port) = 1u << imu_cs.bit;
    for (size_t i = 0; i < len && ok; i++) {
        SPI0_SR = SPI_SR_RFDF | SPI_SR_TCF | SPI_SR_EOQF; /* write 1 to clear */
        SPI0_PUSHR = tx[i];
        uint32_t spins = 0;
        while ((SPI0_SR & SPI_SR_RFDF) == 0) {
            if (++spins > SPI_TIMEOUT_SPINS) {
                ok = false;
                break;
            }
        }
        rx[i] = ok ? (uint8_t)SPI0_POPR : 0u;
    }
    GPIO_PSOR(imu_cs.port) = 1u << imu_cs.bit;
    return ok;
#else
    (void)dev;
    (void)max_hz;
    (void)tx;
    (void)rx;
    (void)len;
    return false;
#endif
}
