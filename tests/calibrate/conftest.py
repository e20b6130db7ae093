"""Model-generated flights shared by the calibration tests (generated once per session)."""

import pytest
from airwake.calibrate.synthetic import NoiseSpec, generate_flight
from airwake.record.flight_table import write_flight_table


@pytest.fixture(scope="session")
def still_air_flight():
    """Table 5.2 helicopter, 4 segments x 10 s at 150 Hz (6004 rows), seed-like noise."""
    return generate_flight("table52", duration_s=10.0, segments=4, seed=7, substeps=2)


@pytest.fixture(scope="session")
def short_flight():
    """3 s, noise-free: for unit checks of the measurement pieces."""
    return generate_flight("table52", duration_s=3.0, seed=3, substeps=2,
                           noise=NoiseSpec.none())


@pytest.fixture(scope="session")
def short_flight_file(tmp_path_factory):
    """A 4 s still-air flight with noise as a Parquet file (for the CLI)."""
    ft = generate_flight("table52", duration_s=4.0, seed=4, substeps=2)
    path = tmp_path_factory.mktemp("flights") / "short.parquet"
    write_flight_table(ft.df, path, ft.metadata)
    return path
