"""A small simulated campaign shared by the campaign tests: 6 flights of 12 s over beta 0
and 15, a 30 s still-air calibration flight and 20 s of still-air cruise legs, flown once
per session by `airwake sim campaign` on a 2-worker LocalCluster."""

import json
import subprocess
import sys

import pytest


@pytest.fixture(scope="session")
def sim_campaign(shared_path):
    def make(path):
        done = subprocess.run(
            [sys.executable, "-m", "airwake.cli", "sim", "campaign", "--out", str(path),
             "--flights", "6", "--betas", "0,15", "--seed", "11", "--duration", "12",
             "--calibration-s", "30", "--still-air-s", "20", "--workers", "2", "--json"],
            capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, done.stderr[-3000:]
        summary = json.loads(done.stdout)
        assert len(summary["flights"]) == 6 and len(summary["calibrations"]) == 1
        assert len(summary["still_air"]) == 1

    return shared_path("sim_campaign", make)
