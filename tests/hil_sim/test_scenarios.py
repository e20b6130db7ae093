"""Scenario files: every shipped scenario validates; bad files fail with the file, key and value."""

from __future__ import annotations

import pytest
from world_helpers import scenario_table

from hil_sim.world.pilot import script_duration
from hil_sim.world.scenario import (
    ScenarioError,
    find_scenario,
    load_scenario,
    scenario_names,
)

REQUIRED = ("still_air_calibration", "still_air_speed_legs", "still_air_cruise", "fans_indoor",
            "ship_airwake_b0",
            "ship_airwake_b15",
            "hidden_ground_effect", "hidden_lever_arm", "hidden_servo_lag",
            "hidden_rotor_droop", "hidden_dynamic_inflow", "hidden_wake_recirculation",
            "hidden_vibration_rectification", "hidden_input_time_skew")
HIDDEN_OF = {"hidden_ground_effect": ["ground_effect"], "hidden_lever_arm": ["lever_arm"],
             "hidden_servo_lag": ["servo_lag"], "hidden_rotor_droop": ["rotor_droop"],
             "hidden_dynamic_inflow": ["dynamic_inflow"],
             "hidden_wake_recirculation": ["wake_recirculation"],
             "hidden_vibration_rectification": ["vibration_rectification"],
             "hidden_input_time_skew": ["input_time_skew"]}


def write(tmp_path, text: str, name: str = "s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


@pytest.mark.parametrize("name", REQUIRED)
def test_shipped_scenario_loads_and_its_script_fits_its_duration(name):
    # a scenario whose script is longer than its flight would silently lose segments
    sc = load_scenario(name)
    assert name in scenario_names()
    assert sc.rate_hz >= 1000.0
    assert script_duration(sc.pilot) <= sc.duration_s
    assert list(sc.hidden.enabled()) == HIDDEN_OF.get(name, [])


def test_clean_scenarios_have_no_hidden_effect_and_ship_ones_fly_in_the_ship_frame():
    for name in ("still_air_calibration", "fans_indoor"):
        assert load_scenario(name).hidden.enabled() == {}
    for beta, name in ((0.0, "ship_airwake_b0"), (15.0, "ship_airwake_b15")):
        sc = load_scenario(name)
        assert sc.site.type == "ship" and sc.pilot.frame == "ship"
        assert sc.wind["relative_wind_heading_deg"] == beta


def test_shipped_scenarios_fly_the_blade_element_truth_and_hidden_ones_our_own_model(tmp_path):
    # the truth a user's flight of a shipped scenario gets is not our model; a hidden
    # effect is a catalogue effect, so it rides on the effect truth (docs/truth-world.md)
    for name in REQUIRED:
        heli = load_scenario(name).helicopter
        want = (("effects", "full_state") if name in HIDDEN_OF
                else ("blade_element", "crossover"))
        assert (heli.model, heli.pilot) == want, name
    # a file that extends a shipped scenario inherits its truth and pilot
    child = write(tmp_path, 'extends = "ship_airwake_b0"\nseed = 3\n')
    assert load_scenario(child).helicopter.model == "blade_element"
    # and the commands' --truth brings its own pilot (the demo's, the campaign's)
    from hil_sim.boards.demo import truth_arguments

    assert truth_arguments("effects")[-2:] == ["--pilot", "full_state"]


def test_sim_scenarios_lists_who_flies_each(capsys):
    import json

    from airwake.cli import main

    assert main(["sim", "scenarios", "--json"]) == 0
    rows = {r["name"]: r for r in json.loads(capsys.readouterr().out)}
    for name in REQUIRED:
        heli = load_scenario(name).helicopter
        assert (rows[name]["truth"], rows[name]["pilot"]) == (heli.model, heli.pilot)
    assert main(["sim", "scenarios"]) == 0
    line = next(s for s in capsys.readouterr().out.splitlines()
                if s.startswith("ship_airwake_b0 "))
    assert "blade_element crossover" in line


def test_scenario_found_by_path_and_extends_resolves_relative_to_the_file(tmp_path):
    base = write(tmp_path, 'duration_s = 10.0\nseed = 4\n[wind]\ntype = "still_air"\n',
                 "base.toml")
    child = write(tmp_path, 'extends = "base"\nseed = 9\n', "child.toml")
    sc = load_scenario(str(child))
    assert (sc.duration_s, sc.seed) == (10.0, 9)
    assert find_scenario(str(base)) == base.resolve()


def test_extends_merges_tables_and_replaces_lists(tmp_path):
    write(tmp_path, 'extends = "still_air_calibration"\n[[pilot.segments]]\ntype = "hover"\n'
          'duration_s = 2.0\n[sensors]\nvibration_scale = 0.0\n', "c.toml")
    sc = load_scenario(str(tmp_path / "c.toml"))
    parent = load_scenario("still_air_calibration")
    assert len(sc.pilot.segments) == 1 and sc.pilot.start_m == parent.pilot.start_m
    assert sc.sensors.vibration_scale == 0.0
    assert sc.sensors.vn200 == parent.sensors.vn200


@pytest.mark.parametrize("text, needle", [
    ('duraton_s = 3.0\n', "unknown key 'duraton_s'"),
    ('rate_hz = 500.0\n', "rate_hz = 500.0"),
    ('seed = -1\n', "seed = -1"),
    ('[hidden.ground_efect]\n', "unknown hidden effect 'ground_efect'"),
    ('[hidden.servo_lag]\ndamping_ratio = -0.1\n', "hidden.servo_lag: damping_ratio = -0.1"),
    ('[hidden.lever_arm]\nposition = [0, 0, 0]\n', "hidden.lever_arm: unknown key 'position'"),
    ('[wind]\ntype = "tornado"\n', "wind.type = 'tornado'"),
    ('[wind]\ntype = "ship_airwake"\n', "needs site.type = 'ship'"),
    ('[ship]\nspeed_m_s = 2.0\n', "needs site.type = 'ship'"),
    ('[site]\ntype = "moon"\n', "site: type = 'moon'"),
    ('[pilot]\nframe = "ship"\n', "pilot.frame = 'ship'"),
    ('[[pilot.segments]]\ntype = "loop"\n', "pilot.segments[0].type = 'loop'"),
    ('[[pilot.segments]]\ntype = "goto"\nduration_s = 2.0\n', "position_m = None"),
    ('[[pilot.segments]]\ntype = "chirp"\nduration_s = 2.0\nchannel = "throttle"\n',
     "channel = 'throttle'"),
    ('[sensors.vn200]\nrate_hz = -5.0\n', "sensors.vn200: rate_hz = -5.0"),
    ('[sensors]\nvibration_scale = "lots"\n', "sensors.vibration_scale = 'lots'"),
    ('[helicopter.overrides]\nlock_number = 3.0\n', "'effect.parameter'"),
    ('[faults]\nbyte_loss = 0.1\n', "faults: unknown key 'byte_loss'"),
    ('[faults]\nbit_flip_probability = 2.0\n', "bit_flip_probability = 2.0"),
    ('[[faults.resets]]\nboard = "gps"\nat_s = 1.0\n', "faults.resets[0]: board = 'gps'"),
])
def test_bad_scenario_names_file_key_and_value(tmp_path, text, needle):
    p = write(tmp_path, text)
    with pytest.raises(ScenarioError) as err:
        load_scenario(str(p))
    msg = str(err.value)
    assert str(p) in msg and needle in msg


def test_faults_are_accepted_and_validated_for_the_sil_layer(tmp_path):
    p = write(tmp_path, '[faults]\nbyte_loss_probability = 0.01\n[faults.rover]\n'
              'bit_flip_probability = 0.001\n[[faults.unplugs]]\nboard = "losa"\n'
              'at_s = 5.0\nduration_s = 2.0\n[[faults.resets]]\nboard = "base"\nat_s = 8.0\n')
    f = load_scenario(str(p)).faults
    assert f.any
    assert f.link("rover").bit_flip_probability == 0.001
    assert f.link("rover").byte_loss_probability == 0.01
    assert f.link("marker").byte_loss_probability == 0.01
    assert f.unplugs[0].board == "losa" and f.resets[0].at_s == 8.0


def test_missing_scenario_lists_the_shipped_ones():
    with pytest.raises(ScenarioError, match="still_air_calibration"):
        load_scenario("no_such_scenario")


def test_extends_loop_is_an_error(tmp_path):
    write(tmp_path, 'extends = "b"\n', "a.toml")
    write(tmp_path, 'extends = "a"\n', "b.toml")
    with pytest.raises(ScenarioError, match="extends loops"):
        load_scenario(str(tmp_path / "a.toml"))


def test_invalid_toml_names_the_file(tmp_path):
    p = write(tmp_path, "duration_s = = 3\n")
    with pytest.raises(ScenarioError, match="not valid TOML"):
        load_scenario(str(p))


def test_replace_validates_like_the_file():
    sc = load_scenario("still_air_calibration")
    assert sc.replace(duration_s=3.0).duration_s == 3.0
    with pytest.raises(ValueError, match="duration_s"):
        sc.replace(duration_s=-1.0)


def test_scenario_table_helper_matches_loader():
    assert scenario_table("hidden_lever_arm")["hidden"]["lever_arm"]["position_m"] == [
        0.14, 0.03, -0.09]


def test_sim_table_cli_writes_a_loadable_table_and_prints_the_realtime_factor(tmp_path,
                                                                              capsys):
    from airwake.cli import main
    from airwake.record.flight_table import load_flight_table

    out = tmp_path / "flight.csv"
    status = main(["sim", "table", "--scenario", "still_air_calibration", "--duration", "1.5",
                   "--seed", "3", "--out", str(out), "--quiet"])
    assert status == 0
    printed = capsys.readouterr().out
    assert "real-time factor" in printed and str(out) in printed
    ft = load_flight_table(out)
    assert ft.metadata["seed"] == 3 and ft.metadata["scenario"] == "still_air_calibration"
    assert ft.df["t_s"].iloc[-1] > 1.3


def test_sim_table_cli_bad_scenario_is_one_line_and_exit_2(tmp_path, capsys):
    from airwake.cli import main

    bad = tmp_path / "bad.toml"
    bad.write_text("rate_hz = 10.0\n")
    status = main(["sim", "table", "--scenario", str(bad), "--out", str(tmp_path / "f.parquet")])
    err = capsys.readouterr().err
    assert status == 2
    assert "rate_hz = 10.0" in err and str(bad) in err
    assert not (tmp_path / "f.parquet").exists()
    status = main(["sim", "table", "--scenario", "still_air_calibration", "--out",
                   str(tmp_path / "f.txt")])
    assert status == 2 and "unknown flight-table extension" in capsys.readouterr().err


@pytest.mark.parametrize("text, needle", [
    ('[helicopter]\nspec = "table99"\n', "helicopter.spec = 'table99'"),
    ('[helicopter.overrides]\n"main_rotor.lock_numbr" = 3.0\n', "main_rotor.lock_numbr"),
    ('[helicopter.overrides]\n"main_rotor.lock_number" = 99.0\n', "lock_number"),
])
def test_bad_helicopter_spec_or_override_is_a_scenario_error(tmp_path, text, needle):
    p = write(tmp_path, text)
    with pytest.raises(ScenarioError) as err:
        load_scenario(str(p))
    assert str(p) in str(err.value) and needle in str(err.value)
