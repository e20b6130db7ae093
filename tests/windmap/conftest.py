"""A simulated hand-carried anemometer survey of the two-fan hall, once per session."""

import pytest

from hil_sim.world.anemometer_survey import SurveyConfig

# Smaller than the default survey (165 stations instead of 364; 20 s at each, as in the
# reference), still dense enough for 1.3 x 1.3 x 0.6 m volumes around every station.
TEST_SURVEY = SurveyConfig(x_range_m=(1.0, 6.0), y_range_m=(-0.6, 0.6),
                           heights_d_m=(-1.5, -2.0, -2.5), dwell_s=20.0)


@pytest.fixture(scope="session")
def survey(tmp_path_factory):
    """(FlightTable, path) of the survey written as a flight table (seed 5)."""
    from airwake.record.flight_table import load_flight_table, write_flight_table

    from hil_sim.world.anemometer_survey import survey_table

    df, meta = survey_table(TEST_SURVEY, seed=5)
    path = tmp_path_factory.mktemp("survey") / "survey.parquet"
    write_flight_table(df, path, meta)
    return load_flight_table(path, required=("t_s",)), path


@pytest.fixture(scope="session")
def survey_map(survey):
    """The map of the survey, scored."""
    from airwake.windmap.compensate import compensate
    from airwake.windmap.grid import build_windmap
    from airwake.windmap.report import score_windmap

    table, _ = survey
    wmap = build_windmap(compensate(table.df, table.metadata))
    wmap.score = score_windmap(wmap, table.metadata)
    return wmap
