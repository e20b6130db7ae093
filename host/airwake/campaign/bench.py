"""Campaign figures for `airwake bench` (docs/campaigns.md), from two simulated campaigns
(`airwake sim campaign`, with a still-air calibration flight each).

The speed-up: 8 flights of 60 s over beta 0 and 15, every step (calibrate, the still-air
wind net on the calibration flight and 100 s of still-air cruise legs, the estimate
anchored on its mean flow, map, model report); quick: 8 flights of 30 s, a 60 s
calibration flight fitted on 8 windows, no report. Run from an empty store on a
LocalCluster of 2 workers, then of 1 (the wall time a user waits: cluster start and
worker warm-up included), then again:

    campaign_run_1_worker_s, campaign_run_2_workers_s, campaign_speedup_2_workers
        (target >= 1.7 on 2 cores)
    campaign_concurrency_2_workers   the 2-worker run's task seconds over its wall time:
        2 when both workers were busy throughout (start-up, the calibration every estimate
        waits for and the last task's tail lower it). On a shared machine the wall
        speed-up also measures the cores other programs took; this does not
    campaign_rerun_s, campaign_rerun_fraction   the finished campaign run again (every
        result in the store) and its share of the 2-worker run (target < 0.05)
    campaign_<step>_s_per_task    seconds per task of each step (mean), and
    campaign_flight_s             their sum over one flight's steps (estimate, map, report)
    campaign_worker_peak_rss_mb   the largest worker's peak memory in the 2-worker run

The merged map (not in quick): 12 flights at beta 0 with the full sweep plans (every
station of the deck area), calibrate, still-air net, estimate (anchored) and map on 2
workers:

    campaign_merged_deck_coverage, campaign_merged_deck_cells_covered   the deck-area
        cells with >= 2 s (target >= 0.8)
    campaign_merged_field_rms_<u|v|w>_m_s   the merged map against the simulator's field
        at the cell centres over those cells (target <= 0.3 m/s)
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

SECTION = "campaign"


def _simulate(out: Path, args: list, steps: dict | None = None) -> Path:
    """`airwake sim campaign` into `out`; `steps` replaces parts of its [steps] table."""
    done = subprocess.run([sys.executable, "-m", "airwake.cli", "sim", "campaign", "--out",
                           str(out), *args, "--json"], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"airwake sim campaign failed: {done.stderr[-2000:]}")
    path = out / "campaign.toml"
    if steps:
        import tomllib

        import tomli_w

        table = tomllib.loads(path.read_text())
        for key, value in steps.items():
            if isinstance(value, dict):
                table["steps"].setdefault(key, {}).update(value)
            else:
                table["steps"][key] = value
        path.write_text(tomli_w.dumps(table))
    return path


def _peak_rss_mb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _timed(campaign, out: Path, workers: int):
    """(run, wall seconds with the cluster's start and close, the workers' peak RSS)."""
    from airwake.campaign.cluster import open_client
    from airwake.campaign.execute import run_campaign

    t0 = time.perf_counter()
    with open_client(workers, dashboard_address="127.0.0.1:0") as client:
        run = run_campaign(campaign, out, client=client, show=False)
        rss = max(client.run(_peak_rss_mb).values())
    return run, time.perf_counter() - t0, rss


def run(quick: bool) -> dict:
    from airwake.campaign.execute import run_campaign
    from airwake.campaign.spec import load_campaign

    out: dict = {}
    with tempfile.TemporaryDirectory(prefix="airwake-campaign-bench-") as tmp:
        tmp = Path(tmp)
        args = ["--flights", "8", "--betas", "0,15", "--seed", "21", "--duration",
                "30" if quick else "60"]
        steps = None
        if quick:
            args += ["--calibration-s", "60"]
            steps = {"run": ["calibrate", "still_air_net", "estimate", "map"],
                     "calibrate": {"max_windows": 8}}
        campaign = load_campaign(_simulate(tmp / "speed", args, steps))
        two, t2, rss = _timed(campaign, tmp / "two", 2)
        one, t1, _ = _timed(campaign, tmp / "one", 1)
        t0 = time.perf_counter()  # as a user re-runs it: no cluster starts for nothing
        again = run_campaign(campaign, tmp / "two", workers=2, show=False)
        t_again = time.perf_counter() - t0
        if again.ran:
            raise RuntimeError(f"the re-run ran {again.ran} tasks instead of none")
        per_step: dict[str, list] = {}
        for rec in two.records.values():
            if rec["status"] == "done":
                per_step.setdefault(rec["step"], []).append(rec["seconds"])
        out.update({
            "campaign_flights": len(campaign.flights), "campaign_run_1_worker_s": t1,
            "campaign_run_2_workers_s": t2, "campaign_speedup_2_workers": t1 / t2,
            "campaign_concurrency_2_workers": sum(map(sum, per_step.values())) / t2,
            "campaign_rerun_s": t_again, "campaign_rerun_fraction": t_again / t2,
            "campaign_worker_peak_rss_mb": rss,
            "campaign_failed_tasks": len(two.failed) + len(one.failed)})
        for step, secs in sorted(per_step.items()):
            out[f"campaign_{step}_s_per_task"] = sum(secs) / len(secs)
        out["campaign_flight_s"] = sum(out.get(f"campaign_{s}_s_per_task", 0.0)
                                       for s in ("estimate", "map", "report"))
        if quick:
            return out

        import pandas as pd

        campaign = load_campaign(_simulate(
            tmp / "cover", ["--flights", "12", "--betas", "0", "--seed", "22"],
            {"run": ["calibrate", "still_air_net", "estimate", "map"]}))
        cover = run_campaign(campaign, tmp / "cover-out", workers=2, show=False)
        m = pd.read_parquet(cover.out / "merged.parquet").iloc[0]
        out["campaign_merged_flights"] = int(m["flights"])
        out["campaign_merged_deck_coverage"] = float(m["deck_coverage"])
        out["campaign_merged_deck_cells_covered"] = int(m["deck_cells_covered"])
        for c in ("u", "v", "w"):
            key = f"field_rms_deck_{c}_m_s"
            if key in m:
                out[f"campaign_merged_field_rms_{c}_m_s"] = float(m[key])
    return out
