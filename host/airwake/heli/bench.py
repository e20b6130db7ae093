"""`airwake bench` section "model": helicopter-model throughput."""

from __future__ import annotations

import time

import numpy as np

SECTION = "model"


def _best(fn, repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def run(quick: bool = False) -> dict:
    from airwake.heli import load_spec
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
    rep = 3 if quick else 10
    t_batch = _best(lambda: model.derivatives(x, u, w), rep)
    t_meas = _best(lambda: model.measure(x, u, w), rep)
    t_one = _best(lambda: model.derivatives(x[:1], u[:1], w[:1]), rep * 5)
    # measurement model over a flight (hidden-state reconstruction included)
    samples = 1500 if quick else 15000
    t = np.arange(samples) / 150.0
    cols = {"t_s": t, "delta_col_rad": tr.u[0] + 0.005 * np.sin(2 * t),
            "delta_lat_rad": tr.u[1] + 0.01 * np.sin(3 * t),
            "delta_lon_rad": tr.u[2] + 0.01 * np.sin(2.5 * t),
            "delta_ped_rad": tr.u[3] + 0.01 * np.sin(1.3 * t)}
    names = ("pos_n_m", "pos_e_m", "pos_d_m", "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
             "roll_rad", "pitch_rad", "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s")
    for i, c in enumerate(names):
        cols[c] = tr.x[i] + (0.05 * np.sin((1 + i) * t) if i >= 3 else 0.0)
    t_flight = _best(lambda: predict_measurements(model, cols), 1 if quick else 2)
    return {
        "model_evals_per_s": n / t_batch,
        "model_batch2000_derivatives_ms": 1e3 * t_batch,
        "model_batch2000_measure_ms": 1e3 * t_meas,
        "model_single_row_derivatives_us": 1e6 * t_one,
        "model_rk4_1khz_realtime_factor_single": 1.0 / (4000 * t_one),
        "model_predict_flight_samples_per_s": samples / t_flight,
        "model_predict_62k_flight_s_extrapolated": 62000 * t_flight / samples,
    }
