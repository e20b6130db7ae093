"""The anemometer map of the simulated two-fan survey against the simulator's field
(issue 12 targets: map within 0.2 m/s RMS where sampled; eq 3.15 model error in the
reference's 3-11 % of the source wind, Fig 3.14B)."""

import numpy as np


def test_map_is_within_0_2_m_s_rms_of_the_field_where_sampled(survey_map):
    sc = survey_map.score
    assert sc["sampled_points"] > 500
    for n in ("u_m_s", "v_m_s", "w_m_s"):
        assert sc["map"]["where_sampled"][n]["rms"] < 0.15, (n, sc["map"])
    assert sc["map"]["where_sampled"]["vector_rms_m_s"] < 0.2
    assert sc["map_within_target"]


def test_linear_model_error_sits_in_the_reference_band(survey_map):
    # Fig 3.14B: "most of the modeling error falls in 3-11 %" of 7.24 m/s. Here most grid
    # points are below 11 % and the median inside the band's low end or just under it.
    e = survey_map.model_error["eq_3_15"]
    assert e["fraction_below_11_pct"] > 0.8, e
    assert 1.0 < e["median_pct"] < 11.0, e


def test_linear_model_smooths_the_jets_more_than_the_measured_map(survey_map):
    # the 1.3 m volumes average across jets ~0.5 m wide: eq 3.15's mean flow is further
    # from the field than the measured map (honest, not a target)
    sc = survey_map.score
    m = sc["map"]["where_sampled"]["vector_rms_m_s"]
    assert sc["eq_3_15"]["where_sampled"]["vector_rms_m_s"] > m


def test_grid_is_5_cm_and_parameters_are_finite(survey_map):
    g = survey_map.grid
    xs = np.unique(g["x_m"].to_numpy())
    np.testing.assert_allclose(np.diff(xs), 0.05, atol=1e-9)
    assert np.isfinite(g.drop(columns=["sampled"]).to_numpy(float)).all()
    assert (survey_map.locations["rank12"] == 4).all()


def test_map_stays_within_target_with_a_trackers_pose_errors(survey):
    # what the pose EKF will hand over instead of the truth: 1 deg attitude, 3 cm/s
    # velocity and 1 cm position errors, correlated over ~1 s (Gauss-Markov)
    from airwake.windmap.compensate import compensate
    from airwake.windmap.grid import build_windmap
    from airwake.windmap.report import score_windmap
    from scipy.signal import lfilter

    table, _ = survey
    df = table.df.copy()
    rng = np.random.default_rng(7)

    def slow(sigma, tau_s):
        a = np.exp(-0.01 / tau_s)
        e = rng.standard_normal(len(df)) * sigma * np.sqrt(1 - a * a)
        return lfilter([1.0], [1.0, -a], e)

    for c in ("roll", "pitch", "yaw"):
        df[f"truth_{c}_rad"] += slow(np.radians(1.0), 1.0)
    for c in "uvw":
        df[f"truth_vel_{c}_m_s"] += slow(0.03, 0.3)
    for c in "ned":
        df[f"truth_pos_{c}_m"] += slow(0.01, 1.0)
    wmap = build_windmap(compensate(df, table.metadata))
    sc = score_windmap(wmap, table.metadata)
    assert sc["map"]["where_sampled"]["vector_rms_m_s"] < 0.2, sc["map"]
