"""A flight script's positions can be the rotor hub's (`[pilot] point = "hub"`): the pilot
flies the CG, lower by the airframe's hub height, so the hub — what a wind map bins — flies
the planned height (`airwake sim campaign` plans its sweeps through a layer above the deck
this way)."""

import dataclasses

import numpy as np
import pytest

from hil_sim.world.pilot import PilotConfig, Segment, cg_script, pilot_from_dict
from hil_sim.world.run import run_scenario
from hil_sim.world.scenario import load_scenario


def test_a_hub_script_moves_every_position_down_by_the_hub_height_and_a_cg_one_not():
    cfg = PilotConfig(frame="ship", point="hub", start_m=(1.0, 2.0, -2.5), segments=(
        Segment("hover", duration_s=1.0),
        Segment("sweep", a_m=(0.0, -3.0, -2.25), b_m=(0.0, 3.0, -2.25)),
        Segment("path", waypoints_m=((1.0, 0.0, -3.0), (2.0, 0.0, -2.0))),
        Segment("goto", duration_s=2.0, position_m=(0.0, 0.0, -2.75))))
    hub = np.array([0.01, 0.0, -0.24])  # 0.24 m above the CG (body z is down)
    out = cg_script(cfg, hub)
    assert out.point == "cg" and out.start_m == pytest.approx((1.0, 2.0, -2.26))
    assert out.segments[1].a_m == pytest.approx((0.0, -3.0, -2.01))
    assert out.segments[1].b_m == pytest.approx((0.0, 3.0, -2.01))
    assert [w[2] for w in out.segments[2].waypoints_m] == pytest.approx([-2.76, -1.76])
    assert out.segments[3].position_m == pytest.approx((0.0, 0.0, -2.51))
    assert out.segments[0] == cfg.segments[0]  # no position: as it was
    plain = dataclasses.replace(cfg, point="cg")
    assert cg_script(plain, hub) is plain
    with pytest.raises(ValueError, match="point"):
        pilot_from_dict({"point": "nose"})


@pytest.mark.parametrize("truth", ["blade_element", "effects"])
def test_the_hub_flies_the_planned_height(tmp_path, truth):
    path = tmp_path / "hover.toml"
    path.write_text(f'''
extends = "still_air_calibration"
duration_s = 6.0
[helicopter]
model = "{truth}"
pilot = "{"crossover" if truth == "blade_element" else "full_state"}"
[pilot]
frame = "ned"
point = "hub"
start_m = [0.0, 0.0, -2.5]
[[pilot.segments]]
type = "hover"
duration_s = 6.0
''')
    res = run_scenario(load_scenario(path), seed=3)
    tr = res.truth
    hub = np.asarray(res.truth_model.hub_offset_body_m, float)
    assert hub[2] < -0.1  # the hub is well above the CG on both airframes
    rot = tr.quat_wxyz  # the hub's height from the CG's and the attitude
    from hil_sim.world.kinematics import quat_to_dcm

    hub_z = tr.pos_ned_m[:, 2] + np.einsum("nij,j->ni", quat_to_dcm(rot), hub)[:, 2]
    late = tr.t_s > 2.0
    assert np.mean(-hub_z[late]) == pytest.approx(2.5, abs=0.06)
    assert np.mean(-tr.pos_ned_m[late, 2]) == pytest.approx(2.5 + hub[2], abs=0.06)
