"""`airwake bench` section "calibrate": least squares vs the reference's PSO on the same
62,000-sample model-generated flight (Table 5.2 truth + seed-like noise, calibrated from
Table 5.1 with the fixed constants at their Table 5.2 values).

Keys: calibration_lsq_s, calibration_lsq_rms (RMS over the 6 channels of the per-channel
residual RMS, units ignored, as the reference's 0.848), calibration_pso_s (extrapolated
to 2000 particles x 500 iterations from the measured time per iteration: a full run
takes hours; calibration_pso_extrapolated says so), calibration_pso_rms (the global
best after the iterations actually run: calibration_pso_iterations_run), the ratio, the
noise floor of the flight (calibration_noise_rms) and the generation time.
"""

from __future__ import annotations

import hashlib
import json
import time
from pathlib import Path

import numpy as np

SECTION = "calibrate"
_REPO = Path(__file__).resolve().parents[3]
CACHE = _REPO / "build" / "bench-cache"


def cached_flight(name: str, **kw):
    """A synthetic flight generated once and kept in build/bench-cache (keyed by the
    generator's arguments and source)."""
    from airwake.calibrate import synthetic
    from airwake.record.flight_table import load_flight_table, write_flight_table

    src = Path(synthetic.__file__).read_bytes()
    key = hashlib.sha1(src + json.dumps(kw, sort_keys=True, default=str).encode()).hexdigest()
    path = CACHE / f"{name}-{key[:12]}.parquet"
    if path.is_file():
        return load_flight_table(path, required=()), 0.0
    CACHE.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    ft = synthetic.generate_flight(**kw)
    seconds = time.perf_counter() - t0
    write_flight_table(ft.df, path, ft.metadata)
    ft.path = path
    return ft, seconds


def start_model():
    """Table 5.1 for every free parameter, Table 5.2 for the fixed constants."""
    from airwake.heli import load_spec

    m51, m52 = load_spec("table51"), load_spec("table52")
    vec = m52.parameter_vector()
    free = ~m51.fixed_mask()
    vec[free] = m51.parameter_vector()[free]
    return m51.with_parameters(vec)


def _rms(per_channel) -> float:
    return float(np.sqrt(np.mean(np.asarray(per_channel) ** 2)))


def run(quick: bool = False) -> dict:
    from airwake.calibrate import calibrate
    from airwake.calibrate.params import select_parameters
    from airwake.calibrate.pso import fit_pso
    from airwake.calibrate.residuals import FlightData, WindowedPredictor, make_windows

    samples = 6000 if quick else 62000
    segments = 4 if quick else 8
    per_seg = samples / segments / 150.0
    ft, gen_s = cached_flight(f"calib{samples}", duration_s=per_seg, segments=segments,
                              seed=5)
    model = start_model()
    out = {"calibration_flight_samples": int(len(ft.df)),
           "calibration_flight_generate_s": gen_s,
           "calibration_noise_rms": _rms([0.2] * 3 + [0.3] * 3)}
    t0 = time.perf_counter()
    # the white-noise synthetic flight, fitted raw on every free parameter: the same
    # problem as the PSO below (the front end and subset selection are for real flights)
    lsq = calibrate(ft, model, "lsq", max_nfev=30 if quick else 60, cutoff_hz=None,
                    params=[n for n, f in zip(model.parameter_names, select_parameters(model),
                                              strict=True) if f])
    out["calibration_lsq_s"] = time.perf_counter() - t0
    out["calibration_lsq_rms"] = _rms(lsq.rms_after)
    out["calibration_start_rms"] = _rms(lsq.rms_before)
    out["calibration_lsq_evaluations"] = int(lsq.info.get("nfev", 0))

    # PSO: 2000 particles, a few iterations measured, time extrapolated to 500
    particles = 200 if quick else 2000
    iters = 2
    data = FlightData.from_flight(model, ft)
    pred = WindowedPredictor(model, data, make_windows(data))
    free = select_parameters(model)
    t0 = time.perf_counter()
    pso = fit_pso(model, pred, free, np.random.default_rng(0), particles, 0, 16)
    setup_and_final = time.perf_counter() - t0
    t0 = time.perf_counter()
    pso = fit_pso(model, pred, free, np.random.default_rng(0), particles, iters, 16)
    per_iter = max(time.perf_counter() - t0 - setup_and_final, 1e-9) / iters
    full = setup_and_final + 500 * per_iter * (2000 / particles)
    out.update({
        "calibration_pso_s": full,
        "calibration_pso_extrapolated": True,
        "calibration_pso_s_per_iteration_2000": per_iter * 2000 / particles,
        "calibration_pso_iterations_run": iters,
        "calibration_pso_particles_run": particles,
        "calibration_pso_rms": _rms(pso.rms_after),
        "calibration_pso_over_lsq_time": full / out["calibration_lsq_s"],
    })
    return out
