"""The SIL flights shared by the tests (helpers: sil_harness.py).

- `clean_flight`: 12 s of still_air_calibration (hover, then the lateral chirp) with all
  four boards, stepped, no faults.
- `fault_flight`: the same flight from a scenario file with a [faults] table: byte loss
  and bit flips on the LOSA link, the marker's link throttled to 57600 baud, loss and
  flips on the rover's XBee link to the base, the base's pty unplugged for 1 s, the
  LOSA link stalled for 0.5 s, the rover reset; the boards are the ASan/UBSan builds.
- `crash_flight`: rover + base, wall-paced (real time, the daemon on its own clock); the
  daemon is killed with SIGKILL after 4-4.25 s (a random moment of its flush cycle).
"""

from __future__ import annotations

import random
import signal
import time

import pytest
from sil_harness import run_flight, shared_flight

CLEAN_S = 12.0
FAULT_S = 12.0
CRASH_KILL_S = 4.0

# The SIL tests' flight: still_air_calibration's helicopter, site and sensors with a
# hover and the lateral chirp (the marker stays in the tracker's view; the calibration
# flight's own script starts with 9 m legs across the hall).
CLEAN_SCENARIO = """
extends = "still_air_calibration"
description = "SIL test flight: hover, then the lateral chirp"

# the boards and the daemon: plumbing, on the effect truth (docs/truth-world.md)
[helicopter]
model = "effects"
pilot = "full_state"

[[pilot.segments]]
type = "hover"
duration_s = 4.0

[[pilot.segments]]
type = "chirp"
channel = "lat"
amplitude_deg = 0.7
f0_hz = 0.3
f1_hz = 4.0
duration_s = 20.0
"""

FAULT_SCENARIO = CLEAN_SCENARIO.replace("SIL test flight: hover, then the lateral chirp",
                                        "SIL fault test: impaired links, an unplug, a stall, "
                                        "a reset") + """

[faults.losa]
byte_loss_probability = 0.002
bit_flip_probability = 0.0002

[faults.marker]
throttle_baud = 57600

[faults.rover]
byte_loss_probability = 0.001
bit_flip_probability = 0.0001

[[faults.unplugs]]
board = "base"
at_s = 4.0
duration_s = 1.0

[[faults.stalls]]
board = "losa"
at_s = 7.0
duration_s = 0.5

[[faults.resets]]
board = "rover"
at_s = 6.0
"""


@pytest.fixture(scope="session")
def clean_flight(tmp_path_factory):
    def make(d):
        from hil_sim.world.scenario import load_scenario

        path = d / "clean.toml"
        path.write_text(CLEAN_SCENARIO)
        run_flight(d, load_scenario(path), duration_s=CLEAN_S, log_frames=True)

    return shared_flight(tmp_path_factory, "clean", make)


@pytest.fixture(scope="session")
def fault_flight(tmp_path_factory):
    def make(d):
        from hil_sim.world.scenario import load_scenario

        path = d / "faults.toml"
        path.write_text(FAULT_SCENARIO)
        # the ASan/UBSan builds: the base's forwarder parses the corrupted XBee bytes
        run_flight(d, load_scenario(path), duration_s=FAULT_S, log_frames=True,
                   flavour="asan")

    return shared_flight(tmp_path_factory, "faults", make)


@pytest.fixture(scope="session")
def crash_flight(tmp_path_factory):
    # at a random moment in the writer's flush cycle (record.recording.FLUSH_S)
    kill_at_s = CRASH_KILL_S + random.uniform(0.0, 0.25)

    def kill(run, extra):
        if run.t_us >= kill_at_s * 1e6 and "kill_ns" not in extra:
            extra["kill_ns"] = run.kill_daemon(signal.SIGKILL)
            extra["kill_sim_s"] = run.t_us / 1e6
            extra["delivered"] = {b: p.log for b, p in run.ptys.items()}
            for b, p in run.ptys.items():
                (run.out.parent / f"delivered-{b}.bin").write_bytes(bytes(p.keep))
            time.sleep(0.2)
        return run.t_us >= (CRASH_KILL_S + 1.0) * 1e6

    def make(d):
        from hil_sim.boards.rig import rig_for
        from hil_sim.world.scenario import load_scenario

        path = d / "clean.toml"
        path.write_text(CLEAN_SCENARIO)
        sc = load_scenario(path)
        run_flight(d, sc, duration_s=CRASH_KILL_S + 2.0, rig=rig_for(sc, ("rover", "base")),
                   export=False, during=kill, keep_delivered=True, mode="wall")

    return shared_flight(tmp_path_factory, "crash", make)
