"""`airwake bench` section "sim": the truth world's speed.

`sim_realtime_factor`: simulated seconds per wall second for `still_air_calibration` as
shipped (the blade-element truth, the crossover pilot) with every sensor on (integration
at 1 kHz + sensors + the flight table), one process; the split is reported beside it
(`sim_integration_s`, `sim_sensors_s`, `sim_table_s`, and the integration's own factor
`sim_integration_realtime_factor`). `sim_effects_realtime_factor`: the same flight on the
effect truth (our own model, the LQR pilot: what the tests that need it fly).
The SIL figures (`sil_stepped_realtime_factor`, ...) come from `hil_sim/boards/bench.py`.
"""

from __future__ import annotations

SECTION = "sim"


def run(quick: bool) -> dict:
    # imports and the compiled model's first load are not the simulator's speed: warm up
    import airwake.record.flight_builder  # noqa: F401  (pandas, pyarrow)

    from hil_sim.world.run import run_scenario
    from hil_sim.world.scenario import load_scenario

    duration = 5.0 if quick else 30.0
    scenario = load_scenario("still_air_calibration")
    run_scenario(scenario, seed=scenario.seed, duration_s=0.2).flight_table()
    result = run_scenario(scenario, seed=scenario.seed, duration_s=duration)
    built = result.flight_table()
    t = result.timing
    figures = {
        "sim_realtime_factor": round(result.realtime_factor, 3),
        "sim_duration_s": duration,
        "sim_rate_hz": scenario.rate_hz,
        "sim_integration_s": round(t["integration"], 3),
        "sim_sensors_s": round(t["sensors"], 3),
        "sim_table_s": round(t["table"], 3),
        "sim_integration_realtime_factor": round(duration / t["integration"], 3),
        "sim_table_rows": int(len(built.df)),
    }
    ours = scenario.with_helicopter(model="effects", pilot="full_state")
    run_scenario(ours, seed=scenario.seed, duration_s=0.2)
    figures["sim_effects_realtime_factor"] = round(
        run_scenario(ours, seed=scenario.seed, duration_s=duration).realtime_factor, 3)
    # the SIL layer's figures (hil_sim/boards/bench.py): boards + daemon, stepped
    try:
        from hil_sim.boards import bench as sil_bench

        figures.update(sil_bench.run(quick))
    except Exception as exc:  # noqa: BLE001 — the world's figures stand on their own
        figures["sil_error"] = f"{type(exc).__name__}: {exc}"
    return figures
