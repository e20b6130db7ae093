"""The campaign file is refused up front, naming the file, the key and the value; a good one
reads beta, helicopter and day from the flights' metadata."""

import numpy as np
import pandas as pd
import pytest
import tomli_w
from airwake.campaign import CampaignError, load_campaign
from airwake.campaign.spec import Grid
from airwake.record.flight_table import write_flight_table


def _flight(path, meta):
    df = pd.DataFrame({"t_s": np.arange(3) * 0.01, "acc_x_m_s2": np.zeros(3)})
    path.parent.mkdir(parents=True, exist_ok=True)
    write_flight_table(df, path, meta)
    return path


@pytest.fixture
def tree(tmp_path):
    _flight(tmp_path / "f" / "a.parquet",
            {"campaign": {"beta_deg": 15.0, "helicopter": "h1", "day": "d2"}})
    _flight(tmp_path / "f" / "b.csv", {"scenario_config": {"wind": {
        "type": "ship_airwake", "relative_wind_heading_deg": 30.0}}})
    _flight(tmp_path / "cal" / "still.parquet", {})
    _flight(tmp_path / "plain" / "c.parquet", {})
    return tmp_path


def _write(tree, table):
    path = tree / "campaign.toml"
    path.write_text(tomli_w.dumps(table))
    return path


GOOD = {"helicopters": {"h1": {"model": "table52", "calibration": "cal/still.parquet"}},
        "flights": [{"path": "f/*"}]}


def test_good_file_reads_beta_helicopter_and_day_from_metadata(tree):
    camp = load_campaign(_write(tree, GOOD))
    by = {f.name: f for f in camp.flights}
    assert sorted(by) == ["a", "b"]
    assert (by["a"].beta_deg, by["a"].helicopter, by["a"].day) == (15.0, "h1", "d2")
    assert by["b"].beta_deg == 30.0  # a simulated ship flight's relative wind
    assert camp.steps == ("export", "calibrate", "still_air_net", "estimate", "map", "report")
    assert camp.helicopters["h1"].calibration.path == (tree / "cal" / "still.parquet")
    # its still-air flights: the calibration flight only (a net on it is made only when
    # the file names method = "anchored": test below)
    assert [s.path for s in camp.helicopters["h1"].still_air_flights] == [
        tree / "cal" / "still.parquet"]


def test_calibration_flights_are_not_also_flights(tree):
    table = {**GOOD, "flights": [{"path": "*/*.parquet", "beta_deg": 0}]}
    names = [f.name for f in load_campaign(_write(tree, table)).flights]
    assert "still" not in names and sorted(names) == ["a", "c"]


@pytest.mark.parametrize("change, key, value", [
    ({"colour": "red"}, "colour", "'red'"),
    ({"grid": {"cell_m": -1.0}}, "grid.cell_m", "-1.0"),
    ({"grid": {"height_m": [3.0, 2.0]}}, "grid.height_m", "[3.0, 2.0]"),
    ({"steps": {"run": ["estimate", "paint"]}}, "steps.run", "['estimate', 'paint']"),
    ({"steps": {"run": ["calibrate", "map"]}}, "steps.run", "['calibrate', 'map']"),
    ({"steps": {"estimate": {"method": "magic"}}}, "steps.estimate.method", "'magic'"),
    ({"steps": {"estimate": {"method": "net"}}}, "steps.estimate.method", "'net'"),
    ({"steps": {"calibrate": {"max_nfev": 0}}}, "steps.calibrate.max_nfev", "0"),
    ({"steps": {"calibrate": {"max_windows": 2.5}}}, "steps.calibrate.max_windows", "2.5"),
    ({"steps": {"report": {"sindy": "no"}}}, "steps.report.sindy", "'no'"),
    ({"steps": {"map": {"zoom": 2}}}, "steps.map.zoom", "2"),
    ({"helicopters": {"h1": {"model": "table99"}}}, "helicopters.h1.model", "'table99'"),
    ({"helicopters": {"h1": {"calibration": "cal/none.parquet"}}},
     "helicopters.h1.calibration", "'cal/none.parquet'"),
    ({"helicopters": {"h1": {"still_air": "cal/still.parquet"}}},
     "helicopters.h1.still_air", "'cal/still.parquet'"),
    ({"helicopters": {"h1": {"still_air": ["cal/none.parquet"]}}},
     "helicopters.h1.still_air[0]", "'cal/none.parquet'"),
    ({"helicopters": {"h1": {"still_air": ["cal/still.parquet"]}}},
     "helicopters.h1.still_air[0]", "'cal/still.parquet'"),
    ({"steps": {"run": ["calibrate", "estimate"], "estimate": {"method": "anchored"}}},
     "steps.estimate.method", "'anchored'"),
    ({"steps": {"still_air_net": {"max_rows": 10}}}, "steps.still_air_net.max_rows", "10"),
    ({"flights": [{"path": "nothing/*.parquet"}]}, "flights[0].path", "'nothing/*.parquet'"),
    ({"flights": [{"path": "plain/*"}]}, "flights[0].beta_deg", "None"),
    ({"flights": [{"path": "f/a.parquet", "helicopter": "h9"}]}, "flights[0].helicopter",
     "'h9'"),
    ({"flights": [{"path": "f/a.parquet", "beta_deg": "ahead"}]}, "flights[0].beta_deg",
     "'ahead'"),
    ({"flights": [{"path": "f/a.parquet"}, {"path": "f/a.parquet"}]}, "flights[1].path",
     "'f/a.parquet'"),
])
def test_bad_entry_is_refused_naming_file_key_and_value(tree, change, key, value):
    table = {**GOOD, **change}
    if "helicopters" in change:
        table["helicopters"] = {"h1": {**GOOD["helicopters"]["h1"],
                                       **change["helicopters"]["h1"]}}
    path = _write(tree, table)
    with pytest.raises(CampaignError) as err:
        load_campaign(path)
    msg = str(err.value)
    assert msg.startswith(f"{path}: {key} = {value}: "), msg


def test_still_air_flights_feed_the_net_and_set_the_estimate_anchored(tree):
    from airwake.campaign.plan import build_plan
    from airwake.campaign.store import DigestCache

    _flight(tree / "cal" / "cruise.parquet", {})
    table = {"helicopters": {"h1": {"model": "table52", "calibration": "cal/still.parquet",
                                    "still_air": ["cal/cruise.parquet"]}},
             "flights": [{"path": "*/*.parquet", "beta_deg": 0}]}
    camp = load_campaign(_write(tree, table))
    h = camp.helicopters["h1"]
    assert [s.path.name for s in h.still_air_flights] == ["still.parquet", "cruise.parquet"]
    # neither still-air flight is a ship flight
    assert sorted(f.name for f in camp.flights) == ["a", "c"]
    plan = build_plan(camp, DigestCache(tree / "digests"))
    net = plan.by_subject["h1"]["still_air_net"]
    assert plan.task(net).args["flights"] == {
        "flight 0": str(tree / "cal" / "still.parquet"),
        "flight 1": str(tree / "cal" / "cruise.parquet")}
    for f in ("a", "c"):
        est = plan.task(plan.by_subject[f]["estimate"])
        assert est.args["options"]["method"] == "anchored" and est.deps["net"] == net
    # without the step the estimate is the model's smoother, and a named "anchored" is
    # refused for a helicopter that has no still-air flight
    table["steps"] = {"run": ["calibrate", "estimate", "map"]}
    plan = build_plan(load_campaign(_write(tree, table)), DigestCache(tree / "digests"))
    est = plan.task(plan.by_subject["a"]["estimate"])
    assert est.args["options"]["method"] == "smoother" and "net" not in est.deps
    bare = {"helicopters": {"h1": {"model": "table52"}},
            "steps": {"estimate": {"method": "anchored"}},
            "flights": [{"path": "f/*"}]}
    with pytest.raises(CampaignError, match=r"helicopters.h1.still_air = \[\]: .*still-air "
                       "flights"):
        load_campaign(_write(tree, bare))
    # with the default method such a helicopter keeps the smoother
    del bare["steps"]
    plan = build_plan(load_campaign(_write(tree, bare)), DigestCache(tree / "digests"))
    assert "still_air_net" not in plan.by_subject.get("h1", {})
    assert plan.task(plan.by_subject["a"]["estimate"]).args["options"]["method"] == "smoother"
    # and so does one with only its calibration flight (a net on its short legs alone reads
    # part of a headwind), unless the file asks for anchored: then the net is on it
    plan = build_plan(load_campaign(_write(tree, GOOD)), DigestCache(tree / "digests"))
    assert "still_air_net" not in plan.by_subject["h1"]
    asked = {**GOOD, "steps": {"estimate": {"method": "anchored"}}}
    plan = build_plan(load_campaign(_write(tree, asked)), DigestCache(tree / "digests"))
    net = plan.task(plan.by_subject["h1"]["still_air_net"])
    assert net.args["flights"] == {"flight 0": str(tree / "cal" / "still.parquet")}


def test_a_net_and_its_estimates_are_keyed_by_the_still_air_data_and_options(tree):
    # content addressing: what the net learns from and how reach every result that reads
    # it, and nothing else
    from airwake.campaign.plan import build_plan
    from airwake.campaign.store import DigestCache

    cruise = _flight(tree / "cal" / "cruise.parquet", {})
    table = {"helicopters": {"h1": {"model": "table52", "calibration": "cal/still.parquet",
                                    "still_air": ["cal/cruise.parquet"]}},
             "flights": [{"path": "f/*"}]}

    def keys(t):
        plan = build_plan(load_campaign(_write(tree, t)), DigestCache(tree / "d.json"))
        return {step: plan.by_subject[subject][step] for subject, step in (
            ("h1", "calibrate"), ("h1", "still_air_net"), ("a", "estimate"), ("a", "map"))}

    base = keys(table)
    seeded = keys({**table, "steps": {"still_air_net": {"seed": 3}}})
    assert seeded["calibrate"] == base["calibrate"]
    assert all(seeded[k] != base[k] for k in ("still_air_net", "estimate", "map"))
    df = pd.DataFrame({"t_s": np.arange(4) * 0.01, "acc_x_m_s2": np.ones(4)})
    write_flight_table(df, cruise, {})  # other bytes in a still-air flight
    changed = keys(table)
    assert changed["calibrate"] == base["calibrate"]
    assert all(changed[k] != base[k] for k in ("still_air_net", "estimate", "map"))
    # the method is in the estimate's key; with the smoother nothing reads a net: none made
    plan = build_plan(load_campaign(_write(tree, {**table, "steps": {
        "estimate": {"method": "smoother"}}})), DigestCache(tree / "d.json"))
    assert "still_air_net" not in plan.by_subject["h1"]
    assert plan.by_subject["a"]["estimate"] != changed["estimate"]


def test_recordings_need_the_export_step(tree):
    (tree / "rec").mkdir()
    table = {**GOOD, "steps": {"run": ["estimate"]},
             "flights": [{"path": "rec", "beta_deg": 0}]}
    with pytest.raises(CampaignError, match="steps.run .* recordings need the 'export' step"):
        load_campaign(_write(tree, table))


def test_not_toml_and_missing_file_are_one_line_errors(tree):
    (tree / "bad.toml").write_text("flights = [")
    with pytest.raises(CampaignError, match="bad.toml: not valid TOML"):
        load_campaign(tree / "bad.toml")
    with pytest.raises(CampaignError, match="not found"):
        load_campaign(tree / "none.toml")


def test_deck_area_is_the_deck_and_six_metres_aft_two_to_three_metres_up():
    cells = Grid().deck_cells()  # 1 m cells: 12 rows aft of the hangar x 8 across x 1 layer
    assert len(cells) == 96
    assert {c[0] for c in cells} == set(range(-12, 0))
    assert {c[1] for c in cells} == set(range(-4, 4))
    assert {c[2] for c in cells} == {-3}  # z from -3 to -2: 2-3 m above the deck
