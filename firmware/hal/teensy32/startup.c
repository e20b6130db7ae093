/*
 * startup.c — MK20DX256 reset path: vector table, flash configuration field,
 * watchdog, clocks (FEI -> FBE -> PBE -> PEE at 96 MHz), .data/.bss, SysTick.
 *
 * Written from the K20 reference manual and the Cortex-M4 ARMv7-M rules; the
 * sequence follows the one Teensyduino's mk20dx128.c uses on this part.
 */
#include <stdint.h>

#include "regs.h"
#include "teensy32.h"

typedef void (*vector_t)(void);

extern uint32_t _estack;           /* top of SRAM_U (linker script) */
extern uint32_t _sidata, _sdata, _edata; /* .data: load address in flash, run address */
extern uint32_t _sbss, _ebss;
int main(void);

void reset_handler(void);
void unused_isr(void);
void fault_isr(void);
void nmi_isr(void) __attribute__((weak, alias("unused_isr")));
void hard_fault_isr(void) __attribute__((weak, alias("fault_isr")));
void systick_isr(void);
void uart0_status_isr(void) __attribute__((weak, alias("unused_isr")));
void uart1_status_isr(void) __attribute__((weak, alias("unused_isr")));
void uart2_status_isr(void) __attribute__((weak, alias("unused_isr")));
void ftm0_isr(void) __attribute__((weak, alias("unused_isr")));
void ftm1_isr(void) __attribute__((weak, alias("unused_isr")));
void ftm2_isr(void) __attribute__((weak, alias("unused_isr")));

/* 16 core exceptions + 95 MK20DX256 interrupts; bit 0 of every handler address is
 * set by the toolchain (Thumb). */
__attribute__((section(".vectors"), used)) const vector_t vector_table[16 + NVIC_NUM_IRQ] = {
    (vector_t)(uintptr_t)&_estack /* 0 initial stack pointer */,
    reset_handler /* 1 reset */,
    nmi_isr /* 2 NMI */,
    hard_fault_isr /* 3 hard fault */,
    fault_isr /* 4 MemManage */,
    fault_isr /* 5 bus fault */,
    fault_isr /* 6 usage fault */,
    fault_isr /* 7 reserved */,
    fault_isr /* 8 reserved */,
    fault_isr /* 9 reserved */,
    fault_isr /* 10 reserved */,
    unused_isr /* 11 SVCall */,
    unused_isr /* 12 debug monitor */,
    fault_isr /* 13 reserved */,
    unused_isr /* 14 PendSV */,
    systick_isr /* 15 SysTick */,
    unused_isr, /* 16 IRQ 0 */
    unused_isr, /* 17 IRQ 1 */
    unused_isr, /* 18 IRQ 2 */
    unused_isr, /* 19 IRQ 3 */
    unused_isr, /* 20 IRQ 4 */
    unused_isr, /* 21 IRQ 5 */
    unused_isr, /* 22 IRQ 6 */
    unused_isr, /* 23 IRQ 7 */
    unused_isr, /* 24 IRQ 8 */
    unused_isr, /* 25 IRQ 9 */
    unused_isr, /* 26 IRQ 10 */
    unused_isr, /* 27 IRQ 11 */
    unused_isr, /* 28 IRQ 12 */
    unused_isr, /* 29 IRQ 13 */
    unused_isr, /* 30 IRQ 14 */
    unused_isr, /* 31 IRQ 15 */
    unused_isr, /* 32 IRQ 16 */
    unused_isr, /* 33 IRQ 17 */
    unused_isr, /* 34 IRQ 18 */
    unused_isr, /* 35 IRQ 19 */
    unused_isr, /* 36 IRQ 20 */
    unused_isr, /* 37 IRQ 21 */
    unused_isr, /* 38 IRQ 22 WDOG */
    unused_isr, /* 39 IRQ 23 */
    unused_isr, /* 40 IRQ 24 */
    unused_isr, /* 41 IRQ 25 */
    unused_isr, /* 42 IRQ 26 SPI0 */
    unused_isr, /* 43 IRQ 27 */
    unused_isr, /* 44 IRQ 28 */
    unused_isr, /* 45 IRQ 29 */
    unused_isr, /* 46 IRQ 30 */
    unused_isr, /* 47 IRQ 31 */
    unused_isr, /* 48 IRQ 32 */
    unused_isr, /* 49 IRQ 33 */
    unused_isr, /* 50 IRQ 34 */
    unused_isr, /* 51 IRQ 35 */
    unused_isr, /* 52 IRQ 36 */
    unused_isr, /* 53 IRQ 37 */
    unused_isr, /* 54 IRQ 38 */
    unused_isr, /* 55 IRQ 39 */
    unused_isr, /* 56 IRQ 40 */
    unused_isr, /* 57 IRQ 41 */
    unused_isr, /* 58 IRQ 42 */
    unused_isr, /* 59 IRQ 43 */
    unused_isr, /* 60 IRQ 44 */
    uart0_status_isr, /* 61 IRQ 45 UART0 status */
    unused_isr, /* 62 IRQ 46 UART0 error */
    uart1_status_isr, /* 63 IRQ 47 UART1 status */
    unused_isr, /* 64 IRQ 48 UART1 error */
    uart2_status_isr, /* 65 IRQ 49 UART2 status */
    unused_isr, /* 66 IRQ 50 UART2 error */
    unused_isr, /* 67 IRQ 51 */
    unused_isr, /* 68 IRQ 52 */
    unused_isr, /* 69 IRQ 53 */
    unused_isr, /* 70 IRQ 54 */
    unused_isr, /* 71 IRQ 55 */
    unused_isr, /* 72 IRQ 56 */
    unused_isr, /* 73 IRQ 57 ADC0 */
    unused_isr, /* 74 IRQ 58 */
    unused_isr, /* 75 IRQ 59 */
    unused_isr, /* 76 IRQ 60 */
    unused_isr, /* 77 IRQ 61 */
    ftm0_isr, /* 78 IRQ 62 FTM0 */
    ftm1_isr, /* 79 IRQ 63 FTM1 */
    ftm2_isr, /* 80 IRQ 64 FTM2 */
    unused_isr, /* 81 IRQ 65 */
    unused_isr, /* 82 IRQ 66 */
    unused_isr, /* 83 IRQ 67 */
    unused_isr, /* 84 IRQ 68 PIT0 */
    unused_isr, /* 85 IRQ 69 */
    unused_isr, /* 86 IRQ 70 */
    unused_isr, /* 87 IRQ 71 */
    unused_isr, /* 88 IRQ 72 */
    unused_isr, /* 89 IRQ 73 USB OTG */
    unused_isr, /* 90 IRQ 74 */
    unused_isr, /* 91 IRQ 75 */
    unused_isr, /* 92 IRQ 76 */
    unused_isr, /* 93 IRQ 77 */
    unused_isr, /* 94 IRQ 78 */
    unused_isr, /* 95 IRQ 79 */
    unused_isr, /* 96 IRQ 80 */
    unused_isr, /* 97 IRQ 81 */
    unused_isr, /* 98 IRQ 82 */
    unused_isr, /* 99 IRQ 83 */
    unused_isr, /* 100 IRQ 84 */
    unused_isr, /* 101 IRQ 85 */
    unused_isr, /* 102 IRQ 86 */
    unused_isr, /* 103 IRQ 87 */
    unused_isr, /* 104 IRQ 88 */
    unused_isr, /* 105 IRQ 89 */
    unused_isr, /* 106 IRQ 90 */
    unused_isr, /* 107 IRQ 91 */
    unused_isr, /* 108 IRQ 92 */
    unused_isr, /* 109 IRQ 93 */
    unused_isr, /* 110 IRQ 94 */
};

/* Flash configuration field, 0x400..0x40F, read by the chip at every reset:
 * backdoor key (8), FPROT0-3 (4: 0xFF = nothing protected), FSEC, FOPT, FEPROT,
 * FDPROT. FSEC 0xDE = unsecured (SEC = 10), mass erase enabled (MEEN = 11),
 * backdoor disabled — any value with SEC != 10 secures the part and the Teensy
 * bootloader can no longer program it. FOPT 0xF9 as on every Teensy 3.x. */
__attribute__((section(".flashconfig"), used)) const uint8_t flash_config[16] = {
    0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, /* backdoor comparison key */
    0xFF, 0xFF, 0xFF, 0xFF,                         /* FPROT3..0 */
    0xDE,                                           /* FSEC */
    0xF9,                                           /* FOPT */
    0xFF,                                           /* FEPROT */
    0xFF,                                           /* FDPROT */
};

void unused_isr(void)
{
    fault_isr();
}

/* A fault we cannot recover from: stop and let the watchdog (if started) reset us. */
void fault_isr(void)
{
    for (;;) {
    }
}

static void clocks_to_96mhz(void)
{
    /* FEI (reset state) -> FBE: 16 MHz crystal, 10 pF load (8 + 2), FLL reference
     * 16 MHz / 512 = 31.25 kHz (within 31.25..39.06 kHz). */
    OSC0_CR = OSC_SC8P | OSC_SC2P | OSC_ERCLKEN;
    MCG_C2 = MCG_C2_RANGE0(2) | MCG_C2_EREFS;
    MCG_C1 = MCG_C1_CLKS(2) | MCG_C1_FRDIV(4);
    while ((MCG_S & MCG_S_OSCINIT0) == 0) {
    }
    while ((MCG_S & MCG_S_IREFST) != 0) {
    }
    while ((MCG_S & MCG_S_CLKST_MASK) != MCG_S_CLKST(2)) {
    }
    /* FBE -> PBE: PLL reference 16 / 4 = 4 MHz (2..4 MHz allowed), x24 = 96 MHz */
    MCG_C5 = MCG_C5_PRDIV0(3);
    MCG_C6 = MCG_C6_PLLS | MCG_C6_VDIV0(0);
    while ((MCG_S & MCG_S_PLLST) == 0) {
    }
    while ((MCG_S & MCG_S_LOCK0) == 0) {
    }
    /* dividers before switching: core 96 MHz, bus 48 MHz (max 50), flash 24 MHz (max 25) */
    SIM_CLKDIV1 = SIM_CLKDIV1_OUTDIV1(0) | SIM_CLKDIV1_OUTDIV2(1) | SIM_CLKDIV1_OUTDIV4(3);
    /* PBE -> PEE */
    MCG_C1 = MCG_C1_CLKS(0) | MCG_C1_FRDIV(4);
    while ((MCG_S & MCG_S_CLKST_MASK) != MCG_S_CLKST(3)) {
    }
    SIM_SOPT2 = SIM_SOPT2_PLLFLLSEL; /* peripherals that can use PLL/FLL take the PLL */
}

__attribute__((used, noreturn)) void reset_handler(void)
{
    /* The watchdog runs out of reset; unlock it within 20 bus cycles, then, within
     * the 256-cycle window, leave it disabled but reconfigurable (watchdog.c starts
     * it once the board is up). */
    WDOG_UNLOCK = WDOG_UNLOCK_SEQ1;
    WDOG_UNLOCK = WDOG_UNLOCK_SEQ2;
    __asm__ volatile("nop");
    __asm__ volatile("nop");
    WDOG_STCTRLH = WDOG_STCTRLH_ALLOWUPDATE;

    SIM_SCGC5 |= SIM_SCGC5_PORTA_E;
    SIM_SCGC6 |= SIM_SCGC6_FTFL;
    if (PMC_REGSC & PMC_REGSC_ACKISO) {
        PMC_REGSC |= PMC_REGSC_ACKISO; /* release pins held after a VLLS wakeup */
    }

    uint32_t *src = &_sidata;
    for (uint32_t *dst = &_sdata; dst < &_edata;) {
        *dst++ = *src++;
    }
    for (uint32_t *dst = &_sbss; dst < &_ebss;) {
        *dst++ = 0;
    }

    for (uint32_t irq = 0; irq < NVIC_NUM_IRQ; irq++) {
        NVIC_IPR(irq) = 128; /* everything medium until a driver says otherwise */
    }
    clocks_to_96mhz();
    teensy_time_init();
    __asm__ volatile("cpsie i" ::: "memory");
    (void)main();
    for (;;) {
    }
}
