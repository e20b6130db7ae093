/*
 * regs.h — the MK20DX256 registers this backend touches (K20 Sub-Family Reference
 * Manual K20P64M72SF1RM, and the ARMv7-M core registers). Our own minimal subset:
 * addresses and the bits we use, nothing else. Only hal/teensy32/ includes it.
 */
#ifndef AW_TEENSY32_REGS_H
#define AW_TEENSY32_REGS_H

#include <stdint.h>

#define REG8(a) (*(volatile uint8_t *)(a))
#define REG16(a) (*(volatile uint16_t *)(a))
#define REG32(a) (*(volatile uint32_t *)(a))

/* ---- clocks: F_CPU 96 MHz, F_BUS 48 MHz, flash 24 MHz ---- */
#define F_CPU 96000000u
#define F_BUS 48000000u

/* ---- SIM: system integration (clock gates, dividers) ---- */
#define SIM_SOPT2 REG32(0x40048004)
#define SIM_SOPT2_PLLFLLSEL 0x00010000u
#define SIM_SCGC3 REG32(0x40048030)
#define SIM_SCGC3_FTM2 0x01000000u
#define SIM_SCGC4 REG32(0x40048034)
#define SIM_SCGC4_UART0 0x00000400u
#define SIM_SCGC4_UART1 0x00000800u
#define SIM_SCGC4_UART2 0x00001000u
#define SIM_SCGC5 REG32(0x40048038)
#define SIM_SCGC5_PORTA_E 0x00003E00u
#define SIM_SCGC6 REG32(0x4004803C)
#define SIM_SCGC6_FTFL 0x00000001u
#define SIM_SCGC6_SPI0 0x00001000u
#define SIM_SCGC6_FTM0 0x01000000u
#define SIM_SCGC6_FTM1 0x02000000u
#define SIM_SCGC6_ADC0 0x08000000u
#define SIM_CLKDIV1 REG32(0x40048044)
#define SIM_CLKDIV1_OUTDIV1(n) ((uint32_t)((n) & 0xFu) << 28) /* core/system */
#define SIM_CLKDIV1_OUTDIV2(n) ((uint32_t)((n) & 0xFu) << 24) /* bus */
#define SIM_CLKDIV1_OUTDIV4(n) ((uint32_t)((n) & 0xFu) << 16) /* flash */

/* ---- RCM: reset cause ---- */
#define RCM_SRS0 REG8(0x4007F000)
#define RCM_SRS0_POR 0x80u
#define RCM_SRS0_PIN 0x40u
#define RCM_SRS0_WDOG 0x20u
#define RCM_SRS0_LVD 0x02u
#define RCM_SRS1 REG8(0x4007F001)
#define RCM_SRS1_SW 0x04u

/* ---- PMC ---- */
#define PMC_REGSC REG8(0x4007D002)
#define PMC_REGSC_ACKISO 0x08u

/* ---- WDOG (16-bit registers) ---- */
#define WDOG_STCTRLH REG16(0x40052000)
#define WDOG_STCTRLH_WAITEN 0x0080u
#define WDOG_STCTRLH_STOPEN 0x0040u
#define WDOG_STCTRLH_ALLOWUPDATE 0x0010u
#define WDOG_STCTRLH_WDOGEN 0x0001u
#define WDOG_TOVALH REG16(0x40052004)
#define WDOG_TOVALL REG16(0x40052006)
#define WDOG_REFRESH REG16(0x4005200C)
#define WDOG_UNLOCK REG16(0x4005200E)
#define WDOG_PRESC REG16(0x40052016)
#define WDOG_UNLOCK_SEQ1 0xC520u
#define WDOG_UNLOCK_SEQ2 0xD928u
#define WDOG_REFRESH_SEQ1 0xA602u
#define WDOG_REFRESH_SEQ2 0xB480u

/* ---- MCG and OSC ---- */
#define MCG_C1 REG8(0x40064000)
#define MCG_C1_CLKS(n) ((uint8_t)(((n) & 3u) << 6)) /* 0 FLL/PLL, 1 internal, 2 external */
#define MCG_C1_FRDIV(n) ((uint8_t)(((n) & 7u) << 3))
#define MCG_C2 REG8(0x40064001)
#define MCG_C2_RANGE0(n) ((uint8_t)(((n) & 3u) << 4)) /* 2: very high frequency crystal */
#define MCG_C2_EREFS 0x04u
#define MCG_C5 REG8(0x40064004)
#define MCG_C5_PRDIV0(n) ((uint8_t)((n) & 0x1Fu)) /* PLL input divide = n + 1 */
#define MCG_C6 REG8(0x40064005)
#define MCG_C6_PLLS 0x40u
#define MCG_C6_VDIV0(n) ((uint8_t)((n) & 0x1Fu)) /* PLL multiply = n + 24 */
#define MCG_S REG8(0x40064006)
#define MCG_S_LOCK0 0x40u
#define MCG_S_PLLST 0x20u
#define MCG_S_IREFST 0x10u
#define MCG_S_CLKST_MASK 0x0Cu
#define MCG_S_CLKST(n) ((uint8_t)(((n) & 3u) << 2))
#define MCG_S_OSCINIT0 0x02u
#define OSC0_CR REG8(0x40065000)
#define OSC_ERCLKEN 0x80u
#define OSC_SC8P 0x02u
#define OSC_SC2P 0x08u

/* ---- PORT (pin mux) and GPIO; port index 0..4 = A..E ---- */
#define PORT_PCR(port, bit) REG32(0x40049000u + 0x1000u * (port) + 4u * (bit))
#define PORT_PCR_MUX(n) ((uint32_t)((n) & 7u) << 8)
#define PORT_PCR_DSE 0x40u
#define PORT_PCR_SRE 0x04u
#define PORT_PCR_PE 0x02u
#define PORT_PCR_PS 0x01u
#define GPIO_PDOR(port) REG32(0x400FF000u + 0x40u * (port))
#define GPIO_PSOR(port) REG32(0x400FF004u + 0x40u * (port))
#define GPIO_PCOR(port) REG32(0x400FF008u + 0x40u * (port))
#define GPIO_PDIR(port) REG32(0x400FF010u + 0x40u * (port))
#define GPIO_PDDR(port) REG32(0x400FF014u + 0x40u * (port))

/* ---- UART0 (0x4006A000), UART1 (0x4006B000), UART2 (0x4006C000) ---- */
#define UART_BASE(n) (0x4006A000u + 0x1000u * (n))
#define UART_BDH(n) REG8(UART_BASE(n) + 0x0u)
#define UART_BDL(n) REG8(UART_BASE(n) + 0x1u)
#define UART_C1(n) REG8(UART_BASE(n) + 0x2u)
#define UART_C2(n) REG8(UART_BASE(n) + 0x3u)
#define UART_S1(n) REG8(UART_BASE(n) + 0x4u)
#define UART_D(n) REG8(UART_BASE(n) + 0x7u)
#define UART_C4(n) REG8(UART_BASE(n) + 0xAu)
#define UART_C2_TIE 0x80u
#define UART_C2_RIE 0x20u
#define UART_C2_TE 0x08u
#define UART_C2_RE 0x04u
#define UART_S1_TDRE 0x80u
#define UART_S1_RDRF 0x20u
#define UART_S1_OR 0x08u
#define UART_S1_NF 0x04u
#define UART_S1_FE 0x02u
#define UART_S1_PF 0x01u

/* ---- ADC0 ---- */
#define ADC0_SC1A REG32(0x4003B000)
#define ADC_SC1_COCO 0x80u
#define ADC_SC1_ADCH(n) ((uint32_t)(n) & 0x1Fu)
#define ADC0_CFG1 REG32(0x4003B008)
#define ADC_CFG1_ADIV(n) ((uint32_t)((n) & 3u) << 5)
#define ADC_CFG1_MODE(n) ((uint32_t)((n) & 3u) << 2) /* 1: 12 bit */
#define ADC_CFG1_ADICLK(n) ((uint32_t)(n) & 3u)       /* 1: bus / 2 */
#define ADC0_CFG2 REG32(0x4003B00C)
#define ADC_CFG2_MUXSEL 0x10u
#define ADC_CFG2_ADHSC 0x04u
#define ADC0_RA REG32(0x4003B010)
#define ADC0_SC2 REG32(0x4003B020)
#define ADC0_SC3 REG32(0x4003B024)
#define ADC_SC3_CAL 0x80u
#define ADC_SC3_CALF 0x40u
#define ADC_SC3_AVGE 0x04u
#define ADC_SC3_AVGS(n) ((uint32_t)(n) & 3u)
#define ADC0_PG REG32(0x4003B02C)
#define ADC0_MG REG32(0x4003B030)
#define ADC0_CLP(k) REG32(0x4003B04Cu - 4u * (k)) /* CLP0 0x4C, CLP1 0x48 .. CLP4 0x3C */
#define ADC0_CLPS REG32(0x4003B038)
#define ADC0_CLM(k) REG32(0x4003B06Cu - 4u * (k)) /* CLM0 0x6C .. CLM4 0x5C */
#define ADC0_CLMS REG32(0x4003B058)

/* ---- SPI0 ---- */
#define SPI0_MCR REG32(0x4002C000)
#define SPI_MCR_MSTR 0x80000000u
#define SPI_MCR_PCSIS(n) ((uint32_t)((n) & 0x1Fu) << 16)
#define SPI_MCR_CLR_TXF 0x00000800u
#define SPI_MCR_CLR_RXF 0x00000400u
#define SPI_MCR_HALT 0x00000001u
#define SPI0_CTAR0 REG32(0x4002C00C)
#define SPI_CTAR_FMSZ(n) ((uint32_t)((n) & 0xFu) << 27)
#define SPI_CTAR_CPOL 0x04000000u
#define SPI_CTAR_CPHA 0x02000000u
#define SPI_CTAR_PBR(n) ((uint32_t)((n) & 3u) << 16)
#define SPI_CTAR_BR(n) ((uint32_t)(n) & 0xFu)
#define SPI0_SR REG32(0x4002C02C)
#define SPI_SR_TCF 0x80000000u
#define SPI_SR_EOQF 0x10000000u
#define SPI_SR_RFDF 0x00020000u
#define SPI0_PUSHR REG32(0x4002C034)
#define SPI0_POPR REG32(0x4002C038)

/* ---- FTM0 (0x40038000), FTM1 (0x40039000), FTM2 (0x400B8000) ---- */
#define FTM_BASE(n) ((n) == 2u ? 0x400B8000u : 0x40038000u + 0x1000u * (n))
#define FTM_SC(n) REG32(FTM_BASE(n) + 0x00u)
#define FTM_SC_TOF 0x80u
#define FTM_SC_CLKS(n) ((uint32_t)((n) & 3u) << 3) /* 1: system (bus) clock */
#define FTM_SC_PS(n) ((uint32_t)(n) & 7u)          /* divide by 2^n */
#define FTM_CNT(n) REG32(FTM_BASE(n) + 0x04u)
#define FTM_MOD(n) REG32(FTM_BASE(n) + 0x08u)
#define FTM_CSC(n, ch) REG32(FTM_BASE(n) + 0x0Cu + 8u * (ch))
#define FTM_CV(n, ch) REG32(FTM_BASE(n) + 0x10u + 8u * (ch))
#define FTM_CNTIN(n) REG32(FTM_BASE(n) + 0x4Cu)
#define FTM_MODE(n) REG32(FTM_BASE(n) + 0x54u)
#define FTM_MODE_WPDIS 0x04u
#define FTM_CSC_CHF 0x80u
#define FTM_CSC_CHIE 0x40u
#define FTM_CSC_MSB 0x20u
#define FTM_CSC_MSA 0x10u
#define FTM_CSC_ELSB 0x08u
#define FTM_CSC_ELSA 0x04u

/* ---- FTFL and FlexRAM (EEPROM emulation) ---- */
#define FTFL_FSTAT REG8(0x40020000)
#define FTFL_FSTAT_CCIF 0x80u
#define FTFL_FSTAT_ERRORS 0x70u /* RDCOLERR | ACCERR | FPVIOL */
#define FTFL_FCNFG REG8(0x40020001)
#define FTFL_FCNFG_RAMRDY 0x02u
#define FTFL_FCNFG_EEERDY 0x01u
#define FTFL_FCCOB0 REG8(0x40020007)
#define FTFL_FCCOB4 REG8(0x4002000B)
#define FTFL_FCCOB5 REG8(0x4002000A)
#define FTFL_CMD_PGMPART 0x80u
#define FLEXRAM_BASE 0x14000000u

/* ---- Cortex-M4 core ---- */
#define SYST_CSR REG32(0xE000E010)
#define SYST_CSR_CLKSOURCE 0x4u
#define SYST_CSR_TICKINT 0x2u
#define SYST_CSR_ENABLE 0x1u
#define SYST_RVR REG32(0xE000E014)
#define SYST_CVR REG32(0xE000E018)
#define SCB_ICSR REG32(0xE000ED04)
#define SCB_ICSR_PENDSTSET 0x04000000u
#define SCB_AIRCR REG32(0xE000ED0C)
#define SCB_AIRCR_SYSRESETREQ 0x05FA0004u
#define SCB_SHPR3 REG32(0xE000ED20) /* byte 3: SysTick priority */
#define NVIC_ISER(n) REG32(0xE000E100u + 4u * ((n) >> 5))
#define NVIC_IPR(n) REG8(0xE000E400u + (n))

/* IRQ numbers (vector = 16 + IRQ) */
#define IRQ_UART0_STATUS 45u
#define IRQ_UART1_STATUS 47u
#define IRQ_UART2_STATUS 49u
#define IRQ_FTM0 62u
#define IRQ_FTM1 63u
#define IRQ_FTM2 64u
#define NVIC_NUM_IRQ 95u

static inline void nvic_enable(uint32_t irq, uint8_t priority)
{
    NVIC_IPR(irq) = priority;
    NVIC_ISER(irq) = 1u << (irq & 31u);
}

static inline uint32_t irq_save(void)
{
    uint32_t primask;
    __asm__ volatile("mrs %0, primask\n cpsid i" : "=r"(primask)::"memory");
    return primask;
}

static inline void irq_restore(uint32_t primask)
{
    __asm__ volatile("msr primask, %0" ::"r"(primask) : "memory");
}

#endif /* AW_TEENSY32_REGS_H */
