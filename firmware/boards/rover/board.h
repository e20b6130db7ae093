/*
 * board.h (rover) — the helicopter's board (reference §4.2.1, §5.2): VN200 INS and
 * Piksi RTK (nav_ports), main-rotor speed from the IR reflections of the two
 * blades (input capture -> F2's rotor_speed), the tail-servo pulse width (input
 * capture -> F2's pwm_capture), everything out on the XBee (HAL_PORT_HOST).
 */
#ifndef AW_BOARD_ROVER_H
#define AW_BOARD_ROVER_H

#include <stdint.h>

#include "base/pwm_capture.h"
#include "board_link.h"
#include "hal.h"
#include "nav_ports.h"
#include "rotor_speed.h"

#define BOARD_NAME "rover"
#define BOARD_ID AW_BOARD_ROVER

#define ROVER_ROTOR_HZ 150u
#define ROVER_TAIL_HZ 50u
#define ROVER_WATCHDOG_MS 500u

typedef struct {
    board_link_t link;
    nav_ports_t nav;
    rotor_speed_cfg_t rotor_cfg;
    rotor_speed_t rotor;
    pwm_capture_cfg_t tail_cfg;
    pwm_channel_t tail;
    uint64_t t0_us;
    uint32_t rotor_k, tail_k;
} rover_board_t;

extern rover_board_t rover_board; /* for tests */

void board_init(const hal_t *hal);
uint64_t board_task(const hal_t *hal);

#endif /* AW_BOARD_ROVER_H */
