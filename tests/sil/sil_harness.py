"""SIL flights for the tests: run once per pytest session, shared by xdist workers.

A flight costs ~15 s (truth world, daemon start, stepping, export), so each named flight
runs once: the first worker to ask runs it under a file lock into a shared directory;
the others wait and read it. What a flight leaves there:

    DIR/rec/             the recording (+ rec/sil/run.json, rec/sil/frames.npz)
    DIR/flight.parquet   `airwake export` of it
    DIR/truth.npz        the truth world at 1 kHz + the VN200 samples (for scoring)
    DIR/extra.json       whatever the flight's maker adds (e.g. the kill time)
"""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import traceback
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
BAD_KINDS = ("crc_error", "cobs_error", "unknown_id", "def_mismatch", "oversize")


def shared_dir(tmp_path_factory) -> Path:
    """A directory every xdist worker of this session sees (the session's own otherwise)."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def shared_flight(tmp_path_factory, name: str, make) -> Path:
    """Run `make(dir)` once per session (under a lock); later callers get the same dir."""
    root = shared_dir(tmp_path_factory)
    d = root / f"sil-{name}"
    with open(root / f"sil-{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if (d / "failed").exists():
            raise RuntimeError(f"flight {name} failed in another worker:\n"
                               + (d / "failed").read_text())
        if not (d / "done").exists():
            shutil.rmtree(d, ignore_errors=True)
            d.mkdir(parents=True)
            try:
                make(d)
            except BaseException:
                (d / "failed").write_text(traceback.format_exc())
                raise
            (d / "done").write_text("ok")
    return d


def save_truth(run, path: Path) -> None:
    """What the tests score against: the world's truth at its rate and the VN200 samples."""
    w = run.world
    tr, imu = w.truth, w.imu_truth
    vn = w.samples["vn200"]
    arrays = {
        "t_s": tr.t_s, "euler_rad": tr.euler_rad, "rates_rad_s": tr.rates_body_rad_s,
        "imu_specific_force_m_s2": imu.specific_force_body_m_s2,
        "rotor_speed_rad_s": tr.rotor_speed_rad_s, "applied_rad": w.applied_rad,
        "vn_t_s": vn.t_s, "vn_time_startup_ns": vn.time_startup_ns.astype(np.int64),
        "vn_ypr_deg": vn.ypr_deg, "vn_rates_rad_s": vn.rates_body_rad_s,
        "vn_accel_m_s2": vn.accel_body_m_s2,
    }
    if "marker_pos_tracker_m" in run.feeds.truth:
        from hil_sim.boards.feeds import marker_in_tracker

        pos, quat = marker_in_tracker(tr, run.rig)
        arrays["marker_pos_tracker_m"] = pos
        arrays["marker_quat_tracker"] = quat
    np.savez(path, **arrays)


def run_flight(d: Path, scenario, *, duration_s: float, rig=None, export: bool = True,
               during=None, **kwargs) -> dict:
    """A SIL flight into d/rec (+ truth, export). `during(run)` is called after each step
    and may return True to stop stepping early (crash tests)."""
    from airwake.record.export import export_recording
    from airwake.record.flight_table import write_flight_table
    from airwake.record.reader import open_recording

    from hil_sim.boards.sil import SilRun

    run = SilRun(scenario, out=d / "rec", duration_s=duration_s, rig=rig, **kwargs)
    extra: dict = {}
    try:
        run.start()
        while not run.done:
            run.step()
            if during is not None and during(run, extra):
                break
        result = run.finish()
    except BaseException:
        run._abort()
        raise
    save_truth(run, d / "truth.npz")
    extra["host_offset_ns"] = run.host_offset_ns
    (d / "extra.json").write_text(json.dumps(extra))
    if export:
        built = export_recording(open_recording(d / "rec"))
        write_flight_table(built.df, d / "flight.parquet", built.metadata)
    return result.summary


def summary(d: Path) -> dict:
    return json.loads((d / "rec" / "sil" / "run.json").read_text())


def frame_logs(d: Path) -> dict[str, np.ndarray]:
    with np.load(d / "rec" / "sil" / "frames.npz") as z:
        return {k: z[k] for k in z.files}


def as_set(rows: np.ndarray, cols=slice(1, 5)) -> set[tuple[int, ...]]:
    return {tuple(int(v) for v in r) for r in rows[:, cols]}


def delivered_frames(logs: dict) -> set:
    """Frames delivered intact on the host ptys (the rover's arrive through the base)."""
    return set().union(*(as_set(logs[f"{b}_delivered"]) for b in ("losa", "marker", "base")
                         if f"{b}_delivered" in logs))


def sent_frames(logs: dict) -> tuple[set, set]:
    """(every frame a board sent, those with a byte or delimiter impaired on a link)."""
    sent, touched = set(), set()
    for key, rows in logs.items():
        if key.endswith("_sent"):
            sent |= as_set(rows)
            touched |= as_set(rows[rows[:, 5] == 1])
    return sent, touched


def sim_time(table_t_s: np.ndarray, metadata: dict, extra: dict) -> np.ndarray:
    """Flight-table time -> simulator time: the stepped daemon's host clock is
    host_offset_ns + simulator time, and t_s counts from the recording's start."""
    return table_t_s + (metadata["t0_monotonic_ns"] - extra["host_offset_ns"]) / 1e9


def load_export(d: Path):
    from airwake.record.flight_table import load_flight_table

    ft = load_flight_table(d / "flight.parquet")
    extra = json.loads((d / "extra.json").read_text())
    return ft.df, ft.metadata, extra
