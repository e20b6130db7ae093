"""One task, where it runs (a Dask worker, or this process): the store checked first, the
step run into a scratch directory, the result committed by one rename, failures caught.

    record = run_task(task, store_root, upstream_records)

A record is a JSON-able dict: key, step, subject, status ("done", "failed", "skipped"),
cached, seconds, worker, outputs (names -> paths inside the result directory), summary
(the step's numbers), error and traceback (failed), finished_utc. Only done records are
stored: a failed task runs again on the next run. A task whose upstream did not finish is
"skipped" with the upstream's failure named, so one flight's failure stops only that
flight's later steps.
"""

from __future__ import annotations

import shutil
import socket
import time
import traceback
from pathlib import Path

from airwake.campaign.store import Store, task_key

EVENT_TOPIC = "airwake-campaign"
# the output of an upstream task each input role reads
ROLE_OUTPUT = {"flight": "flight", "model": "model", "wind": "wind", "net": "net"}


def _output_of(role: str) -> str:
    if role.startswith("map "):
        return "cells"
    # a still-air net's flights ("flight 0", "flight 1", ...): each an export's table
    return ROLE_OUTPUT[role.split(" ", 1)[0]]


def _worker_name() -> str:
    try:
        from distributed import get_worker

        return get_worker().address
    except (ImportError, ValueError):
        return f"local:{socket.gethostname()}"


def _announce(task) -> None:
    """Tell the client a task started (its live display counts it as running)."""
    try:
        from distributed import get_worker

        get_worker().log_event(EVENT_TOPIC, {"key": task.key, "step": task.step})
    except (ImportError, ValueError):
        pass


def base_record(task, status: str, **extra) -> dict:
    return {"key": task.key, "step": task.step, "subject": task.subject, "status": status,
            "cached": False, "seconds": 0.0, "worker": "", "outputs": {}, "summary": {},
            "error": "", "traceback": "", **extra}


def inputs_of(task, upstream: dict, store: Store) -> dict:
    """role -> path: the upstream outputs, else the task's own input files."""
    paths = {role: str(store.output(rec, _output_of(role))) for role, rec in upstream.items()}
    for role in ("flight", "model"):
        if role not in paths and role in task.args:
            paths[role] = task.args[role]
    return paths


def result_key(task, upstream: dict) -> tuple[str, dict, list]:
    """(key, the upstream records the step reads, the subjects left out). A merge goes on
    without the flights whose map did not finish: the flights it holds become part of its
    key, so the next run, which retries them, merges again instead of reusing it."""
    if task.step != "merge":
        return task.key, upstream, []
    done = {r: rec for r, rec in upstream.items() if rec["status"] == "done"}
    missing = sorted(rec["subject"] for rec in upstream.values() if rec["status"] != "done")
    if not missing or not done:
        return task.key, upstream, []
    return (task_key("merge", {"of": task.key,
                               "maps": sorted(rec["key"] for rec in done.values())}),
            done, missing)


def run_task(task, store_root: str, upstream: dict) -> dict:
    """Run one task (module docstring); never raises for a step's own failure."""
    from airwake.campaign.steps import STEPS

    store = Store(store_root)
    key, upstream, _ = result_key(task, upstream)
    if store.done(key):  # finished by an earlier run, or by a worker that then died
        return {**store.load(key), "cached": True}
    bad = {role: rec for role, rec in upstream.items() if rec["status"] != "done"}
    if bad:
        role, rec = next(iter(bad.items()))
        return base_record(task, "skipped",
                           error=f"{rec['step']} of {rec['subject']} did not finish "
                           f"({rec['status']}): {rec['error']}")
    _announce(task)
    t0 = time.perf_counter()
    tmp = store.scratch(key)
    try:
        summary, outputs = STEPS[task.step](task, inputs_of(task, upstream, store), tmp)
    except Exception as exc:  # noqa: BLE001 — one flight's failure is reported, not raised
        shutil.rmtree(tmp, ignore_errors=True)
        return base_record(task, "failed", seconds=time.perf_counter() - t0,
                           worker=_worker_name(), error=f"{type(exc).__name__}: {exc}",
                           traceback=traceback.format_exc())
    record = base_record(task, "done", key=key, seconds=time.perf_counter() - t0,
                         worker=_worker_name(), outputs=outputs, summary=summary,
                         finished_utc=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()))
    store.commit(key, Path(tmp), record)
    return record
