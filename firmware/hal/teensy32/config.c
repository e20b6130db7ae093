/*
 * config.c — persistent configuration in the MK20's FlexRAM EEPROM emulation:
 * 2 KiB at 0x14000000, backed by the 32 KiB FlexNVM. The first boot partitions
 * the FlexNVM (PGMPART, once per chip); the flash command runs from RAM because
 * the flash controller is busy while it executes. Each byte write waits for
 * EEERDY; unchanged bytes are not rewritten (endurance).
 */
#include "regs.h"
#include "teensy32.h"

#define CONFIG_SIZE 2048u
#define EEESIZE_2KIB 0x33u    /* EEESPLIT 0x30 (required) | 2 KiB */
#define EEPARTITION_NONE 0x03u /* all 32 KiB FlexNVM backs the EEPROM */
#define EEE_WAIT_SPINS 200000u

static bool ready;

/* Runs from RAM (.ramfunc is copied with .data): launch the command, wait for it. */
__attribute__((section(".ramfunc"), noinline, long_call)) static void
flash_command_from_ram(volatile uint8_t *fstat)
{
    *fstat = FTFL_FSTAT_CCIF;
    while ((*fstat & FTFL_FSTAT_CCIF) == 0) {
    }
}

static bool wait_eee_ready(void)
{
    for (uint32_t i = 0; i < EEE_WAIT_SPINS; i++) {
        if (FTFL_FCNFG & FTFL_FCNFG_EEERDY) {
            return true;
        }
    }
    return false;
}

void config_init(void)
{
    if (FTFL_FCNFG & FTFL_FCNFG_RAMRDY) {
        /* FlexRAM is plain RAM: this chip was never partitioned for EEPROM */
        FTFL_FSTAT = FTFL_FSTAT_ERRORS;
        FTFL_FCCOB0 = FTFL_CMD_PGMPART;
        FTFL_FCCOB4 = EEESIZE_2KIB;
        FTFL_FCCOB5 = EEPARTITION_NONE;
        uint32_t primask = irq_save();
        flash_command_from_ram(&FTFL_FSTAT);
        irq_restore(primask);
        if (FTFL_FSTAT & FTFL_FSTAT_ERRORS) {
            FTFL_FSTAT = FTFL_FSTAT_ERRORS;
            return; /* config_read/write will refuse */
        }
    }
    ready = wait_eee_ready();
}

bool config_read(uint32_t offset, void *buf, size_t len)
{
    if (!ready || offset > CONFIG_SIZE || len > CONFIG_SIZE - offset || !wait_eee_ready()) {
        return false;
    }
    const volatile uint8_t *src = (const volatile uint8_t *)(FLEXRAM_BASE + offset);
    uint8_t *dst = buf;
    for (size_t i = 0; i < len; i++) {
        dst[i] = src[i];
    }
    return true;
}

bool config_write(uint32_t offset, const void *buf, size_t len)
{
    if (!ready || offset > CONFIG_SIZE || len > CONFIG_SIZE - offset) {
        return false;
    }
    volatile uint8_t *dst = (volatile uint8_t *)(FLEXRAM_BASE + offset);
    const uint8_t *src = buf;
    for (size_t i = 0; i < len; i++) {
        if (dst[i] == src[i]) {
            continue;
        }
        if (!wait_eee_ready()) {
            return false;
        }
        dst[i] = src[i];
        if (!wait_eee_ready()) {
            return false;
        }
    }
    return true;
}
