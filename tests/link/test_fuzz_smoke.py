"""libFuzzer in `make test`: the link decoder, the VN200 and the SBP parsers, each for
10^6 inputs under ASan + UBSan (firmware/fuzz/, firmware/mk/fuzz.mk).

The corpora are seeded by firmware/fuzz/make_seeds.py: the golden vectors of
protocol/vectors/ for the decoder, synthetic valid packets for the VN200 and SBP parsers.
Each target checks invariants, not only the absence of crashes (valid CRC of every
packet handed out, byte accounting, whole = chunked feed, exact recovery of generated
packet streams). Longer runs: `make -C firmware fuzz-run FUZZ_TIME=600` (docs/firmware.md).
`make test` installs clang through `make setup`, so a missing clang fails here.
"""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess

import pytest

from .conftest import REPO, build_firmware_target

RUNS = 1_000_000
# Inputs stay short, so 10^6 of them fit the time budget of `make test` (about 50 s of
# CPU for the three): a whole golden frame (<= 272 bytes) for the decoder, a packet and a
# half (VN-100 style: 124 bytes, ours: 88) for the parsers, whose recipe half still
# builds streams of up to 384 bytes from them.
MAX_LEN = {"fuzz_decoder": 300, "fuzz_vn200": 192, "fuzz_sbp": 192}
SAFETY_S = 240  # -max_total_time: a cap far above the ~10-45 s these take; not the goal
TARGETS = ("fuzz_decoder", "fuzz_vn200", "fuzz_sbp")


def _seeds_module():
    path = REPO / "firmware/fuzz/make_seeds.py"
    spec = importlib.util.spec_from_file_location("make_seeds", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def parse_libfuzzer(output: str) -> dict:
    """The run count ("Done N runs in S second(s)") and the final stats of libFuzzer."""
    done = re.findall(r"^Done (\d+) runs in (\d+) second", output, re.M)
    stats = dict(re.findall(r"^stat::(\w+):\s+(\d+)", output, re.M))
    rate = stats.get("average_exec_per_sec")
    return {"runs": int(done[-1][0]) if done else None,
            "seconds": int(done[-1][1]) if done else None,
            "exec_per_s": int(rate) if rate is not None else None}


def test_parse_libfuzzer_reads_the_done_line():
    out = ("#1000000\tDONE   cov: 193 ft: 1145 corp: 340/11389b lim: 256 exec/s: 40000 rss: 435Mb\n"
           "Done 1000000 runs in 25 second(s)\nstat::number_of_executed_units: 1000000\n"
           "stat::average_exec_per_sec:     40000\n")
    assert parse_libfuzzer(out) == {"runs": 1_000_000, "seconds": 25, "exec_per_s": 40000}
    assert parse_libfuzzer("==1== ERROR: libFuzzer: deadly signal\n")["runs"] is None


def test_seeds_are_valid_packets():
    """The synthetic seeds are what they claim: CRC-valid VN200 packets and SBP frames."""
    import binascii

    seeds = _seeds_module()
    vn = seeds.vn200_seeds()
    for name in ("ours", "vn100_style", *(f"group{g}_all_fields" for g in range(1, 8))):
        pkt = vn[name]
        assert pkt[0] == 0xFA and binascii.crc_hqx(pkt[1:], 0) == 0, name
    assert len(vn["ours"]) == 88 and len(vn["vn100_style"]) == 124
    for name, frame in seeds.sbp_seeds().items():
        if name == "stream":
            continue
        assert frame[0] == 0x55 and len(frame) == 8 + frame[5], name
        assert binascii.crc_hqx(frame[1:-2], 0) == int.from_bytes(frame[-2:], "little"), name
    dec = seeds.decoder_seeds()
    assert sum(k.startswith("frame_") for k in dec) >= 20


@pytest.fixture(scope="module")
def fuzzers():
    if shutil.which("clang") is None:
        pytest.fail("clang (libFuzzer) is not installed: run `make setup` (make test does), "
                    "it installs clang and libclang-rt-14-dev")
    for t in TARGETS:
        build_firmware_target(REPO / "build/fuzz" / t)
    return {t: REPO / "build/fuzz" / t for t in TARGETS}


@pytest.mark.parametrize("target", TARGETS)
def test_a_million_inputs_without_a_crash(fuzzers, target, tmp_path):
    corpus = tmp_path / "corpus"
    n_seeds = _seeds_module().write_seeds(corpus, [target])[target]
    assert n_seeds > 0
    cmd = [str(fuzzers[target]), f"-runs={RUNS}", f"-max_total_time={SAFETY_S}",
           f"-max_len={MAX_LEN[target]}", "-seed=1", "-print_final_stats=1",
           f"-artifact_prefix={tmp_path}/", str(corpus / target)]
    result = subprocess.run(cmd, capture_output=True, text=True, timeout=SAFETY_S + 60)
    out = result.stdout + result.stderr
    crashes = sorted(p.name for p in tmp_path.glob("*-*") if p.is_file())
    assert result.returncode == 0 and not crashes, \
        f"{target}: rc {result.returncode}, {crashes}\n{out[-3000:]}"
    stats = parse_libfuzzer(out)
    print(f"{target}: {stats}")
    assert stats["runs"] is not None and stats["runs"] >= RUNS, \
        f"{target} stopped early: {stats}\n{out[-1500:]}"
