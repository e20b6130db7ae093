"""`airwake bench` section "nets": the rate network on 60 s of a 150 Hz truth-world
still-air flight (seed 7; the shipped scenario's truth: the blade-element airframe and
the crossover pilot), one torch thread.

Keys: nets_train_s (features, split, ARX and AdamW training to early stop; target
< 60 s), nets_infer_realtime_factor (flight seconds per second of `predict`: features +
forward pass over the whole flight; target >= 100), nets_test_rms_deg_s_{p,q,r} (held-out
test rows of that flight: its last 20 %; next to Table 2.2's best 2.13 deg/s) and nets_epochs.

The airwake-intensity map (docs/networks.md, A_ω) with that net on a ship_airwake_b0
flight of the same length (seed 7): nets_airwake_map_s (predict, eq 2.4 / residual std
series, placing in the ship frame, gridding; target: well under the flight's length),
nets_airwake_map_realtime_factor, nets_airwake_cells (>= 2 s of data) and the cells'
Pearson correlation with the simulator's turbulence, nets_airwake_a_omega_pearson and
nets_airwake_resid_std_pearson: a smoke figure on one short flight with few cells, not
the doc's table (4 flights of 150 s).
"""

from __future__ import annotations

import time

SECTION = "nets"


def run(quick: bool) -> dict:
    import torch

    from airwake.nets import net_flight_from_df, predict, train_net
    from hil_sim.world.run import run_scenario
    from hil_sim.world.scenario import load_scenario

    duration_s = 20.0 if quick else 60.0
    built = run_scenario(load_scenario("still_air_calibration"), seed=7,
                         duration_s=duration_s).flight_table()
    flight = net_flight_from_df(built.df, "bench still_air_calibration seed 7")
    old = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        t0 = time.perf_counter()
        net = train_net([flight], target="rates", seed=0)
        train_s = time.perf_counter() - t0
        predict(net, flight)  # warm-up
        reps = 3
        t0 = time.perf_counter()
        for _ in range(reps):
            predict(net, flight)
        infer_s = (time.perf_counter() - t0) / reps
    finally:
        torch.set_num_threads(old)
    span = float(flight.t_s[-1] - flight.t_s[0])
    test = net.card["metrics"]["test"]["measured"]["net"]
    out = {"nets_train_s": round(train_s, 3),
           "nets_infer_realtime_factor": round(span / infer_s, 1),
           "nets_train_rows": int(len(flight)),
           "nets_epochs": int(net.card["training"]["epochs_run"])}
    out.update({f"nets_test_rms_deg_s_{a}": round(test[a]["rms"], 4) for a in "pqr"})
    out.update(_airwake_map(net, duration_s))
    return out


def _airwake_map(net, duration_s: float) -> dict:
    import math

    import torch

    from airwake.nets import predict
    from airwake.nets.intensity import IntensityConfig
    from airwake.nets.intensity_map import build_intensity_map, score_intensity
    from hil_sim.world.run import run_scenario
    from hil_sim.world.scenario import load_scenario

    ship = run_scenario(load_scenario("ship_airwake_b0"), seed=7,
                        duration_s=duration_s).flight_table()
    old = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        t0 = time.perf_counter()
        amap = build_intensity_map(predict(net, ship.df), ship.df, IntensityConfig())
        map_s = time.perf_counter() - t0
        scored = build_intensity_map(predict(net, ship.df), ship.df, IntensityConfig(),
                                     flight_metadata=ship.metadata)
    finally:
        torch.set_num_threads(old)
    score = score_intensity(scored.cells)

    def fin(v: float):
        return round(v, 3) if math.isfinite(v) else None

    span = float(ship.df["t_s"].iloc[-1] - ship.df["t_s"].iloc[0])
    return {"nets_airwake_map_s": round(map_s, 3),
            "nets_airwake_map_realtime_factor": round(span / map_s, 1),
            "nets_airwake_cells": int(score["cells"]) if len(amap.cells) else 0,
            "nets_airwake_a_omega_pearson": fin(score["a_omega_pearson"]),
            "nets_airwake_resid_std_pearson": fin(score["resid_std_pearson"])}
