"""A few seconds of libFuzzer on the C decoder (the long runs are `make -C firmware proto-fuzz`)."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from .conftest import REPO, build_firmware_target

FUZZER = REPO / "build/fuzz/fuzz_decoder"


@pytest.mark.skipif(shutil.which("clang") is None, reason="clang (libFuzzer) not installed")
def test_decoder_survives_a_short_fuzz_run(tmp_path):
    try:
        build_firmware_target(FUZZER)
    except subprocess.CalledProcessError:
        pytest.skip("clang cannot build libFuzzer targets here")
    corpus = tmp_path / "corpus"
    corpus.mkdir()
    for i, name in enumerate(("frames.json", "streams.json")):
        (corpus / f"seed{i}").write_bytes((REPO / "protocol/vectors" / name).read_bytes()[:4096])
    result = subprocess.run([str(FUZZER), "-max_total_time=3", "-seed=1", str(corpus)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr[-2000:]
