"""The firmware bench (firmware/bench/bench.py): callgrind profile plumbing."""

import importlib.util
import shutil

import awboards as A
import pytest

pytestmark = pytest.mark.skipif(shutil.which("valgrind") is None, reason="valgrind missing")


def _bench():
    spec = importlib.util.spec_from_file_location("fw_bench", A.FIRMWARE / "bench" / "bench.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bench_reports_contract_keys_and_fits_budget():
    # Why: `airwake bench` consumers read these keys; the LOSA frame must stay far
    # inside ARCHITECTURE's 96k-cycle budget (instruction counts are deterministic).
    figures = _bench().run(quick=True)
    for key in ("firmware_losa_frame_instructions", "firmware_marker_step_instructions"):
        assert figures[key] > 0
    assert figures["firmware_losa_frame_soft_float_ops"] > 0  # the classifier sees floats
    assert figures["firmware_losa_frame_m4_cycles_est"] < 96_000
    assert figures["firmware_losa_frame_budget_pct"] < 50
    assert all(figures[f"firmware_algo_flash_bytes_{b}"] > 0 for b in A_BOARDS)


A_BOARDS = ("losa", "marker", "rover", "base")
