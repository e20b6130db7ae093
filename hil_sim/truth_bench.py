"""`airwake bench` section "truth": the blade-element truth's speed.

`truth_realtime_factor`: simulated seconds per wall second of a 60 s `ship_airwake_b15`
flight on the blade-element truth (hil_sim.world.rotorcraft) flown by the crossover pilot,
sensors and the flight table included, in one process on one core (BLAS held to one
thread; the compiled dynamics are single-threaded). Its parts beside it: trim and
linearisation, the wind field sampled on the moving grid, the compiled integration, the
scoring fit, the sensors and the table (`truth_*_s`), and the integration's own
factor. The compiled code is loaded (and cached) by a short warm-up flight first.
"""

from __future__ import annotations

SECTION = "truth"


def run(quick: bool) -> dict:
    import dataclasses

    import airwake.record.flight_builder  # noqa: F401  (pandas, pyarrow)
    from threadpoolctl import threadpool_limits

    from hil_sim.world.run import run_scenario
    from hil_sim.world.scenario import load_scenario

    duration = 10.0 if quick else 60.0
    scenario = load_scenario("ship_airwake_b15")
    scenario = dataclasses.replace(scenario, helicopter=dataclasses.replace(
        scenario.helicopter, model="blade_element", pilot="crossover"))
    with threadpool_limits(1):
        run_scenario(scenario, duration_s=0.5).flight_table()
        result = run_scenario(scenario, duration_s=duration)
        built = result.flight_table()
    t = result.timing
    parts = result.pilot_info["blade_element_timing_s"]
    return {
        "truth_realtime_factor": round(result.realtime_factor, 3),
        "truth_duration_s": duration,
        "truth_step_hz": round(1.0 / float(result.truth.t_s[1] - result.truth.t_s[0]), 1),
        "truth_trim_s": round(parts["trim"], 3),
        "truth_field_s": round(parts["field"], 3),
        "truth_integrate_s": round(parts["integrate"], 3),
        "truth_scoring_s": round(parts["scoring"], 3),
        "truth_sensors_s": round(t["sensors"], 3),
        "truth_table_s": round(t["table"], 3),
        "truth_integration_realtime_factor": round(duration / parts["integrate"], 3),
        "truth_table_rows": int(len(built.df)),
    }
