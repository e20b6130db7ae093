"""`airwake.calibrate.sequence`: the commands each step runs, as a user types them, and
what it keeps (the commands' own work is tested where they live)."""

import pytest
from airwake.calibrate.sequence import discrepancy_step, steady_step


def _diagnosis(kind="effect", effect="advance_torque"):
    return {"verdict": {"kind": kind, "effect": effect, "text": f"verdict {effect}"},
            "candidates": [{"effect": effect, "explained": 0.26, "significant": True,
                            "testable": True}]}


class _Commands:
    """Answers `airwake model diagnose` / `model add` with canned JSON, keeping the calls."""

    def __init__(self, diagnosis, worse=()):
        self.calls, self.diagnosis, self.worse = [], diagnosis, list(worse)

    def __call__(self, *args):
        self.calls.append(args)
        if args[1] == "diagnose":
            return self.diagnosis
        return {"worse_channels": self.worse, "before": {"rdot": 0.39},
                "after": {"rdot": 0.27}}


def test_the_steady_step_fits_on_the_legs_and_measures_the_misfit_on_the_calibration_flight():
    run = _Commands(_diagnosis())
    step = steady_step("cruise.parquet", "cyc.toml", "wind.toml", "still.parquet", run=run)
    assert run.calls[0] == ("model", "diagnose", "cruise.parquet", "--model", "cyc.toml",
                            "--no-sindy", "--refine", "4", "--json")
    assert run.calls[1] == ("model", "add", "advance_torque", "--data", "cruise.parquet",
                            "--model", "cyc.toml", "--out", "wind.toml", "--misfit-on",
                            "still.parquet", "--json")
    assert step["model"] == "wind.toml" and step["added"] == "advance_torque"
    assert step["ranked"] == "advance_torque 26 % (significant)"


def test_the_first_step_measures_the_misfit_where_it_fits():
    run = _Commands(_diagnosis(effect="advance_cyclic"))
    discrepancy_step("still.parquet", "cal.toml", "cyc.toml", run=run)
    assert "--misfit-on" not in run.calls[1]


@pytest.mark.parametrize("kind", ["calibrate", "wind", "none"])
def test_a_verdict_with_no_effect_keeps_the_model(kind):
    run = _Commands(_diagnosis(kind=kind, effect=None))
    step = steady_step("cruise.parquet", "cyc.toml", "wind.toml", "still.parquet", run=run)
    assert step["model"] == "cyc.toml" and step["added"] is None and len(run.calls) == 1
    assert kind in step["why"]


def test_an_effect_that_makes_a_channel_worse_is_not_kept():
    run = _Commands(_diagnosis(), worse=["pdot"])
    step = steady_step("cruise.parquet", "cyc.toml", "wind.toml", "still.parquet", run=run)
    assert step["model"] == "cyc.toml" and step["added"] is None
    assert "pdot" in step["why"]
