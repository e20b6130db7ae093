"""Firmware algorithm benchmark: callgrind instruction counts and a Cortex-M4 estimate.

Loaded by `airwake bench` (SECTION "firmware"). Builds the callgrind drivers
(`make -C firmware algo-bench algo-arm`), runs each under valgrind's callgrind with
collection toggled on inside the measured function, and reports per call:

* `firmware_losa_frame_instructions`: x86-64 instructions (callgrind Ir) of one
  `losa_frame_process` (4 sensors: peaks + slot tracking + exposure);
* `firmware_marker_step_instructions`: the same for one `marker_imu_step` (tracking);
* an estimate of the cycles on the 96 MHz MK20DX256 (Cortex-M4, no FPU, soft float),
  the time and the share of the budget (300 Hz LOSA frame: 3.33 ms; marker at 450 Hz).

The M4 model. Every scalar SSE float/double instruction that callgrind saw executed is a
libgcc soft-float call on the M4 and costs SOFT_FLOAT_CYCLES (libgcc's ARM
ieee754-sf/df.S routines incl. call overhead, rounded up from their published cycle
counts). Every other x86 instruction costs INT_CYCLES_PER_X86_INSTR M4 cycles: ~1.25
Thumb-2 instructions per x86 instruction (load/store architecture, 64-bit arithmetic
split in two) at CPI ~1.3 (branches, and flash wait states at 96 MHz that the MK20's
prefetch buffer mostly hides). The drivers are built -O2 without vectorisation so each
float operation is one scalar instruction. The per-instruction profile comes from
`--dump-instr=yes` mapped onto `objdump -d` of the (non-PIE) driver.

Also reported: code size (text + data) of each board's algorithm modules compiled for
the M4 with arm-none-eabi-gcc -Os.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from collections import Counter
from pathlib import Path

SECTION = "firmware"
REPO = Path(__file__).resolve().parents[2]
BUILD = REPO / "build"

M4_HZ = 96e6
LOSA_FRAME_BUDGET_S = 1.0 / 300.0
MARKER_RATE_HZ = 450.0
INT_CYCLES_PER_X86_INSTR = 1.6
SOFT_FLOAT_CYCLES = {
    "f_add": 60,
    "f_mul": 55,
    "f_div": 130,
    "f_sqrt": 450,
    "f_cmp": 30,
    "f_cvt": 45,
    "d_add": 100,
    "d_mul": 110,
    "d_div": 350,
    "d_sqrt": 800,
    "d_cmp": 40,
    "d_cvt": 50,
}
_FLOAT_OPS = [
    (re.compile(r"^(add|sub)ss$"), "f_add"),
    (re.compile(r"^mulss$"), "f_mul"),
    (re.compile(r"^divss$"), "f_div"),
    (re.compile(r"^sqrtss$"), "f_sqrt"),
    (re.compile(r"^(u?comiss|maxss|minss|cmp\w*ss)$"), "f_cmp"),
    (re.compile(r"^(cvtsi2ss[lq]?|cvtt?ss2si[lq]?)$"), "f_cvt"),
    (re.compile(r"^(add|sub)sd$"), "d_add"),
    (re.compile(r"^mulsd$"), "d_mul"),
    (re.compile(r"^divsd$"), "d_div"),
    (re.compile(r"^sqrtsd$"), "d_sqrt"),
    (re.compile(r"^(u?comisd|maxsd|minsd|cmp\w*sd)$"), "d_cmp"),
    (re.compile(r"^(cvtsi2sd[lq]?|cvtt?sd2si[lq]?|cvtss2sd|cvtsd2ss)$"), "d_cvt"),
]

DRIVERS = {
    # key prefix: (driver, measured function, calls in full / quick mode)
    "losa_frame": ("bench_losa_frame", "losa_frame_process", 2000, 200),
    "marker_step": ("bench_marker_step", "marker_imu_step", 20000, 2000),
}
BOARD_MODULES = {
    "losa": ["boards/losa/peak", "boards/losa/slots", "boards/losa/exposure", "boards/losa/frame"],
    "marker": [
        "boards/marker/leds",
        "boards/marker/attitude",
        "boards/marker/marker_logic",
        "common/quat",
    ],
    "rover": [
        "boards/rover/crc16_xmodem",
        "boards/rover/vn200",
        "boards/rover/sbp",
        "boards/rover/rotor_speed",
        "boards/base/pwm_capture",
    ],
    "base": [
        "boards/rover/crc16_xmodem",
        "boards/rover/vn200",
        "boards/rover/sbp",
        "boards/base/pwm_capture",
        "boards/base/sbus",
    ],
}


def _make(*targets: str) -> None:
    subprocess.run(["make", "-s", "-C", str(REPO / "firmware"), *targets], check=True)


def _mnemonics(binary: Path) -> dict[int, str]:
    out = subprocess.run(
        ["objdump", "-d", "--no-show-raw-insn", str(binary)],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    table = {}
    for line in out.splitlines():
        m = re.match(r"^\s*([0-9a-f]+):\s+(\S+)", line)
        if m:
            table[int(m.group(1), 16)] = m.group(2)
    return table


def _classify(mnemonic: str) -> str:
    for pattern, cls in _FLOAT_OPS:
        if pattern.match(mnemonic):
            return cls
    return "int"


def profile(binary: Path, function: str, calls: int) -> dict:
    """Instructions per call of `function`, by class (int / soft-float op kinds)."""
    if shutil.which("valgrind") is None:
        raise RuntimeError("valgrind not installed (make setup installs it)")
    with tempfile.TemporaryDirectory() as tmp:
        out_file = Path(tmp) / "callgrind.out"
        subprocess.run(
            [
                "valgrind",
                "--tool=callgrind",
                "--dump-instr=yes",
                "--dump-line=no",
                "--compress-pos=no",
                "--compress-strings=no",
                f"--toggle-collect={function}",
                f"--callgrind-out-file={out_file}",
                str(binary),
                str(calls),
            ],
            check=True,
            capture_output=True,
        )
        text = out_file.read_text()
    mnemonic = _mnemonics(binary)
    by_class: Counter = Counter()
    skip_next = False
    for line in text.splitlines():
        if line.startswith("calls="):
            skip_next = True  # the next cost line is the call's inclusive cost
            continue
        m = re.match(r"^(0x[0-9a-f]+)\s+(\d+)$", line)
        if not m:
            continue
        if skip_next:
            skip_next = False
            continue
        cls = _classify(mnemonic.get(int(m.group(1), 16), ""))
        by_class[cls] += int(m.group(2))
    total = sum(by_class.values())
    summary = re.search(r"^summary:\s+(\d+)", text, re.M)
    if summary and int(summary.group(1)) != total:
        raise RuntimeError(
            f"callgrind profile of {function}: per-instruction sum {total} "
            f"!= summary {summary.group(1)}"
        )
    return {cls: n / calls for cls, n in by_class.items()}


def m4_cycles(per_call: dict) -> float:
    cycles = per_call.get("int", 0.0) * INT_CYCLES_PER_X86_INSTR
    for cls, n in per_call.items():
        if cls != "int":
            cycles += n * SOFT_FLOAT_CYCLES[cls]
    return cycles


def code_sizes() -> dict:
    sizes = {}
    for board, modules in BOARD_MODULES.items():
        objs = [str(BUILD / "teensy32" / "algos" / f"{m}.o") for m in modules]
        out = subprocess.run(
            ["arm-none-eabi-size", "-t", *objs], check=True, capture_output=True, text=True
        ).stdout
        text, data = out.strip().splitlines()[-1].split()[:2]
        sizes[f"firmware_algo_flash_bytes_{board}"] = int(text) + int(data)
    return sizes


def run(quick: bool) -> dict:
    _make("algo-bench", "algo-arm")
    figures: dict = {}
    for key, (driver, function, full, short) in DRIVERS.items():
        calls = short if quick else full
        per_call = profile(BUILD / "native" / "algo_bench" / driver, function, calls)
        cycles = m4_cycles(per_call)
        figures[f"firmware_{key}_instructions"] = round(sum(per_call.values()))
        figures[f"firmware_{key}_soft_float_ops"] = round(
            sum(n for c, n in per_call.items() if c != "int"), 1
        )
        figures[f"firmware_{key}_m4_cycles_est"] = round(cycles)
        figures[f"firmware_{key}_m4_us_est"] = round(cycles / M4_HZ * 1e6, 2)
    figures["firmware_losa_frame_budget_pct"] = round(
        100.0 * figures["firmware_losa_frame_m4_cycles_est"] / (M4_HZ * LOSA_FRAME_BUDGET_S), 2
    )
    figures["firmware_marker_cpu_pct_at_450hz"] = round(
        100.0 * figures["firmware_marker_step_m4_cycles_est"] * MARKER_RATE_HZ / M4_HZ, 2
    )
    figures.update(code_sizes())
    return figures


if __name__ == "__main__":
    import json
    import sys

    print(json.dumps(run(quick="--quick" in sys.argv), indent=2))
