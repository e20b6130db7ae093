"""Fixtures shared across the test areas: the documented calibration and truth-world
flights for the wind tests (made once per session, shared by the xdist workers).

The shipped scenarios fly the blade-element truth by default; these fixtures fly the
effect truth (`truths.effect_truth`: our own model with its LQR pilot), said here once:
the tests that use them check the estimators' and nets' mechanics, and their own-model
figures are "our own model" context (docs/truth-world.md, "Where the effect truth stays,
and why"). Accuracy on the blade-element truth is tested where a test flies it by name."""

import pytest
from airwake.record.flight_table import write_flight_table
from hypothesis import settings
from truths import effect_truth

# Property tests assert properties, not speed (speed is `airwake bench`'s): no per-example
# deadline, which a loaded 2-core machine misses (a ship-frame round trip took 429 ms of
# hypothesis's default 200 under the parallel suite)
settings.register_profile("airwake", deadline=None)
settings.load_profile("airwake")


def _shared_dir(tmp_path_factory):
    base = tmp_path_factory.getbasetemp()
    root = base.parent if base.name.startswith("popen-gw") else base
    d = root / "wind-shared"
    d.mkdir(exist_ok=True)
    return d


def _once(tmp_path_factory, name: str, make):
    """The file `name`, made by make(path) exactly once across the xdist workers."""
    import fcntl

    d = _shared_dir(tmp_path_factory)
    path = d / name
    with open(d / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not path.exists():
            tmp = d / f".{name}.tmp{path.suffix}"
            make(tmp)
            tmp.rename(path)
    return path


@pytest.fixture(scope="session")
def wind_baseline(tmp_path_factory):
    """The documented calibration (docs/calibration.md, docs/wind-estimation.md): the
    still-air calibration flight, `airwake calibrate` from Table 5.2 on 24 windows."""
    from airwake.calibrate import calibrate
    from airwake.heli import save_spec

    def make(path):
        flight = _once(tmp_path_factory, "still_air_calibration.parquet",
                       lambda p: _sim("still_air_calibration", None, None, p))
        res = calibrate(flight, model="table52", max_windows=24)
        from airwake.calibrate.commands import calibration_table

        save_spec(res.model, path, description="test baseline",
                  calibration=calibration_table(res, flight, "table52"))

    return _once(tmp_path_factory, "baseline.toml", make)


def _sim(scenario, seed, duration, path):
    from hil_sim.world.run import run_scenario

    built = run_scenario(effect_truth(scenario), seed=seed, duration_s=duration).flight_table()
    write_flight_table(built.df, path, built.metadata)


@pytest.fixture(scope="session")
def truth_world_flight(tmp_path_factory):
    """Factory: (scenario, seed, duration_s) -> path of its truth-world flight table."""

    def get(scenario: str, seed: int, duration_s: float):
        name = f"{scenario}-{seed}-{duration_s:g}.parquet"
        return _once(tmp_path_factory, name, lambda p: _sim(scenario, seed, duration_s, p))

    return get


@pytest.fixture(scope="session")
def shared_path(tmp_path_factory):
    """Factory: (name, make) -> the file or directory `name`, made by make(path) exactly
    once across the xdist workers."""
    return lambda name, make: _once(tmp_path_factory, name, make)
