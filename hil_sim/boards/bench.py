"""SIL speed figures (called from `hil_sim/bench.py`, section "sim").

`sil_stepped_realtime_factor`: simulated seconds per wall second of a stepped SIL flight
of `still_air_calibration` with all four native boards and the real daemon recording
(the stepping loop only: the truth world is computed before, see `sim_realtime_factor`).
Beside it, the CPU each part spent per simulated second — the load the same flight
puts on the machine in real time: `sil_daemon_cpu_s_per_sim_s` (the daemon at the
boards' full rates in SIL; compare `daemon_cpu_fraction` with fake boards),
`sil_simulator_cpu_s_per_sim_s` (feeds, LOSA optics, links, channel),
`sil_boards_cpu_s_per_sim_s` (the four firmware processes), and
`sil_waiting_for_daemon_fraction` (wall time spent waiting for the daemon in lockstep).
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path


def measure(duration_s: float, scenario_name: str = "still_air_calibration",
            boards: tuple[str, ...] | None = None) -> dict:
    from hil_sim.boards.rig import rig_for
    from hil_sim.boards.sil import SilRun
    from hil_sim.world.scenario import load_scenario

    scenario = load_scenario(scenario_name)
    tmp = Path(tempfile.mkdtemp(prefix="airwake-sil-bench-"))
    try:
        run = SilRun(scenario, out=tmp / "rec", duration_s=duration_s,
                     rig=rig_for(scenario, boards))
        s = run.run().summary
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    t, cpu = s["timing"], s["cpu"]
    sim = s["duration_s"]
    return {
        "sil_stepped_realtime_factor": t["realtime_factor"],
        "sil_duration_s": sim,
        "sil_boards": ",".join(s["boards"]),
        "sil_flight_wall_s": t["flight_wall_s"],
        "sil_daemon_cpu_s_per_sim_s": round((cpu["daemon_s"] or 0.0) / sim, 3),
        "sil_simulator_cpu_s_per_sim_s": round(cpu["simulator_s"] / sim, 3),
        "sil_boards_cpu_s_per_sim_s": round(sum(v or 0.0 for v in cpu["boards_s"].values())
                                            / sim, 3),
        "sil_waiting_for_daemon_fraction": round(t["waiting_for_daemon_s"]
                                                 / t["flight_wall_s"], 3),
        "sil_setup_s": t["setup_s"],
    }


def run(quick: bool) -> dict:
    return measure(5.0 if quick else 30.0)
