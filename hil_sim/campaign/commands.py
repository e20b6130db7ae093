"""`airwake sim campaign --out DIR --flights N --betas 0,15,30 --seed S [--truth MODEL]`."""

from __future__ import annotations

import argparse
import json


def _betas(text: str) -> tuple[float, ...]:
    try:
        values = tuple(float(x) for x in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--betas {text!r}: expected comma-separated degrees, e.g. 0,15,30") from None
    return values


def _handle(args: argparse.Namespace) -> int:
    from hil_sim.campaign.fly import generate

    s = generate(args.out, args.flights, args.betas, args.seed, truth=args.truth,
                 helicopters=args.helicopters, duration_s=args.duration,
                 calibration_s=args.calibration_s, still_air_s=args.still_air_s,
                 speed_m_s=args.speed,
                 workers=args.workers, progress=not args.json)
    if args.json:
        print(json.dumps(s, indent=2))
    else:
        flown = sum(f["duration_s"] for f in s["flights"])
        print(f"{s['campaign']}: {len(s['flights'])} flights, {len(s['calibrations'])} "
              f"calibration and {len(s['still_air'])} still-air cruise flight(s), "
              f"{flown:.0f} s flown ({s['sim_seconds']:.0f} s of computing); run it with "
              f"`airwake campaign {s['campaign']}`")
    return 0


def register_campaign(sub) -> None:
    """`sim campaign` under the `sim` group."""
    from hil_sim.campaign.plan import STILL_AIR_S, TRUTH_MODELS

    p = sub.add_parser(
        "campaign", help="fly a simulated campaign and write DIR/campaign.toml",
        description="Fly N ship-airwake flights spread over the relative wind headings "
        "(lateral sweeps at different stations and heights so the merged maps cover the "
        "deck area), one still-air calibration flight and one still-air cruise flight (for "
        "its still-air wind net) per helicopter in the truth world, and write their flight "
        "tables (truth columns included) and DIR/campaign.toml for `airwake campaign` "
        "(docs/campaigns.md).")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--flights", type=int, required=True, metavar="N", help="ship flights")
    p.add_argument("--betas", type=_betas, default=(0.0,), metavar="B1,B2,...",
                   help="relative wind headings, deg (default 0)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="campaign seed (0)")
    p.add_argument("--truth", choices=TRUTH_MODELS, default=None,
                   help="the truth helicopter (scenario key [helicopter] model; default: "
                   "the scenario's default)")
    p.add_argument("--helicopters", type=int, default=1, metavar="K",
                   help="helicopters (flights shared out in turn; one calibration flight "
                   "each; default 1)")
    p.add_argument("--duration", type=float, default=None, metavar="S",
                   help="cut every flight at S seconds (default: the whole plan, ~1 min per "
                   "station)")
    p.add_argument("--calibration-s", type=float, default=None, metavar="S",
                   help="length of the calibration flights (default: the whole scenario)")
    p.add_argument("--still-air-s", type=float, default=STILL_AIR_S, metavar="S",
                   help="length of each helicopter's still-air cruise flight, which its "
                   "still-air wind net learns from beside the calibration flight (default "
                   f"{STILL_AIR_S:g}; 0 = none: the campaign estimates with the model's "
                   "smoother alone)")
    p.add_argument("--speed", type=float, default=0.6, metavar="M_S",
                   help="sweep speed (peak of each leg, 0.6 m/s)")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="fly on a LocalCluster of N workers (default: one per core); 0 = "
                   "one after another in this process")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=_handle)
