/* test_hal_tsl1401.c — SI/CLK sequencing of the TSL1401 driver against a strict
 * chip model (hal_fake.c). */
#include <stdio.h>
#include <string.h>

#include "hal_fake.h"
#include "tsl1401.h"

#define CHECK(cond)                                                                 \
    do {                                                                            \
        if (!(cond)) {                                                              \
            fprintf(stderr, "%s:%d: %s failed\n", __FILE__, __LINE__, #cond);       \
            return 1;                                                               \
        }                                                                           \
    } while (0)

/* Off-by-one clocking shifts every pixel: pixel i of each array must land in lines[s][i]. */
static int test_tsl1401_read_puts_every_pixel_of_every_array_in_place(void)
{
    const hal_t *hal = fake_hal_init();
    for (unsigned s = 0; s < 4; s++) {
        for (unsigned i = 0; i < 128; i++) {
            fake.scene[s][i] = (uint16_t)(s * 1000u + i);
        }
    }
    tsl1401_t st;
    tsl1401_init(hal, &st);
    static uint16_t lines[4][TSL1401_PIXELS];
    tsl1401_read(hal, &st, lines, 4);
    for (unsigned s = 0; s < 4; s++) {
        for (unsigned i = 0; i < 128; i++) {
            CHECK(lines[s][i] == s * 1000u + i);
        }
    }
    CHECK(fake.tsl_violations == 0);
    return 0;
}

/* The readout must end (129th clock) so the next SI is legal and AO goes quiet. */
static int test_tsl1401_readout_ends_after_129_clocks(void)
{
    const hal_t *hal = fake_hal_init();
    tsl1401_t st;
    tsl1401_init(hal, &st);
    CHECK(fake.tsl_index == -1);
    static uint16_t lines[4][TSL1401_PIXELS];
    for (int k = 0; k < 3; k++) {
        tsl1401_read(hal, &st, lines, 4);
        CHECK(fake.tsl_index == -1);
        tsl1401_flush(hal, &st);
        CHECK(fake.tsl_index == -1);
    }
    CHECK(fake.tsl_violations == 0);
    CHECK(fake.si_latches == 7); /* init flush + 3 x (read + flush) */
    CHECK(!fake.clk && !fake.si);
    return 0;
}

/* Exposure control needs the true integration time: SI latch to SI latch. */
static int test_tsl1401_reports_time_between_si_latches_as_exposure(void)
{
    const hal_t *hal = fake_hal_init();
    fake.now_us = 5000;
    tsl1401_t st;
    tsl1401_init(hal, &st);
    fake.now_us += 1234;
    static uint16_t lines[4][TSL1401_PIXELS];
    CHECK(tsl1401_read(hal, &st, lines, 4) == 1234u);
    fake.now_us += 700;
    tsl1401_flush(hal, &st);
    fake.now_us += 250;
    CHECK(tsl1401_read(hal, &st, lines, 4) == 250u);
    CHECK(st.last_si_us == fake.now_us);
    return 0;
}

/* Reading fewer arrays must not touch the others' slots (nor read their ADCs). */
static int test_tsl1401_reads_only_the_arrays_asked_for(void)
{
    const hal_t *hal = fake_hal_init();
    memset(fake.scene, 0x11, sizeof(fake.scene));
    tsl1401_t st;
    tsl1401_init(hal, &st);
    static uint16_t lines[4][TSL1401_PIXELS];
    memset(lines, 0, sizeof(lines));
    tsl1401_read(hal, &st, lines, 2);
    CHECK(lines[1][127] == 0x1111 && lines[2][0] == 0 && lines[3][127] == 0);
    return 0;
}

int main(void)
{
    int fails = 0;
    fails += test_tsl1401_read_puts_every_pixel_of_every_array_in_place();
    fails += test_tsl1401_readout_ends_after_129_clocks();
    fails += test_tsl1401_reports_time_between_si_latches_as_exposure();
    fails += test_tsl1401_reads_only_the_arrays_asked_for();
    if (fails) {
        fprintf(stderr, "test_hal_tsl1401: %d failed\n", fails);
        return 1;
    }
    printf("test_hal_tsl1401: ok\n");
    return 0;
}
