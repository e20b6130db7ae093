"""`airwake bench` section "estimate": the wind particle filter's speed, memory and
accuracy on a model-generated flight (Table 5.2 model, slowly varying wind + gusts,
seed-like noise).

The filter runs in a child process pinned to one thread (OMP/OpenBLAS/MKL/numba = 1):
apf_realtime_factor = seconds of 150 Hz flight per wall second with 2000 particles,
apf_peak_rss_mb = the child's peak resident memory (getrusage). Accuracy: error
(estimate - truth) std per component after 2 s, apf_error_std_*, next to Table 5.3.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

SECTION = "estimate"

BENCH_WIND = dict(mean=(2.0, -1.0, 0.3, 0.1, -0.05, 0.08),
                  amplitude=(1.5, 1.5, 0.5, 0.15, 0.1, 0.1),
                  gust_std=(0.5, 0.5, 0.2, 0.05, 0.05, 0.05), gust_tau_s=3.0)


def bench_flight(quick: bool):
    from airwake.calibrate.bench import cached_flight
    from airwake.calibrate.synthetic import WindProfile

    base = WindProfile.slowly_varying(BENCH_WIND["mean"], BENCH_WIND["amplitude"])
    wind = WindProfile(base.mean, base.amplitude, base.period_s, base.phase_rad,
                       BENCH_WIND["gust_std"], BENCH_WIND["gust_tau_s"])
    return cached_flight("apf5" if quick else "apf30", duration_s=5.0 if quick else 30.0,
                         wind=wind, seed=11)


def _child(path: str, particles: int) -> None:
    """Run in the child: filter the flight, print timing, memory and the score."""
    import resource
    import time

    from airwake.estimate import estimate_wind, score_wind
    from airwake.record.flight_table import load_flight_table

    ft = load_flight_table(path, required=())
    t0 = time.perf_counter()
    est = estimate_wind(ft, "table52", n_particles=particles, seed=0)
    wall = time.perf_counter() - t0
    span = float(ft.df["t_s"].iloc[-1] - ft.df["t_s"].iloc[0])
    score = score_wind(est.df, ft.df)
    rss_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"wall_s": wall, "flight_s": span, "filter_s": est.seconds,
                      "peak_rss_mb": rss_kb / 1024.0, "score": score,
                      "mean_ess": float(est.df["ess"].mean())}))


def run(quick: bool = False) -> dict:
    ft, gen_s = bench_flight(quick)
    particles = 2000
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1", NUMBA_NUM_THREADS="1")
    code = f"from airwake.estimate.bench import _child; _child({str(ft.path)!r}, {particles})"
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=False)
    if proc.returncode != 0:
        raise RuntimeError(f"filter child failed: {proc.stderr.strip()[-500:]}")
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    out = {
        "apf_realtime_factor": res["flight_s"] / res["filter_s"],
        "apf_realtime_factor_incl_setup": res["flight_s"] / res["wall_s"],
        "apf_peak_rss_mb": res["peak_rss_mb"],
        "apf_particles": particles,
        "apf_flight_s": res["flight_s"],
        "apf_mean_ess": res["mean_ess"],
        "apf_flight_generate_s": gen_s,
    }
    for name, c in res["score"]["components"].items():
        short = name.replace("wind_", "").split("_")[0]
        out[f"apf_error_std_{short}"] = c["error_std"]
        out[f"apf_error_mean_{short}"] = c["error_mean"]
        out[f"apf_table53_std_{short}"] = c["table_5_3_std"]
    return out
