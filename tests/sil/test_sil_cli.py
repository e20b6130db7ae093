"""`airwake sim run`: clear errors, and one short flight through the command."""

from __future__ import annotations

import json
import subprocess
import sys

from sil_harness import REPO


def airwake(*args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "airwake.cli", *args], cwd=REPO,
                          capture_output=True, text=True, timeout=timeout)


def test_sim_run_refuses_a_recording_directory_that_is_not_empty(tmp_path):
    # a recording is never written over another one
    (tmp_path / "rec").mkdir()
    (tmp_path / "rec" / "old.mcap").write_bytes(b"x")
    r = airwake("sim", "run", "--scenario", "ship_airwake_b0", "--duration", "1",
                "--out", str(tmp_path / "rec"))
    assert r.returncode == 2
    assert "exists and is not an empty directory" in r.stderr and "rec" in r.stderr
    assert r.stderr.count("\n") == 1  # one line, no traceback


def test_sim_run_names_an_unknown_or_incomplete_board_set(tmp_path):
    r = airwake("sim", "run", "--scenario", "ship_airwake_b0", "--boards", "rover,plane",
                "--out", str(tmp_path / "rec"))
    assert r.returncode == 2 and "plane" in r.stderr and "losa, marker, rover, base" in r.stderr
    r = airwake("sim", "run", "--scenario", "ship_airwake_b0", "--boards", "base",
                "--out", str(tmp_path / "rec2"))
    assert r.returncode == 2 and "needs the rover" in r.stderr


def test_sim_run_names_a_fault_event_on_a_board_not_flying(tmp_path):
    # an unplug of the LOSA in a ship flight (rover + base) is a mistake in the file
    sc = tmp_path / "bad.toml"
    sc.write_text('extends = "ship_airwake_b0"\n[[faults.unplugs]]\nboard = "losa"\n'
                  'at_s = 1.0\nduration_s = 0.5\n')
    r = airwake("sim", "run", "--scenario", str(sc), "--duration", "2", "--out",
                str(tmp_path / "rec"))
    assert r.returncode == 2 and "faults.unplugs" in r.stderr and "'losa'" in r.stderr
    assert not (tmp_path / "rec").exists() or not any((tmp_path / "rec").glob("*.mcap"))


def test_sim_run_flies_and_reports_the_recording_and_link_health(tmp_path):
    # the command end to end: recording, real-time factor, the daemon's link health
    rec = tmp_path / "rec"
    r = airwake("sim", "run", "--scenario", "still_air_calibration", "--duration", "2",
                "--boards", "rover,base", "--out", str(rec))
    assert r.returncode == 0, r.stderr[-2000:]
    assert f"recording: {rec}" in r.stdout and "real-time factor" in r.stdout
    assert "port base:" in r.stdout and "board rover:" in r.stdout and "ins 150" in r.stdout
    assert "sil " in r.stderr  # progress
    s = json.loads((rec / "sil" / "run.json").read_text())
    assert s["daemon_exit"] == 0 and s["boards"] == ["rover", "base"]
    # the daemon read nothing but its ports in mid-flight (a lazy import, 413 kB of
    # numpy.ma on its first clock fit, had met the lockstep's byte count early all flight)
    assert s["lockstep"] == {"other_read_bytes": 0, "other_reads": 0}
    assert not (rec / "ports").exists()
    info = airwake("recording", "info", str(rec), "--json")
    assert info.returncode == 0 and "/rover/ins" in info.stdout
    # stepped is deterministic: the same flight again gives the same frames, bit for bit
    # (the host's own stamps differ: its clock starts at the wall time of the run)
    import numpy as np
    from airwake.record.reader import open_recording

    from hil_sim.boards.rig import rig_for
    from hil_sim.boards.sil import SilRun
    from hil_sim.world.scenario import load_scenario

    sc = load_scenario("still_air_calibration")
    SilRun(sc, out=tmp_path / "again", duration_s=2.0, rig=rig_for(sc, ("rover", "base"))).run()
    a, b = open_recording(rec), open_recording(tmp_path / "again")
    for topic in ("/rover/ins", "/rover/rotor_speed", "/rover/tail_servo", "/base/pilot_inputs"):
        ra, rb = a.table(topic).rows, b.table(topic).rows
        assert len(ra) > 90 and ra.tobytes() == rb.tobytes(), topic
    assert np.array_equal(a.table("/rover/heartbeat").rows["boot_count"],
                          b.table("/rover/heartbeat").rows["boot_count"])
