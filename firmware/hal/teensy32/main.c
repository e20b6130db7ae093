/* main.c — Teensy 3.2 entry point (called by reset_handler in startup.c). */
#include "board.h"
#include "teensy32.h"

int main(void)
{
    const hal_t *hal = teensy_hal_init();
    board_init(hal);
    for (;;) {
        hal->idle(board_task(hal));
    }
}
