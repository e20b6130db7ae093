"""Helpers shared by the truth-world tests (test_world_*, test_hidden_*, test_scenarios*)."""

from __future__ import annotations

import copy
import tomllib

import numpy as np

from hil_sim.world.scenario import SCENARIO_DIR, scenario_from_table


def scenario_table(name: str = "still_air_calibration") -> dict:
    """The merged table of a shipped scenario (after `extends`)."""
    from hil_sim.world.scenario import _read_table

    return _read_table(SCENARIO_DIR / f"{name}.toml")


def short_scenario(base: str = "still_air_calibration", *, segments=None, hidden=None,
                   duration_s: float = 4.0, seed: int = 5, effect_truth: bool = True, **top):
    """A shipped scenario with its script, hidden effects and duration replaced; flown by
    the effect truth and its LQR pilot unless `effect_truth=False` (these tests check the
    truth world's own parts: wind, sensors, hidden effects, the recorded inputs)."""
    t = copy.deepcopy(scenario_table(base))
    if effect_truth:
        t.setdefault("helicopter", {}).update(model="effects", pilot="full_state")
    if segments is not None:
        t["pilot"]["segments"] = segments
    if hidden is not None:
        t["hidden"] = hidden
    t["duration_s"] = duration_s
    t["seed"] = seed
    for key, value in top.items():
        t[key] = value
    return scenario_from_table(t, name=f"test_{base}")


def rms(a) -> float:
    a = np.asarray(a, dtype=float)
    return float(np.sqrt(np.mean(a * a)))


def load_toml(path) -> dict:
    with open(path, "rb") as fh:
        return tomllib.load(fh)
