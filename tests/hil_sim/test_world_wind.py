"""Wind through the world: the truth_wind_* columns along a ship-airwake flight are the
field's eq 5.3 wind at the hub, with the field's mean, turbulence and shedding."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.signal import welch
from world_helpers import short_scenario

from hil_sim.world.kinematics import euler_to_quat, rotate, rotate_inverse
from hil_sim.world.run import run_scenario
from hil_sim.world.wind import LOCAL_WIND_COLUMNS, build_wind_field

STATION_M = (-8.0, 0.0, -1.2)  # behind the flight deck, in the hangar's shear layer


def hover_flight(duration_s: float, seed: int, **wind):
    sc = short_scenario("ship_airwake_b0", segments=[{"type": "hover",
                                                      "duration_s": duration_s}],
                        duration_s=duration_s, seed=seed)
    sc = dataclasses.replace(sc, pilot=dataclasses.replace(sc.pilot, start_m=STATION_M),
                             wind={**sc.wind, **wind})
    r = run_scenario(sc, sensors=True)
    return r, r.flight_table().df


@pytest.fixture(scope="module")
def airwake():
    return hover_flight(15.0, seed=21)


def _hub_ned(df, r):
    att = df[["truth_roll_rad", "truth_pitch_rad", "truth_yaw_rad"]].to_numpy()
    q = euler_to_quat(att)
    cg = df[["truth_pos_n_m", "truth_pos_e_m", "truth_pos_d_m"]].to_numpy()
    return cg + rotate(q, r.truth_model.hub_offset_body_m), q


def test_truth_wind_is_the_fields_local_wind_at_the_hub(airwake):
    # same seed, same field: re-sampling it at the flown hub pose must give the columns
    # (to the 100 Hz hold), else the truth the scoring uses is not what drove the aircraft
    r, df = airwake
    field = build_wind_field(r.scenario.wind, rng=np.random.default_rng(
        np.random.SeedSequence(21).spawn(1)[0]), ship=r.ship)
    rows = df.iloc[200:2200:100]
    hub, q = _hub_ned(rows, r)
    t_update = np.floor(rows["t_s"].to_numpy() * 100.0 + 1e-9) / 100.0
    again = field.local_wind(t_update, hub, q)
    cols = rows[list(LOCAL_WIND_COLUMNS)].to_numpy()
    assert np.max(np.abs(again[:, :3] - cols[:, :3])) < 0.05
    assert np.max(np.abs(again[:, 3:] - cols[:, 3:])) < 0.05


def test_airwake_mean_and_turbulence_intensity_along_the_flight(airwake):
    r, df = airwake
    sel = df["t_s"].to_numpy() > 3.0
    d = df[sel]
    field = r.pilot_info["wind_description"]
    u_rel = field["relative_wind_speed_m_s"]
    hub, q = _hub_ned(d, r)
    fresh = build_wind_field(r.scenario.wind, rng=np.random.default_rng(0), ship=r.ship)
    mean_body = rotate_inverse(q, fresh.mean_velocity_ned(d["t_s"].to_numpy(), hub))
    v = d[list(LOCAL_WIND_COLUMNS[:3])].to_numpy()
    assert np.allclose(v.mean(0), mean_body.mean(0), atol=0.25)
    # relative to the ship, the wake slows the 3 m/s relative wind but keeps it aft-going
    ship_v = rotate_inverse(q, r.ship.translational_velocity_ned(d["t_s"].to_numpy()))
    rel = (v - ship_v).mean(0)
    assert -u_rel < rel[0] < -0.3 * u_rel
    ti = np.linalg.norm(v.std(0)) / u_rel
    assert 0.05 < ti < 0.45


def test_vortex_shedding_frequency_shows_in_the_wind_spectrum():
    # turbulence turned down so the hangar's shedding tone stands out: St U / H = 0.5 Hz
    r, df = hover_flight(34.0, seed=22, ambient_turbulence_intensity=0.005,
                         shear_turbulence_intensity=0.01, bubble_turbulence_intensity=0.01)
    sel = df["t_s"].to_numpy() > 2.0
    vz = df.loc[sel, "truth_wind_vz_m_s"].to_numpy()
    f, p = welch(vz - vz.mean(), fs=150.0, nperseg=150 * 16)
    band = (f > 0.15) & (f < 3.0)
    peak = f[band][np.argmax(p[band])]
    c = r.scenario.wind
    expected = 0.25 * c["relative_wind_speed_m_s"] / r.scenario.ship.hangar_height_m
    assert peak == pytest.approx(expected, abs=0.08)
