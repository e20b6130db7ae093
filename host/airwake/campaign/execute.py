"""Run a campaign: plan, skip what the store holds, run the rest on Dask, write results.

    run = run_campaign(campaign, "OUT")                       # LocalCluster, cores workers
    run = run_campaign(campaign, "OUT", scheduler="tcp://host:8786")
    run = run_campaign(campaign, "OUT", client=client)        # a client of your own
    run = run_campaign(campaign, "OUT", workers=0)            # here, one task at a time
    run.records[key]    # every task's record (`runner`); run.summary: summary.parquet

Tasks already in the store (same content address) are not submitted at all, and no
cluster is started when nothing is left to do: a re-run of a finished campaign only
hashes its inputs (remembered by size and mtime) and rewrites the summary. The rest goes
to Dask as one future per task, each given its upstream futures (Dask runs a calibration
before the estimates that read it, and places tasks on free workers). Dask's own
resilience does the rest: when a worker dies, the scheduler re-runs its tasks elsewhere
(from their inputs: a task's result lives in the store, so a re-run whose result was
already committed returns at once); a task that kills `allowed-failures` workers in a row
is reported failed (KilledWorker). A step's own exception never reaches Dask: the task
returns a failed record, its flight's later steps are skipped, the other flights go on.
"""

from __future__ import annotations

import shutil
import sys
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path

from airwake.campaign.display import CampaignDisplay
from airwake.campaign.plan import Plan, build_plan
from airwake.campaign.runner import EVENT_TOPIC, base_record, run_task
from airwake.campaign.store import DigestCache, Store


@dataclass
class CampaignRun:
    plan: Plan
    records: dict  # key -> record
    out: Path
    summary: object  # pandas DataFrame (summary.parquet)
    ran: int  # tasks run now (not found in the store)
    dashboard: str | None = None

    @property
    def failed(self) -> list[dict]:
        return [r for r in self.records.values() if r["status"] != "done"]


def _dask_failure(task, future) -> dict:
    """The record of a task Dask itself gave up on (a worker it killed, a lost input)."""
    import traceback

    try:
        exc, tb = future.exception(), future.traceback()
    except Exception as err:  # noqa: BLE001 — cancelled: the scheduler dropped it
        exc, tb = err, None
    text = "".join(traceback.format_exception(type(exc), exc, tb)) if tb else repr(exc)
    return base_record(task, "failed", error=f"{type(exc).__name__}: {exc}", traceback=text,
                       dask=True)


# Dask runs the ready task of highest priority first: the long model reports before the
# short maps, so the maps fill the end of the run instead of one report holding it up
PRIORITY = {"export": 5, "calibrate": 4, "still_air_net": 4, "estimate": 3, "report": 2,
            "map": 1, "merge": 0}


def _run_dask(client, plan: Plan, todo: list, records: dict, store: Store,
              display: CampaignDisplay, on_record) -> None:
    from distributed import as_completed

    from airwake.campaign.cluster import WarmWorker

    models = sorted({t.args["start"] for t in plan.tasks if t.step == "calibrate"}
                    | {t.args["model"] for t in plan.tasks if "model" in t.args})
    # a step uses a network: a still-air net's training (an anchored estimate reads it)
    # or a wind net's estimate
    nets = any(t.step == "still_air_net" or (t.step == "estimate" and t.args["options"].get(
        "method") == "net") for t in plan.tasks)
    client.register_plugin(WarmWorker(models or ("table52",), torch=nets))
    client.subscribe_topic(EVENT_TOPIC, lambda event: display.started(event[1]["step"]))
    futures = {}
    for t in todo:
        upstream = {role: futures.get(k, records.get(k)) for role, k in t.deps.items()}
        futures[t.key] = client.submit(run_task, t, str(store.root), upstream, key=t.key,
                                       pure=False, priority=PRIORITY[t.step])
    try:
        for fut in as_completed(list(futures.values())):
            task = plan.task(fut.key)
            rec = fut.result() if fut.status == "finished" else _dask_failure(task, fut)
            records[task.key] = rec
            display.finished(rec)
            if on_record is not None:
                on_record(rec)
    finally:
        client.unsubscribe_topic(EVENT_TOPIC)
        for fut in futures.values():
            fut.release()


def _run_here(plan: Plan, todo: list, records: dict, store: Store,
              display: CampaignDisplay, on_record) -> None:
    from airwake.campaign.cluster import single_threaded

    with single_threaded():  # the workers' setting: results do not depend on where they ran
        for t in todo:
            display.started(t.step)
            rec = run_task(t, str(store.root),
                           {role: records[k] for role, k in t.deps.items()})
            records[t.key] = rec
            display.finished(rec)
            if on_record is not None:
                on_record(rec)


def _upstream_failures(plan: Plan, records: dict) -> None:
    """A task Dask failed because its input task failed is the input's failure: say
    'skipped' and name it, as the runner does for a step's own failure."""
    for t in plan.tasks:
        rec = records.get(t.key)
        if rec is None or not rec.get("dask"):
            continue
        for k in t.deps.values():
            up = records.get(k)
            if up is not None and up["status"] != "done":
                records[t.key] = base_record(
                    t, "skipped", error=f"{up['step']} of {up['subject']} did not finish "
                    f"({up['status']}): {up['error']}")
                break


def run_campaign(campaign, out_dir, *, client=None, workers: int | None = None,
                 scheduler: str | None = None, show: bool = True, on_record=None,
                 dashboard_address: str = "127.0.0.1:8787", log=None) -> CampaignRun:
    """Run every task of `campaign` not already in OUT/store (module docstring) and write
    OUT/summary.parquet and OUT/index.html. `workers=0`: in this process, no Dask.
    `on_record(record)` is called as each task finishes (in the caller's thread)."""
    from airwake.campaign.results import write_results

    log = log or sys.stderr
    out = Path(out_dir).resolve()
    store = Store(out / "store")
    digests = DigestCache(store.root / "digests.json")
    plan = build_plan(campaign, digests)
    digests.save()
    records = {t.key: {**store.load(t.key), "cached": True}
               for t in plan.tasks if store.done(t.key)}
    todo = [t for t in plan.tasks if t.key not in records]
    totals, cached = {}, {}
    for t in plan.tasks:
        totals[t.step] = totals.get(t.step, 0) + 1
        if t.key in records:
            cached[t.step] = cached.get(t.step, 0) + 1
    dashboard = None
    if todo:
        if workers == 0 and client is None and not scheduler:
            display = CampaignDisplay(totals, cached, enabled=show)
            try:
                _run_here(plan, todo, records, store, display, on_record)
            finally:
                display.close()
        else:
            from airwake.campaign.cluster import open_client

            ctx = nullcontext(client) if client is not None else open_client(
                workers, scheduler, dashboard_address)
            with ctx as c:
                dashboard = c.dashboard_link
                n = len(c.scheduler_info(n_workers=-1)["workers"])
                print(f"airwake campaign: {len(todo)} of {len(plan.tasks)} tasks to run on "
                      f"{n} Dask worker(s); dashboard {dashboard}", file=log, flush=True)
                display = CampaignDisplay(totals, cached, enabled=show)
                try:
                    _run_dask(c, plan, todo, records, store, display, on_record)
                finally:
                    display.close()
        _upstream_failures(plan, records)
        for tmp in store.root.glob(".*-*"):  # scratch left by killed workers
            if tmp.is_dir():
                shutil.rmtree(tmp, ignore_errors=True)
    summary = write_results(campaign, plan, records, store, out)
    return CampaignRun(plan, records, out, summary, len(todo), dashboard)
