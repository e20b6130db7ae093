"""The firmware's layering (STYLE 1-3): board code sees only the HAL, and the two HAL
backends are sibling folders with the same file names.

If board code reached a register or a backend header, the native (SIL) build would
no longer run the same logic as the Teensy — the whole point of the HAL.
"""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
BOARDS = REPO / "firmware" / "boards"
HAL = REPO / "firmware" / "hal"

# headers that belong to a backend or a vendor, never to board code
FORBIDDEN_INCLUDES = re.compile(
    r'#\s*include\s*[<"](?:[^">]*/)?(?:teensy32/|native/|kinetis|mk20|core_pins|'
    r"regs\.h|board_pins\.h|teensy32\.h|native\.h|sim_proto\.h|tsl1401_model\.h|"
    r"Arduino|avr/|unistd|termios|sys/)",
    re.IGNORECASE,
)
# MK20 register / peripheral names: board code must ask the HAL instead
REGISTER_NAMES = re.compile(
    r"\b(?:SIM_SCGC\d|SIM_CLKDIV\d|PORT[A-E]_PCR\d+|PORT_PCR|GPIO[A-E]_P[DSCT]OR|GPIO_P\w+|"
    r"UART\d_(?:C\d|S\d|D|BDH|BDL)|FTM\d_\w+|ADC\d_\w+|SPI\d_\w+|WDOG_\w+|MCG_\w+|NVIC_\w+|"
    r"SYST_\w+|SCB_\w+|FTFL_\w+|0x4[0-9A-Fa-f]{7})\b"
)


def board_sources() -> list[Path]:
    return sorted(p for p in BOARDS.rglob("*") if p.suffix in (".c", ".h"))


def test_board_code_includes_no_vendor_or_backend_header():
    offenders = []
    for path in board_sources():
        for lineno, line in enumerate(path.read_text().splitlines(), 1):
            if FORBIDDEN_INCLUDES.search(line):
                offenders.append(f"{path.relative_to(REPO)}:{lineno}: {line.strip()}")
    assert not offenders, "board code includes a backend/vendor header:\n" + "\n".join(offenders)


def test_board_code_names_no_mk20_register():
    offenders = []
    for path in board_sources():
        text = re.sub(r"/\*.*?\*/|//[^\n]*", "", path.read_text(), flags=re.DOTALL)
        for lineno, line in enumerate(text.splitlines(), 1):
            match = REGISTER_NAMES.search(line)
            if match:
                offenders.append(f"{path.relative_to(REPO)}:{lineno}: {match.group(0)}")
    assert not offenders, "board code touches registers:\n" + "\n".join(offenders)


def test_the_layering_checks_would_catch_an_offender():
    # the two patterns above must fire on what they are meant to catch
    assert FORBIDDEN_INCLUDES.search('#include "teensy32/regs.h"')
    assert FORBIDDEN_INCLUDES.search("#include <kinetis.h>")
    assert FORBIDDEN_INCLUDES.search('#include "board_pins.h"')
    assert not FORBIDDEN_INCLUDES.search('#include "hal.h"')
    assert REGISTER_NAMES.search("SIM_SCGC4 |= 1;")
    assert REGISTER_NAMES.search("*(volatile uint32_t *)0x4006A000 = 0;")
    assert not REGISTER_NAMES.search("hal->uart_write(HAL_PORT_HOST, buf, n);")


def test_backends_are_siblings_with_the_same_file_names():
    # STYLE 2: the same concept lives in the same file name in every backend
    common = {"hal.c", "main.c", "time.c", "uart.c", "gpio.c", "adc.c", "spi.c", "capture.c",
              "pwm.c", "watchdog.c", "config.c"}
    for backend in ("teensy32", "native"):
        names = {p.name for p in (HAL / backend).glob("*.c")}
        assert common <= names, f"hal/{backend} lacks {sorted(common - names)}"


def test_only_the_teensy_pin_header_maps_roles_to_pins():
    # STYLE 3: pins appear in one header per target; the backend's drivers use roles
    pin_tables = [p.name for p in (HAL / "teensy32").glob("*")
                  if re.search(r"\buart_map\[HAL_PORT_COUNT\]\s*=", p.read_text())]
    assert pin_tables == ["board_pins.h"]
