"""`airwake sim campaign`'s flight plans: the flights at one heading share the deck area's
stations, and their planned paths give every deck-area cell enough time for a merged map."""

import numpy as np
import pytest
import tomli_w
from airwake.campaign.spec import Grid

from hil_sim.campaign.plan import (
    calibration_scenario,
    flight_scenario,
    plan_flights,
    stations,
    still_air_scenario,
)
from hil_sim.world.pilot import build_reference, pilot_from_dict
from hil_sim.world.scenario import load_scenario


def test_flights_share_out_the_stations_of_each_heading():
    rows = stations()
    assert rows == [x + 0.5 for x in range(-12, 0)]
    flights = plan_flights(7, betas=(0, 15, 30), seed=2)
    assert [f.beta_deg for f in flights].count(0.0) == 3
    for beta in (0.0, 15.0, 30.0):
        mine = [f for f in flights if f.beta_deg == beta]
        flown = sorted(x for f in mine for x in f.stations_x_m)
        assert flown == rows  # each station once per heading
        assert all(2.0 < f.height_m < 3.0 for f in mine)
    assert len({f.seed for f in flights}) == 7
    assert len({f.name for f in flights}) == 7


def test_twelve_flights_at_one_heading_plan_two_seconds_in_every_deck_cell():
    # the plan alone (the pilot's reference path, no flying): the merged map target needs
    # >= 2 s in >= 80 % of the deck area's cells; the plan gives every cell that
    grid = Grid()
    seconds = {}
    for f in plan_flights(12, betas=(0,), seed=5):
        cfg = pilot_from_dict(flight_scenario(f)["pilot"])
        t = np.arange(0.0, flight_scenario(f)["duration_s"], 0.02)
        pos = build_reference(cfg, t, np.random.default_rng(0)).pos_m
        idx = np.floor(pos / np.array([grid.cell_m, grid.cell_m, grid.layer_m])).astype(int)
        for k in map(tuple, idx):
            seconds[k] = seconds.get(k, 0.0) + 0.02
    deck = grid.deck_cells()
    assert min(seconds.get(c, 0.0) for c in deck) >= 2.0


def test_scenarios_load_and_say_what_they_fly(tmp_path):
    f = plan_flights(2, betas=(15,), seed=1)[1]
    table = flight_scenario(f, duration_s=20.0)
    path = tmp_path / "f.toml"
    path.write_text(tomli_w.dumps(table))
    sc = load_scenario(path)
    assert sc.wind["relative_wind_heading_deg"] == 15.0
    assert sc.wind["type"] == "ship_airwake" and sc.ship is not None
    assert sc.duration_s == 20.0 and sc.seed == f.seed
    assert sc.pilot.segments[1].a_m[0] == f.stations_x_m[0]
    # the planned heights are the hub's (what the map bins)
    assert sc.pilot.point == "hub" and sc.pilot.segments[1].a_m[2] == -f.height_m
    cal = tmp_path / "c.toml"
    cal.write_text(tomli_w.dumps(calibration_scenario("heli1", 9, duration_s=30.0)))
    sc = load_scenario(cal)
    assert sc.wind["type"] == "still_air" and sc.seed == 9 and sc.duration_s == 30.0
    # the still-air cruise legs the helicopter's still-air wind net also learns from
    cruise = tmp_path / "s.toml"
    cruise.write_text(tomli_w.dumps(still_air_scenario("heli1", 11)))
    sc = load_scenario(cruise)
    assert sc.wind["type"] == "still_air" and sc.seed == 11 and sc.duration_s == 100.0
    assert sc.helicopter.model == "blade_element"  # the shipped scenario's truth


def test_the_campaign_file_lists_the_still_air_flights_and_anchors_the_estimate():
    from hil_sim.campaign.fly import campaign_file

    table = campaign_file("c", "d", ["heli1", "heli2"])
    assert table["steps"]["run"] == ["calibrate", "still_air_net", "estimate", "map", "report"]
    assert table["helicopters"]["heli2"] == {
        "model": "table52", "calibration": "calibration/calibration_heli2.parquet",
        "still_air": ["calibration/still_air_heli2.parquet"]}
    # without still-air cruise flights: no net, the model's smoother (spec's default)
    table = campaign_file("c", "d", ["heli1"], still_air=False)
    assert "still_air_net" not in table["steps"]["run"]
    assert "still_air" not in table["helicopters"]["heli1"]


def test_truth_helicopter_is_written_only_when_asked():
    f = plan_flights(1, betas=(0,), seed=1)[0]
    assert "helicopter" not in flight_scenario(f)
    # each truth with its pilot (the shipped scenarios name the crossover pilot)
    assert flight_scenario(f, truth="blade_element")["helicopter"] == {
        "model": "blade_element", "pilot": "crossover"}
    assert calibration_scenario("h", 1, truth="effects")["helicopter"] == {
        "model": "effects", "pilot": "full_state"}
    with pytest.raises(ValueError, match="--truth 'wood'"):
        flight_scenario(f, truth="wood")
