"""Which truth a test flies. The shipped scenarios fly the independent blade-element
airframe with the crossover pilot; a test that needs our own model (a known catalogue
effect, or its own-model figures kept as context) says so with `effect_truth`
(docs/truth-world.md, "Where the effect truth stays, and why")."""

from pathlib import Path

# (model, pilot) of the fixtures' flights: the effect truth (module docstring)
EFFECT_TRUTH = ("effects", "full_state")


def effect_truth(scenario):
    """The scenario (a Scenario, a name or a path) flown by the effect truth and its pilot."""
    from hil_sim.world.scenario import load_scenario

    sc = load_scenario(scenario) if isinstance(scenario, str | Path) else scenario
    model, pilot = EFFECT_TRUTH
    return sc.with_helicopter(model=model, pilot=pilot)
