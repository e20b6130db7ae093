"""Model-generated flights with a known wind (Table 5.2 helicopter, seed-like noise)."""

import pytest
from airwake.calibrate.synthetic import WindProfile, generate_flight
from airwake.record.flight_table import write_flight_table

CONSTANT_WIND = (2.0, -1.0, 0.5, 0.1, -0.05, 0.08)


@pytest.fixture(scope="session")
def constant_wind_flight():
    return generate_flight("table52", duration_s=10.0, seed=1, substeps=2,
                           wind=WindProfile.constant(CONSTANT_WIND))


@pytest.fixture(scope="session")
def varying_wind_flight():
    wind = WindProfile.slowly_varying((1.0, -1.0, 0.3, 0.05, -0.05, 0.05),
                                      (1.5, 1.0, 0.4, 0.1, 0.08, 0.1),
                                      period_s=(20, 25, 30, 22, 27, 35))
    return generate_flight("table52", duration_s=20.0, seed=2, substeps=2, wind=wind)


@pytest.fixture(scope="session")
def tiny_wind_flight():
    return generate_flight("table52", duration_s=2.0, seed=5, substeps=2,
                           wind=WindProfile.constant(CONSTANT_WIND))


@pytest.fixture(scope="session")
def tiny_wind_file(tmp_path_factory, tiny_wind_flight):
    path = tmp_path_factory.mktemp("wind") / "tiny.parquet"
    write_flight_table(tiny_wind_flight.df, path, tiny_wind_flight.metadata)
    return path
