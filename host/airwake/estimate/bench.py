"""`airwake bench` section "estimate": the wind particle filter's speed, memory and
accuracy on a model-generated flight (Table 5.2 model, slowly varying wind + gusts,
seed-like noise).

The filter runs in a child process pinned to one thread (OMP/OpenBLAS/MKL/numba = 1).
apf_realtime_factor = seconds of 150 Hz flight per wall second of the filter run with
2000 particles (apf_realtime_factor_cpu: per CPU second, which a busy shared machine
does not distort). apf_peak_rss_mb = peak resident memory of the child during the
filter run (the mark is reset after a warm-up that imports everything and loads the
compiled model kernels); apf_process_peak_rss_mb = the whole child incl. imports and,
when the kernel cache is cold, numba compilation (apf_setup_s). Both from VmHWM:
getrusage's ru_maxrss keeps the parent's peak across exec. Accuracy: error
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


def _vm_hwm_mb() -> float | None:
    try:
        for line in open("/proc/self/status"):
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def _reset_hwm() -> bool:
    """Reset the peak-RSS mark (Linux >= 4.0: write 5 to /proc/self/clear_refs)."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


def _child(path: str, particles: int) -> None:
    """Run in the child: warm up (imports, compiled-kernel load), reset the peak-RSS
    mark, filter the flight, print timing, memory and the score as JSON."""
    import resource
    import time

    from airwake.estimate import estimate_wind, score_wind
    from airwake.record.flight_table import load_flight_table

    t0 = time.perf_counter()
    ft = load_flight_table(path, required=())
    estimate_wind(ft, "table52", n_particles=particles, seed=0, steps=3)  # warm-up
    setup = time.perf_counter() - t0
    setup_peak = _vm_hwm_mb()  # (ru_maxrss would carry the parent's peak over exec)
    reset = _reset_hwm()
    c0 = time.process_time()
    est = estimate_wind(ft, "table52", n_particles=particles, seed=0)
    cpu = time.process_time() - c0
    span = float(ft.df["t_s"].iloc[-1] - ft.df["t_s"].iloc[0])
    score = score_wind(est.df, ft.df)
    print(json.dumps({
        "flight_s": span, "filter_s": est.seconds, "cpu_s": cpu, "setup_s": setup,
        "run_peak_rss_mb": _vm_hwm_mb() if reset else None,
        "process_peak_rss_mb": max(setup_peak or 0.0, _vm_hwm_mb() or 0.0) or (
            resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0),
        "score": score, "mean_ess": float(est.df["ess"].mean())}))


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
        "apf_realtime_factor_cpu": res["flight_s"] / res["cpu_s"],
        "apf_peak_rss_mb": res["run_peak_rss_mb"] or res["process_peak_rss_mb"],
        "apf_process_peak_rss_mb": res["process_peak_rss_mb"],
        "apf_setup_s": res["setup_s"],
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
