"""Flights, models and noise floors for the discrepancy tests.

Flights are hil_sim truth-world flight tables (`hil_sim.world.run.run_scenario` -> the
shared flight-table builder) of the compact scenarios in tests/discrepancy/scenarios/
(each extends a shipped scenario: same helicopter, sensors and hidden-effect settings,
a shorter script). Each is flown once per test session (fixed seeds) and shared.

The noise floor a test compares against is computed from the flight's truth columns:

    floor_c = sqrt(sensor_c^2 + state_c^2)
    sensor_c = RMS band(z_meas - truth_z)                 (output noise: IMU, differentiator)
    state_c  = RMS band(z_hat(measured states, inputs) - z_hat(truth states, inputs))
               (truth states: the CG's, the velocity at the IMU point as the INS reports it,
               and the true hub height)

the second term being the measured states' noise (the INS velocity error is a 5 cm/s
Gauss-Markov process with a 5 s time constant) propagated through the model, which an
equation-error method cannot remove: even the truth model sits at ~5x the output noise
in az and ~6x in pdot on the still-air flight (see tests/discrepancy/README in the
report / docs/model-discrepancy.md). Both in the analysis band over the analysis mask.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np

SCENARIO_DIR = Path(__file__).resolve().parent / "scenarios"
TRUTH_SPEC = Path(__file__).resolve().parents[2] / "hil_sim" / "world" / "truth_helicopter.toml"
STATE_COLUMNS = ("vel_u_m_s", "vel_v_m_s", "vel_w_m_s", "roll_rad", "pitch_rad", "yaw_rad",
                 "p_rad_s", "q_rad_s", "r_rad_s", "rotor_speed_rad_s")
# The tachometer's rotor speed is a measured state too (a model with rotor_droop reads it).
# Not the blade-pitch columns: the flight's inputs are the measured commands (exact to the
# RC quantisation, ~7e-5 rad), while truth_delta_* is the pitch the blades flew, which
# under a hidden servo lag *is* the hidden effect, not noise.
_FLIGHTS: dict = {}


@contextlib.contextmanager
def _tail_thrust_error(relative_change: float):
    """Fly with the out-of-catalogue tail-thrust error appended to the truth model."""
    import hil_sim.world.run as run
    from hil_sim.world.hidden.tail_thrust_airspeed import with_tail_thrust_error

    original = run.build_truth_model

    def build(*args, **kw):
        return with_tail_thrust_error(original(*args, **kw), relative_change)

    run.build_truth_model = build
    try:
        yield
    finally:
        run.build_truth_model = original


def fly(name: str, blade_element: bool = False, hidden: bool = True):
    """FlightTable of tests/discrepancy/scenarios/<name>.toml (cached per session); with
    `blade_element` the independent blade-element truth flown by the crossover pilot, the
    scenario's (sensor-side) hidden effects on top of its own physics; `hidden=False`: the
    same flight without them (a control)."""
    key = (name, blade_element, hidden)
    if key in _FLIGHTS:
        return _FLIGHTS[key]
    from dataclasses import replace

    from airwake.record.flight_table import FlightTable

    from hil_sim.world.run import run_scenario
    from hil_sim.world.scenario import load_scenario

    sc = load_scenario(SCENARIO_DIR / f"{name}.toml")
    if blade_element:
        sc = replace(sc, helicopter=replace(sc.helicopter, model="blade_element",
                                            pilot="crossover"))
    if not hidden:
        from hil_sim.world.hidden import HiddenConfig

        sc = replace(sc, hidden=HiddenConfig())
    ctx = _tail_thrust_error(0.25) if name == "tail_airspeed" else contextlib.nullcontext()
    with ctx:
        built = run_scenario(sc).flight_table()
    ft = FlightTable(built.df, dict(built.metadata), None)
    _FLIGHTS[key] = ft
    return ft


def truth_model():
    from airwake.heli import load_spec

    return load_spec(TRUTH_SPEC)


def noise_floor(an) -> np.ndarray:
    """(6,) floor of an Analysis's flight for its model (module docstring); reads the
    truth columns of the flight the analysis was made from (passed as `an.truth_df`)."""
    from airwake.discrepancy.compare import predict
    from airwake.discrepancy.data import Flight
    from airwake.heli.context import MEAS_CHANNELS

    df = an.truth_df
    truth_z = np.column_stack([df[f"truth_{c}"].to_numpy() for c in MEAS_CHANNELS])
    sensor = an.band(an.flight.z - truth_z)[an.mask]
    tdf = an.flight.df.copy()
    for c in STATE_COLUMNS:
        tdf[c] = df[f"truth_{c}"].to_numpy()
    # the INS reports the IMU point's velocity, v + w x r: with a lever arm that offset is
    # the hidden effect, not noise (truth_vel_* is the CG's)
    r = np.asarray(getattr(an, "imu_position_m", (0.0, 0.0, 0.0)), float)
    w = np.column_stack([df[f"truth_{c}"].to_numpy() for c in ("p_rad_s", "q_rad_s",
                                                                "r_rad_s")])
    wxr = np.cross(w, r[None])
    for j, c in enumerate(("vel_u_m_s", "vel_v_m_s", "vel_w_m_s")):
        tdf[c] = tdf[c].to_numpy() + wxr[:, j]
    if "truth_height_agl_m" in df.columns and "height_agl_m" in tdf.columns:
        tdf["height_agl_m"] = df["truth_height_agl_m"].to_numpy()  # the height's noise too
    z_truth_states = predict(an.model, Flight(tdf, "truth states"))
    state = an.band(an.zhat - z_truth_states)[an.mask]
    return np.sqrt(np.mean(sensor**2, 0) + np.mean(state**2, 0))


def analysed(model, ft, settings=None):
    """analyse() of a flight table, keeping its truth columns for `noise_floor`."""
    from airwake.discrepancy.compare import analyse

    an = analyse(model, ft, settings)
    an.truth_df = ft.df
    an.imu_position_m = (ft.metadata.get("sim") or {}).get("imu_position_m", (0.0, 0.0, 0.0))
    return an
