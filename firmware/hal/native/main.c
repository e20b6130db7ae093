/* main.c — native (SIL) entry point: the same board_init/board_task loop as on
 * the Teensy, with resets returning here through native_reset_jmp. */
#include <setjmp.h>

#include "board.h"
#include "native.h"

int main(int argc, char **argv)
{
    const hal_t *hal = native_start(argc, argv, BOARD_NAME, BOARD_ID);
    (void)setjmp(native_reset_jmp);
    board_init(hal);
    for (;;) {
        hal->idle(board_task(hal));
    }
}
