/* gpio.c — digital outputs by role (TSL1401 SI/CLK, status LED), pins from
 * board_pins.h; set/clear registers so a write is one store. */
#include "board_pins.h"
#include "regs.h"
#include "teensy32.h"

void gpio_init(void)
{
    for (int i = 0; i < HAL_PIN_COUNT; i++) {
        if (!gpio_map[i].wired) {
            continue;
        }
        pin_t p = gpio_map[i].pin;
        PORT_PCR(p.port, p.bit) = PORT_PCR_MUX(1) | PORT_PCR_DSE | PORT_PCR_SRE;
        GPIO_PCOR(p.port) = 1u << p.bit;
        GPIO_PDDR(p.port) |= 1u << p.bit;
    }
}

void gpio_write(hal_pin_t pin, bool high)
{
    if ((unsigned)pin >= HAL_PIN_COUNT || !gpio_map[pin].wired) {
        return;
    }
    pin_t p = gpio_map[pin].pin;
    if (high) {
        GPIO_PSOR(p.port) = 1u << p.bit;
    } else {
        GPIO_PCOR(p.port) = 1u << p.bit;
    }
}
