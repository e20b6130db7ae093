"""`airwake bench` section "estimate": the wind estimators on a SIL ship flight.

The flight is what a user gets: the truth world's `ship_airwake_b15` (seed 101, one no
test uses) flown by the independent blade-element helicopter and the crossover pilot
(`TRUTH`), through the native rover and base firmware and the real daemon (`airwake sim
run`, stepped), exported, with the truth world's columns put beside it for scoring; the
model is made as `make demo` makes it (docs/calibration.md): `airwake calibrate` of the
blade-element `still_air_calibration` flight from Table 5.2 (24 windows), `airwake model
diagnose` on it and `airwake model add` of the effect its verdict names (unless the fit
makes a channel worse), then the same on 100 s of `still_air_cruise` (the steady step,
its misfit measured on the calibration flight; both steps in sequence.json). Both are
made once and kept in build/bench-cache/wind-<key>
(delete it to rebuild; the key covers the scenario files, the truth, BENCH_VERSION and
SPEC_VERSION).

The estimators run in a child process pinned to one thread (OMP/OpenBLAS/MKL/numba = 1),
each after a warm-up that loads the compiled model kernels:

- `wind_estimator_realtime_factor`: the default estimator (smoother), flight seconds per
  wall second; `wind_error_std_*`, `wind_error_mean_*`, `wind_correlation_*`,
  `wind_coverage90_*` against the truth after 2 s; `wind_crlb_std_*` the posterior
  Cramer-Rao bound at the truth (`airwake.estimate.wind.wind_bound`: the channels' error
  at the true wind — the model's misfit and the sensor noise — as a coloured AR process
  per channel, the considered steady offsets as nuisance parameters, the truth's own
  turbulence as the prior, the INS velocity error) and `wind_error_over_crlb_*` the
  error RMS over it; `table53_std_*` the reference's real-flight error std beside them.
- `apf_realtime_factor`: the reference's particle filter (eq 5.17, roulette wheel every
  sample, 2000 particles) on the same flight, on the front end at 30 Hz;
  `apf_realtime_factor_cpu` per CPU second; `apf_peak_rss_mb` the child's peak memory
  during the run (VmHWM after a reset); `apf_error_std_*`.

- `still_air_net_error_mean_*`, `still_air_net_error_std_*`, `still_air_net_coverage90_*`
  (v_x, v_y, v_z; the interval widened by the bench model's smoother, `wind estimate
  --interval-model`; `still_air_net_coverage90_alone_*` with the net's still-air error
  alone): the still-air wind net (docs/networks.md "Still-air labels": `airwake
  nets train --target wind --still-air` on blade-element still-air flights —
  `still_air_calibration` seeds 111-113 and `still_air_cruise` 131-133, no truth wind
  read — then `airwake wind estimate --method net`) on the same SIL flight;
  `still_air_net_realtime_factor` its estimate's flight seconds per wall second,
  `still_air_net_prepare_s` the seconds spent flying and training it (0 when cached in
  build/bench-cache/stillnet-<key>).
- `anchored_error_mean_*`, `anchored_error_std_*`, `anchored_coverage90_*` (all six
  components): the smoother of the bench model anchored on that widened still-air net's
  mean flow (`wind estimate --anchor`): the mean flow the net's, the rotation the
  model's given it.
- `map_field_rms_u`, `_v`, `_w`, `_wx`, `_wy`, `_wz`: the airwake map of that anchored
  estimate (`airwake wind map --score`, cells of 0.5 m), RMS against the truth world's
  field over the `map_cells` cells with >= 2 s of data (what `make demo` maps).

And what the truth world pays for its wind, per field type (`still_air`, `uniform`,
`fans_indoor`, `ship_airwake` at their defaults, the airwake at 15 deg):
`wind_field_us_per_point_<type>`, CPU microseconds per point of a `velocity_ned` call
shaped like the blade-element truth's (21 snapshots 5 ms apart of 112 points around a
moving hub: 2352 points), and `wind_local_us_per_point_<type>` of a `local_wind` call of
20 hubs (75 points each); the best of repeated calls after a warm-up (compiled kernels
loaded), one thread.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

SECTION = "estimate"
BENCH_VERSION = 3
# what `airwake calibrate` writes into the bench model's spec (2: its still-air wind error,
# 2026-11-28; 3: the sequence's steady step on a cruise flight, 2026-11-29): a new one
# rebuilds the calibrated model and its flight, not the still-air net
SPEC_VERSION = 3
# the steady step's cruise flight: the scenario's first two legs (out and back at 3.5 m/s),
# as `make demo` flies them
CRUISE_S = 100.0
SCENARIO = "ship_airwake_b15"
TRUTH = ("--truth", "blade_element", "--pilot", "crossover")
SEED = 101
REPO = Path(__file__).resolve().parents[1]
CACHE = REPO / "build" / "bench-cache"


def _key(duration: float) -> str:
    from hil_sim.world.scenario import find_scenario

    h = hashlib.sha1(f"{BENCH_VERSION} {SCENARIO} {SEED} {duration} {TRUTH} "
                     f"{SPEC_VERSION}".encode())
    for name in ("still_air_calibration", "still_air_cruise", SCENARIO):
        h.update(find_scenario(name).read_bytes())
    return h.hexdigest()[:12]


def _cli(*args: str):
    """Run one airwake command quietly; its standard output (JSON where asked)."""
    done = subprocess.run([sys.executable, "-m", "airwake.cli", *args], cwd=REPO,
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"airwake {' '.join(args[:2])} failed: {done.stderr[-800:]}")
    return done.stdout


def prepare(quick: bool) -> tuple[Path, Path, float]:
    """(flight with truth, calibrated spec, seconds spent making them: 0 when cached)."""
    import time

    duration = 20.0 if quick else 60.0
    d = CACHE / f"wind-{_key(duration)}"
    flight, spec = d / "flight_with_truth.parquet", d / "model.toml"
    if flight.is_file() and spec.is_file():
        return flight, spec, 0.0
    t0 = time.perf_counter()
    d.mkdir(parents=True, exist_ok=True)
    still, base = d / "calibration.parquet", d / "baseline.toml"
    _cli("sim", "table", "--scenario", "still_air_calibration", *TRUTH, "--quiet",
         "--out", str(still))
    _cli("calibrate", str(still), "--model", "table52", "--max-windows", "24", "--out",
         str(base))
    from airwake.calibrate.sequence import discrepancy_step, steady_step

    def run(*args):
        return json.loads(_cli(*args, "--quiet"))

    step = discrepancy_step(still, base, d / "added.toml", run=run)
    cruise = d / "cruise.parquet"
    _cli("sim", "table", "--scenario", "still_air_cruise", *TRUTH, "--duration",
         f"{CRUISE_S:g}", "--quiet", "--out", str(cruise))
    steady = steady_step(cruise, step["model"], d / "steady.toml", still, run=run)
    (d / "sequence.json").write_text(json.dumps({"still_air": step, "steady": steady},
                                                indent=1, default=str))
    shutil.copy(steady["model"], spec)
    rec = d / "recording"
    if rec.exists():
        shutil.rmtree(rec)
    _cli("sim", "run", "--scenario", SCENARIO, *TRUTH, "--seed", str(SEED), "--duration",
         f"{duration:g}", "--stepped", "--quiet", "--out", str(rec))
    _cli("export", str(rec), "--out", str(d / "flight.parquet"))
    _cli("sim", "truth", str(rec), "--flight", str(d / "flight.parquet"), "--out", str(flight))
    return flight, spec, time.perf_counter() - t0


def _short(name: str) -> str:
    """wind_vx_m_s -> vx: a component's name in the bench's keys."""
    return name.replace("wind_", "").split("_")[0]


STILL_AIR_FLIGHTS = (("still_air_calibration", (111, 112, 113)),
                     ("still_air_cruise", (131, 132, 133)))


def prepare_still_air_net(quick: bool) -> tuple[Path, float]:
    """(the still-air wind net, seconds spent flying and training it: 0 when cached)."""
    import time

    from hil_sim.world.scenario import find_scenario

    flights = [(name, seeds[:1] if quick else seeds) for name, seeds in STILL_AIR_FLIGHTS]
    h = hashlib.sha1(f"{BENCH_VERSION} {flights} {quick} {TRUTH}".encode())
    for name, _ in flights:
        h.update(find_scenario(name).read_bytes())
    d = CACHE / f"stillnet-{h.hexdigest()[:12]}"
    net = d / "still_air_net.pt"
    if net.is_file():
        return net, 0.0
    t0 = time.perf_counter()
    d.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, seeds in flights:
        for seed in seeds:
            path = d / f"{name}-{seed}.parquet"
            _cli("sim", "table", "--scenario", name, *TRUTH, "--seed", str(seed), "--quiet",
                 *(("--duration", "60") if quick else ()), "--out", str(path))
            paths.append(str(path))
    _cli("nets", "train", *paths, "--target", "wind", "--still-air", "--quiet", "--out",
         str(net))
    return net, time.perf_counter() - t0


def _still_air_net_figures(flight: Path, spec: Path, net: Path, made_s: float) -> dict:
    """The still-air net's mean flow on the bench flight (module doc)."""
    def estimate(*extra):
        return json.loads(_cli("wind", "estimate", str(flight), "--method", "net", "--net",
                               str(net), *extra, "--score", "--json", "--out",
                               str(net.parent / "wind_on_bench_flight.parquet")))

    res = estimate()
    widened = estimate("--interval-model", str(spec))  # the table the anchor reads
    anchored = json.loads(_cli("wind", "estimate", str(flight), "--model", str(spec),
                               "--anchor", str(net.parent / "wind_on_bench_flight.parquet"),
                               "--score", "--json", "--out",
                               str(net.parent / "anchored_on_bench_flight.parquet")))
    mapdir = net.parent / "map_of_bench_flight"
    shutil.rmtree(mapdir, ignore_errors=True)
    amap = json.loads(_cli("wind", "map", str(net.parent / "anchored_on_bench_flight.parquet"),
                           "--flight", str(flight), "--out", str(mapdir), "--score", "--json"))
    out = {"still_air_net_realtime_factor": res["realtime_factor"],
           "still_air_net_prepare_s": made_s, "map_cells": amap["score"]["cells"]}
    for name, c in amap["score"]["field"].items():  # u_m_s ... wz_rad_s
        out[f"map_field_rms_{name.split('_')[0]}"] = c["rms"]
    for name, c in anchored["score"]["components"].items():
        short = _short(name)
        out[f"anchored_error_mean_{short}"] = c["error_mean"]
        out[f"anchored_error_std_{short}"] = c["error_std"]
        out[f"anchored_coverage90_{short}"] = c["coverage_90"]
    for name in ("wind_vx_m_s", "wind_vy_m_s", "wind_vz_m_s"):
        c = res["score"]["components"][name]
        short = _short(name)
        out[f"still_air_net_error_mean_{short}"] = c["error_mean"]
        out[f"still_air_net_error_std_{short}"] = c["error_std"]
        out[f"still_air_net_coverage90_alone_{short}"] = c["coverage_90"]
        out[f"still_air_net_coverage90_{short}"] = (
            widened["score"]["components"][name]["coverage_90"])
    return out


def _vm_hwm_mb() -> float | None:
    try:
        for line in open("/proc/self/status"):
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def _reset_hwm() -> bool:
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


def _child(flight: str, spec: str, particles: int) -> None:
    """In the child: each estimator after a warm-up; timing, memory and scores as JSON."""
    import time

    from airwake.calibrate import load_flight
    from airwake.estimate import estimate_wind, score_wind
    from airwake.estimate.wind import score_bound, wind_bound

    ft = load_flight(flight)
    span = float(ft.df["t_s"].iloc[-1] - ft.df["t_s"].iloc[0])
    head = ft.df.iloc[:600].reset_index(drop=True)
    estimate_wind(head, spec, em_passes=1)  # warm-up: imports, kernels
    c0 = time.process_time()
    est = estimate_wind(ft, spec)
    sm_cpu = time.process_time() - c0
    score = score_wind(est.df, ft.df)
    score_bound(score, wind_bound(est, ft.df), est.df)
    estimate_wind(head, spec, method="apf", n_particles=particles, resampler="roulette",
                  steps=3)
    reset = _reset_hwm()
    c0 = time.process_time()
    apf = estimate_wind(ft, spec, method="apf", n_particles=particles, resampler="roulette")
    apf_cpu = time.process_time() - c0
    print(json.dumps({
        "flight_s": span, "smoother_s": est.seconds, "smoother_cpu_s": sm_cpu,
        "score": score, "prior": est.metadata["prior"],
        "apf_s": apf.seconds, "apf_cpu_s": apf_cpu,
        "apf_peak_rss_mb": _vm_hwm_mb() if reset else None,
        "apf_score": score_wind(apf.df, ft.df),
        "apf_mean_ess": float(apf.df["ess"].mean())}))


FIELDS = {
    "still_air": {"type": "still_air"},
    "uniform": {"type": "uniform", "velocity_ned_m_s": [3.0, 1.0, 0.0],
                "turbulence_intensity": 0.1},
    "fans_indoor": {"type": "fans_indoor"},
    "ship_airwake": {"type": "ship_airwake", "relative_wind_heading_deg": 15.0},
}
# Where each field is flown: between the fans; over the flight deck behind the hangar.
HUB_NED_M = {"fans_indoor": (3.5, 0.0, -2.0), "ship_airwake": (-4.0, 0.5, -4.0)}


def field_costs(quick: bool) -> dict:
    """CPU microseconds per point of each field type (module doc)."""
    import time

    import numpy as np

    from hil_sim.world.ship import Ship
    from hil_sim.world.wind import build_wind_field

    repeats = 5 if quick else 30
    rng = np.random.default_rng(0)
    snapshots, grid = 21, rng.uniform(-0.8, 0.8, (112, 3))
    t_grid = np.repeat(10.0 + 0.005 * np.arange(snapshots), grid.shape[0])
    drift = np.outer(t_grid - 10.0, [2.0, 0.5, 0.0])  # the hub moves through the grid
    hubs = rng.uniform(-1.0, 1.0, (20, 3))
    t_hubs = 10.0 + 0.01 * np.arange(hubs.shape[0])
    quats = np.tile([1.0, 0.0, 0.0, 0.0], (hubs.shape[0], 1))

    def best(call) -> float:
        call()  # warm-up: loads the compiled kernels
        out = np.inf
        for _ in range(repeats):
            c0 = time.process_time()
            call()
            out = min(out, time.process_time() - c0)
        return out

    out = {}
    for kind, config in FIELDS.items():
        ship = Ship()
        field = build_wind_field(config, rng=np.random.default_rng(1), ship=ship)
        hub = np.array(HUB_NED_M.get(kind, (0.0, 0.0, -3.0)))
        if kind == "ship_airwake":  # the hub rides with the ship
            hub_at = ship.ship_to_ned(t_grid, np.broadcast_to(hub, t_grid.shape + (3,)))
            hubs_at = ship.ship_to_ned(t_hubs, hub + hubs)
        else:
            hub_at, hubs_at = np.broadcast_to(hub, t_grid.shape + (3,)), hub + hubs
        points = hub_at + np.tile(grid, (snapshots, 1)) + drift
        dt = best(lambda f=field, p=points: f.velocity_ned(t_grid, p))
        out[f"wind_field_us_per_point_{kind}"] = round(dt / t_grid.size * 1e6, 4)
        dt = best(lambda f=field, p=hubs_at: f.local_wind(t_hubs, p, quats))
        out[f"wind_local_us_per_point_{kind}"] = round(dt / (hubs.shape[0] * 75) * 1e6, 4)
    return out


def run(quick: bool = False) -> dict:
    fields = field_costs(quick)
    flight, spec, made_s = prepare(quick)
    particles = 2000
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1", NUMBA_NUM_THREADS="1")
    code = (f"from hil_sim.wind_bench import _child; "
            f"_child({str(flight)!r}, {str(spec)!r}, {particles})")
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=False, cwd=REPO)
    if proc.returncode != 0:
        raise RuntimeError(f"estimator child failed: {proc.stderr.strip()[-800:]}")
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    out = {
        "wind_flight": f"{SCENARIO} seed {SEED}, {res['flight_s']:.0f} s SIL (rover+base "
                       "firmware, daemon, export), blade-element truth, crossover pilot",
        "wind_estimator": "smoother",
        "wind_estimator_realtime_factor": res["flight_s"] / res["smoother_s"],
        "wind_estimator_realtime_factor_cpu": res["flight_s"] / res["smoother_cpu_s"],
        "apf_realtime_factor": res["flight_s"] / res["apf_s"],
        "apf_realtime_factor_cpu": res["flight_s"] / res["apf_cpu_s"],
        "apf_peak_rss_mb": res["apf_peak_rss_mb"],
        "apf_particles": particles,
        "apf_mean_ess": res["apf_mean_ess"],
        "wind_bench_prepare_s": made_s,
        **fields,
    }
    for name, c in res["score"]["components"].items():
        short = _short(name)
        out[f"wind_error_mean_{short}"] = c["error_mean"]
        out[f"wind_error_std_{short}"] = c["error_std"]
        out[f"wind_correlation_{short}"] = c["correlation"]
        out[f"wind_coverage90_{short}"] = c["coverage_90"]
        out[f"wind_crlb_std_{short}"] = c["crlb_std"]
        out[f"wind_error_over_crlb_{short}"] = c["error_over_crlb"]
        out[f"table53_std_{short}"] = c["table_5_3_std"]
        a = res["apf_score"]["components"][name]
        out[f"apf_error_std_{short}"] = a["error_std"]
        out[f"apf_error_mean_{short}"] = a["error_mean"]
    out.update(_still_air_net_figures(flight, spec, *prepare_still_air_net(quick)))
    return out
