"""The Teensy 3.2 images: what the MK20DX256 and the Teensy bootloader need to find.

These are checked on the .hex files (what `make flash` writes) and the .elf symbols.
A wrong FSEC byte at 0x40C secures the chip for good; an even reset vector faults on
the first instruction; an initial stack pointer outside SRAM faults before main.
The images are built if missing (`make -C firmware teensy32`).
"""

from __future__ import annotations

import fcntl
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
IMAGES = REPO / "build" / "teensy32"
BOARDS = ("losa", "marker", "rover", "base")

FLASH_SIZE = 256 * 1024
SRAM_L = (0x1FFF8000, 0x20000000)
SRAM_U = (0x20000000, 0x20008000)
RAM_SIZE = 64 * 1024
STACK_RESERVE = 8 * 1024
VECTORS = 16 + 95  # core exceptions + MK20DX256 interrupts
# backdoor key, FPROT0-3, FSEC (0xDE: unsecured, mass erase allowed), FOPT, FEPROT, FDPROT
FLASH_CONFIG = bytes([0xFF] * 12 + [0xDE, 0xF9, 0xFF, 0xFF])

pytestmark = pytest.mark.skipif(shutil.which("arm-none-eabi-gcc") is None,
                                reason="arm-none-eabi-gcc not installed (make setup)")


def parse_ihex(path: Path) -> dict[int, int]:
    """Intel HEX -> {address: byte}; checks every record's checksum."""
    memory: dict[int, int] = {}
    base = 0
    for lineno, line in enumerate(path.read_text().splitlines(), 1):
        if not line:
            continue
        assert line[0] == ":", f"{path}:{lineno}: not an Intel HEX record"
        raw = bytes.fromhex(line[1:])
        assert sum(raw) & 0xFF == 0, f"{path}:{lineno}: bad record checksum"
        count, addr, kind, data = raw[0], int.from_bytes(raw[1:3], "big"), raw[3], raw[4:-1]
        assert len(data) == count, f"{path}:{lineno}: length field disagrees"
        if kind == 0x00:
            for i, b in enumerate(data):
                assert base + addr + i not in memory, f"{path}: address written twice"
                memory[base + addr + i] = b
        elif kind == 0x02:
            base = int.from_bytes(data, "big") << 4
        elif kind == 0x04:
            base = int.from_bytes(data, "big") << 16
        elif kind == 0x01:
            break
    return memory


def word(memory: dict[int, int], addr: int) -> int:
    return int.from_bytes(bytes(memory[addr + i] for i in range(4)), "little")


@pytest.fixture(scope="module")
def images() -> dict[str, dict[int, int]]:
    if not all((IMAGES / f"{b}.hex").exists() for b in BOARDS):
        lock_path = REPO / "build" / ".teensy32-build.lock"
        lock_path.parent.mkdir(parents=True, exist_ok=True)
        with open(lock_path, "w") as lock:  # one make at a time under pytest-xdist
            fcntl.flock(lock, fcntl.LOCK_EX)
            subprocess.run(["make", "-s", "-C", str(REPO / "firmware"), "teensy32"],
                           check=True, capture_output=True)
    return {b: parse_ihex(IMAGES / f"{b}.hex") for b in BOARDS}


def symbols(board: str) -> dict[str, int]:
    out = subprocess.run(["arm-none-eabi-nm", str(IMAGES / f"{board}.elf")], check=True,
                         capture_output=True, text=True).stdout
    table = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3:
            table[parts[2]] = int(parts[0], 16)
    return table


def section_sizes(board: str) -> dict[str, int]:
    out = subprocess.run(["arm-none-eabi-size", "-A", str(IMAGES / f"{board}.elf")],
                         check=True, capture_output=True, text=True).stdout
    sizes = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[0].startswith("."):
            sizes[parts[0]] = int(parts[1])
    return sizes


@pytest.mark.parametrize("board", BOARDS)
def test_flash_config_field_keeps_the_chip_unsecured(images, board):
    # FSEC != 0xDE (SEC bits != 10) would secure the MK20: the bootloader loses it
    memory = images[board]
    field = bytes(memory[0x400 + i] for i in range(16))
    assert field == FLASH_CONFIG, f"{board}: flash config {field.hex()}"
    assert memory[0x40C] == 0xDE


@pytest.mark.parametrize("board", BOARDS)
def test_vector_table_at_zero_has_stack_in_sram_and_thumb_reset_vector(images, board):
    memory = images[board]
    sym = symbols(board)
    sp = word(memory, 0)
    assert SRAM_L[0] < sp <= SRAM_U[1] and sp % 8 == 0, f"{board}: initial SP {sp:#x}"
    assert sp == sym["_estack"]
    reset = word(memory, 4)
    assert reset & 1, f"{board}: reset vector {reset:#x} is not a Thumb address"
    assert (reset & ~1) == sym["reset_handler"]
    assert sym["vector_table"] == 0 and sym["flash_config"] == 0x400


@pytest.mark.parametrize("board", BOARDS)
def test_every_exception_and_interrupt_vector_is_a_thumb_address_in_flash(images, board):
    # a zero or even vector turns a stray interrupt into a lock-up instead of a handler
    memory = images[board]
    for i in range(1, VECTORS):
        v = word(memory, 4 * i)
        assert v & 1 and (v & ~1) < FLASH_SIZE, f"{board}: vector {i} = {v:#x}"


@pytest.mark.parametrize("board", BOARDS)
def test_image_fits_the_mk20dx256_flash_and_sram(images, board):
    memory = images[board]
    assert max(memory) < FLASH_SIZE, f"{board}: image reaches {max(memory):#x}"
    assert min(memory) == 0
    sizes = section_sizes(board)
    flash = sizes[".text"] + sizes.get(".ARM.exidx", 0) + sizes[".data"]
    ram = sizes[".data"] + sizes[".bss"] + sizes.get(".noinit", 0)
    assert flash <= FLASH_SIZE
    assert ram + STACK_RESERVE <= RAM_SIZE, f"{board}: {ram} B RAM + stack"
    # no section straddles the SRAM_L / SRAM_U boundary (accesses across it fault)
    sym = symbols(board)
    assert sym["_ebss"] <= SRAM_L[1] and sym["_sdata"] >= SRAM_U[0]


@pytest.mark.parametrize("board", BOARDS)
def test_image_never_calls_the_heap_or_stdio(board, images):
    # no dynamic allocation (STYLE 5): the link has no syscalls, so malloc would fail
    # to link — and nothing may pull it in through printf & co. either
    sym = symbols(board)
    for name in ("malloc", "free", "_sbrk", "printf", "_malloc_r"):
        assert name not in sym, f"{board} links {name}"
