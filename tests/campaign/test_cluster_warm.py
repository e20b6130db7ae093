"""Workers of one machine warm their kernels one after another (airwake.campaign.cluster)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]


def test_processes_holding_the_warm_lock_run_one_after_another(tmp_path):
    # three processes started together: their locked blocks must not overlap in time
    code = textwrap.dedent(f"""
        import sys, time
        from airwake.campaign.cluster import one_process_at_a_time
        with one_process_at_a_time("airwake-test-lock-{tmp_path.name}"):
            t0 = time.time()
            time.sleep(0.4)
            t1 = time.time()
        print(t0, t1)
    """)
    procs = [subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True,
                              cwd=ROOT) for _ in range(3)]
    spans = sorted(tuple(map(float, p.communicate(timeout=60)[0].split())) for p in procs)
    assert all(p.returncode == 0 for p in procs)
    for (_, end), (start, _) in zip(spans, spans[1:], strict=False):
        assert start >= end, spans


def test_warm_loads_the_model_and_both_kinds_of_truth_field():
    # in a process of its own: warm() holds its process to one thread
    code = "import json\nfrom airwake.campaign.cluster import warm\nprint(json.dumps(warm()))\n"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, timeout=600, check=True)
    info = json.loads(out.stdout.splitlines()[-1])
    assert info["models"] == ["table52"]
    assert info["truth_scenarios"] == ["ship_airwake_b0", "fans_indoor"]
