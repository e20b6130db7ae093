"""`airwake campaign CAMPAIGN.toml [--workers N] [--scheduler tcp://HOST:PORT] [--out DIR]`."""

from __future__ import annotations

import argparse
import json
import sys


def _handle(args: argparse.Namespace) -> int:
    from pathlib import Path

    from airwake.campaign.errors import CampaignError
    from airwake.campaign.execute import run_campaign
    from airwake.campaign.spec import load_campaign

    if args.workers is not None and args.workers < 0:
        raise CampaignError(f"--workers {args.workers}: must be >= 0")
    if args.workers is not None and args.scheduler:
        raise CampaignError("--workers and --scheduler: give one (an existing cluster has "
                            "its own workers)")
    campaign = load_campaign(args.campaign)
    out = Path(args.out) if args.out else campaign.path.parent / "results"
    if out.exists() and not out.is_dir():
        raise CampaignError(f"--out {out}: exists and is not a directory")
    out.mkdir(parents=True, exist_ok=True)
    run = run_campaign(campaign, out, workers=args.workers, scheduler=args.scheduler,
                       show=not args.quiet and not args.json)
    table = run.summary
    failed = table[table["status"] != "done"] if len(table) else table
    report = {"out": str(out), "tasks": len(run.plan.tasks), "ran": run.ran,
              "from_store": len(run.plan.tasks) - run.ran, "dashboard": run.dashboard,
              "flights": int((table["role"] == "flight").sum()) if len(table) else 0,
              "failed": [{"flight": r["flight"], "step": r["failed_step"], "error": r["error"]}
                         for _, r in failed.iterrows()],
              "summary": str(out / "summary.parquet"), "index": str(out / "index.html")}
    merged = run.out / "merged.parquet"
    if merged.is_file():
        import pandas as pd

        report["merged"] = pd.read_parquet(merged).to_dict(orient="records")
    if args.json:
        print(json.dumps(report, indent=2, default=str))
    else:
        print(f"campaign {campaign.name}: {report['flights']} flights, {run.ran} of "
              f"{report['tasks']} tasks run ({report['from_store']} found in {out / 'store'})")
        for m in report.get("merged", []):
            print(f"  beta {m['beta_deg']:g} deg: {m['flights']} flights, deck area covered "
                  f"{100 * m['deck_coverage']:.0f} % ({m['deck_cells_covered']}/"
                  f"{m['deck_cells']} cells)")
        for f in report["failed"]:
            print(f"  FAILED {f['flight']} at {f['step']}: {f['error']}", file=sys.stderr)
        print(f"wrote {report['index']} and {report['summary']}")
    return 1 if report["failed"] else 0


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "campaign", help="many flights on Dask: calibrate, estimate, map, report, merge",
        description="Run a campaign file's flights through export, calibrate, the "
        "still-air wind net, wind estimate (anchored on that net's mean flow), wind map and "
        "model report on dask.distributed (a LocalCluster, or an "
        "existing cluster with --scheduler), merge the maps into one airwake map per "
        "relative wind heading and write DIR/summary.parquet and DIR/index.html. Results "
        "are content-addressed: a re-run skips what is done and an interrupted run resumes "
        "(docs/campaigns.md). Exit status 1 when a flight failed (its error is in the "
        "summary), 2 for a bad campaign file.")
    p.add_argument("campaign", metavar="CAMPAIGN.toml", help="campaign file")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="LocalCluster worker processes, one thread each (default: one per "
                   "core); 0 = run every task in this process, one after another (debugging)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="an existing Dask scheduler (its workers need airwake and the "
                   "campaign's files at the same paths)")
    p.add_argument("--out", metavar="DIR",
                   help="output directory and result store (default: results/ beside the "
                   "campaign file)")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.add_argument("--quiet", action="store_true", help="no progress display")
    p.set_defaults(func=_handle)
