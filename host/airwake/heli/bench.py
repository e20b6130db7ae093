"""`airwake bench` section "model": helicopter-model throughput and compile times.

Every figure is the best of several repeats in this process (the machine is shared);
the compile figures come from fresh subprocesses (empty kernel cache, then the same
cache warm), so they include numba's own start-up.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

import numpy as np

SECTION = "model"

_COMPILE_PROBE = """
import time, numpy as np
t0 = time.perf_counter()
from airwake.heli import load_spec
m = load_spec("table52")
t1 = time.perf_counter()
m.derivatives(m.zero_state(1), np.zeros(4))
t2 = time.perf_counter()
m2 = m.without("empennage")
m2.derivatives(m2.zero_state(1), np.zeros(4))
t3 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2)
"""


def _best(fn, repeat: int, number: int = 1) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return best


def synthetic_flight(model, trim, samples: int, rate_hz: float = 150.0) -> dict:
    """Body states and inputs as slow sinusoids about trim (what the measurement model
    reads; not a consistent flight, which the timing does not need)."""
    t = np.arange(samples) / rate_hz
    cols = {"t_s": t, "rotor_speed_rad_s": 163.3 + 2.0 * np.sin(0.7 * t)}
    for j, c in enumerate(("delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad")):
        cols[c] = trim.u[j] + 0.01 * np.sin((2.0 + 0.5 * j) * t)
    names = ("pos_n_m", "pos_e_m", "pos_d_m", "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
             "roll_rad", "pitch_rad", "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s")
    for i, c in enumerate(names):
        cols[c] = trim.x[i] + (0.05 * np.sin((1 + i) * t) if i >= 3 else 0.0 * t)
    return cols


def _compile_times() -> dict:
    """Cold compile (empty cache) and warm load, each in a fresh process."""
    out = {}
    with tempfile.TemporaryDirectory(prefix="airwake-bench-kernels-") as cache:
        env = {**os.environ, "AIRWAKE_KERNEL_CACHE": cache}
        for label in ("cold", "warm"):
            t0 = time.perf_counter()
            res = subprocess.run([sys.executable, "-c", _COMPILE_PROBE], env=env,
                                 capture_output=True, text=True, timeout=1800, check=True)
            wall = time.perf_counter() - t0
            imp, first, second = map(float, res.stdout.split())
            if label == "cold":
                out["model_compile_cold_first_call_s"] = first
                out["model_compile_new_composition_s"] = second
            else:
                out["model_compile_cached_first_call_s"] = first
                out["model_import_s"] = imp
                out["model_cached_process_wall_s"] = wall
    return out


def run(quick: bool = False) -> dict:
    from airwake.heli import HeliModel, load_spec
    from airwake.heli.integrate import Stepper, simulate
    from airwake.heli.measurement import predict_measurements
    from airwake.heli.trim import trim_hover

    model = load_spec("table52")
    tr = trim_hover(model)
    rng = np.random.default_rng(0)
    n = 2000
    x = np.repeat(tr.x[None], n, 0)
    x[:, 3:6] += rng.normal(0, 1, (n, 3))
    x[:, 9:12] += rng.normal(0, 0.3, (n, 3))
    u = np.repeat(tr.u[None], n, 0)
    w = rng.normal(0, 1, (n, 6))
    rep = 5 if quick else 15
    model.rates_and_measurement(x[:1], u[:1], w[:1])  # compile/load outside the timing
    t_batch = _best(lambda: model.derivatives(x, u, w), rep)
    t_meas = _best(lambda: model.measure(x, u, w), rep)
    t_eval = _best(lambda: model.evaluate(x, u, w), rep)
    x1, u1 = tr.x.copy(), tr.u.copy()
    t_one = _best(lambda: model.derivatives(x1, u1), rep, 200)
    # RK4 at 1 kHz, one row, Python glue included (what a closed-loop simulator pays)
    stepper = Stepper(model, 1e-3)
    w1 = np.zeros(6)
    t_step = _best(lambda: stepper.step(x1, u1, w1), rep, 200)
    steps = 2000 if quick else 10000
    u_seq = tr.u + 0.01 * np.sin(np.arange(steps + 1) * 1e-3)[:, None]
    simulate(model, tr.x, 0.01, 1e-3, u_seq[:11])
    t_sim = _best(lambda: simulate(model, tr.x, steps * 1e-3, 1e-3, u_seq, sample_every=10),
                  2 if quick else 3)
    # the same pipeline with one numpy stage (a user plugin) for comparison
    mixed = HeliModel(list(model.effects) + [_numpy_probe()])
    mixed.derivatives(x1, u1)
    t_mixed_one = _best(lambda: mixed.derivatives(x1, u1), rep, 20)
    t_mixed_batch = _best(lambda: mixed.derivatives(x, u, w), rep)
    # measurement model over a 62,000-sample flight (hidden-state pass included)
    samples = 6200 if quick else 62000
    flight = synthetic_flight(model, tr, samples)
    predict_measurements(model, {k: v[:50] for k, v in flight.items()})
    t_flight = _best(lambda: predict_measurements(model, flight), 1 if quick else 2)
    k_sets = 8
    sets = np.repeat(model.parameter_vector()[None], k_sets, 0)
    sets[:, model.parameter_names.index("main_rotor.lock_number")] *= np.linspace(0.9, 1.1, k_sets)
    short = {k: v[: samples // 10] for k, v in flight.items()}
    t_sets = _best(lambda: predict_measurements(model, short, params=sets), 1 if quick else 2)
    out = {
        "model_evals_per_s": n / t_batch,
        "model_batch2000_derivatives_ms": 1e3 * t_batch,
        "model_batch2000_measure_ms": 1e3 * t_meas,
        "model_batch2000_evaluate_full_context_ms": 1e3 * t_eval,
        "model_single_row_derivatives_us": 1e6 * t_one,
        "model_rk4_step_us": 1e6 * t_step,
        "model_rk4_steps_per_s": 1.0 / t_step,
        "model_rk4_1khz_realtime_factor_single": 1e-3 / t_step,
        "model_simulate_compiled_steps_per_s": steps / t_sim,
        "model_numpy_plugin_single_row_derivatives_us": 1e6 * t_mixed_one,
        "model_numpy_plugin_batch2000_derivatives_ms": 1e3 * t_mixed_batch,
        "model_predict_samples": samples,
        "model_predict_62k_flight_s": 62000 * t_flight / samples,
        "model_predict_k_sets": k_sets,
        "model_predict_per_set_62k_flight_s": 62000 * t_sets / (k_sets * (samples // 10)),
    }
    if not quick:
        out.update(_compile_times())
    return out


def _numpy_probe():
    """A small numpy-style effect (extra side drag at the tail boom), unregistered."""
    from airwake.heli import Effect, Parameter

    class BoomDrag(Effect):
        name = "bench_boom_drag"
        PARAMETERS = (Parameter("cd_m2", 0.01, "m^2", (0.0, 1.0), "bench"),)

        def forces(self, ctx, p):
            vy = ctx.air_velocity_at(np.array([-0.8, 0.0, 0.0]))[:, 1]
            f = np.zeros((ctx.n, 3))
            f[:, 1] = 0.5 * ctx.air_density_kg_m3 * p.cd_m2 * vy * np.abs(vy)
            ctx.add_load(self.name, f, np.zeros(3))

    return BoomDrag()
