"""`airwake campaign --scheduler` against a `dask scheduler` and a `dask worker` started
here (one flight through every step: calibrate, estimate, map, report, merge), and the
index page in a real browser: the flight's map and report and the merged map open with
all their figures."""

import json
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest
from browser import IMAGES, Browser
from campaigns import write_campaign

DASK = Path(sys.executable).with_name("dask")


def _start(args, log: Path):
    return subprocess.Popen([str(DASK), *args], stdout=log.open("w"), stderr=subprocess.STDOUT)


def _stop(proc) -> None:
    proc.terminate()
    try:
        proc.wait(20)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait(10)


@pytest.mark.slow
def test_campaign_runs_on_a_scheduler_and_its_index_opens_in_a_browser(sim_campaign, tmp_path):
    if not DASK.exists():
        pytest.skip(f"no {DASK}")
    sfile = tmp_path / "scheduler.json"
    sched = _start(["scheduler", "--host", "127.0.0.1", "--port", "0",
                    "--dashboard-address", "127.0.0.1:0", "--scheduler-file", str(sfile)],
                   tmp_path / "scheduler.log")
    worker = None
    try:
        end = time.monotonic() + 60
        while not sfile.exists() and time.monotonic() < end:
            time.sleep(0.2)
        assert sfile.exists(), (tmp_path / "scheduler.log").read_text()
        address = json.loads(sfile.read_text())["address"]
        worker = _start(["worker", "--scheduler-file", str(sfile), "--nthreads", "1",
                         "--nworkers", "1", "--host", "127.0.0.1", "--no-dashboard"],
                        tmp_path / "worker.log")
        camp = write_campaign(tmp_path / "campaign.toml", sim_campaign,
                              flights=("flights/beta0_01.parquet",),
                              steps=("calibrate", "estimate", "map", "report"))
        out = tmp_path / "out"
        done = subprocess.run(
            [sys.executable, "-m", "airwake.cli", "campaign", str(camp), "--scheduler",
             address, "--out", str(out), "--json"], capture_output=True, text=True,
            timeout=600)
        assert done.returncode == 0, done.stderr[-3000:]
        report = json.loads(done.stdout)
        assert report["ran"] == report["tasks"] == 5  # calibrate, estimate, map, report, merge
        assert report["failed"] == []
        # the dashboard whose address the command printed serves the scheduler's page
        assert report["dashboard"] and report["dashboard"] in done.stderr
        with urllib.request.urlopen(report["dashboard"], timeout=30) as r:
            assert r.status == 200
    finally:
        for proc in (worker, sched):
            if proc is not None:
                _stop(proc)

    # the index links every flight's map and report and the merged map; each opens with
    # every figure loaded
    with Browser() as b:
        b.get((out / "index.html").as_uri())
        assert b.run(IMAGES) == [1, 1]  # the merged map's figure on the index
        links = [u for u in b.links() if u.startswith("file:")]
        pages = {Path(urllib.request.url2pathname(u[len("file://"):])) for u in links}
        names = {p.parent.name for p in pages}
        assert names == {"map", "report", *(p.parent.name for p in pages
                                            if p.parent.name.startswith("merge-"))}
        assert any(n.startswith("merge-") for n in names)
        for page in sorted(pages):
            assert page.is_file(), page
            b.get(page.as_uri())
            loaded, total = b.run(IMAGES)
            assert total >= 3 and loaded == total, page
