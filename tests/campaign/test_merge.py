"""The merged map's maths (campaign/merge.py): time-weighted means, an uncertainty that
shrinks with data and inflates where flights disagree, turbulence as the total variance."""

import math

import numpy as np
import pandas as pd
from airwake.campaign.merge import COMPONENTS, merge_cells, score_cells, spread_name, std_name
from airwake.campaign.spec import Grid
from hypothesis import given, settings
from hypothesis import strategies as st


def cell(ix=-5, iy=0, iz=-3, seconds=4.0, mean=(3.0, 0.2, -0.1), std=0.1, sigma=0.3,
         truth=None):
    row = {"ix": ix, "iy": iy, "iz": iz, "samples": int(seconds * 15), "seconds": seconds,
           "ti": 0.1, "speed_m_s": float(np.linalg.norm(mean))}
    for j, name in enumerate(COMPONENTS):
        row[name] = mean[j] if j < 3 else 0.01 * j
        row[std_name(name)] = std
    for name in ("sigma_u_m_s", "sigma_v_m_s", "sigma_w_m_s"):
        row[name] = sigma
    if truth is not None:
        for j, name in enumerate(COMPONENTS):
            row[f"truth_{name}"] = truth[j] if j < 3 else 0.0
    return pd.DataFrame([row])


def test_one_flight_merges_to_itself():
    m = merge_cells({"a": cell()}, {"a": 3.0}).iloc[0]
    assert m["u_m_s"] == 3.0 and math.isclose(m["u_std_m_s"], 0.1)
    assert math.isclose(m["sigma_u_m_s"], 0.3) and m["disagreement"] == 0.0
    assert m["flights"] == 1 and m["seconds"] == 4.0
    assert math.isclose(m["ti"], 0.3 / 3.0)


@settings(max_examples=30, deadline=None)
@given(k=st.integers(2, 12), std=st.floats(0.01, 1.0), seconds=st.floats(0.1, 30.0))
def test_agreeing_flights_shrink_the_uncertainty_as_one_over_root_k(k, std, seconds):
    m = merge_cells({f"f{i}": cell(std=std, seconds=seconds) for i in range(k)}).iloc[0]
    assert math.isclose(m["u_std_m_s"], std / math.sqrt(k), rel_tol=1e-9)
    assert m["u_spread_m_s"] < 1e-12 and m["disagreement"] < 1e-9
    assert math.isclose(m["sigma_u_m_s"], 0.3, rel_tol=1e-9)  # no spread added
    assert math.isclose(m["seconds"], k * seconds)


def test_disagreeing_flights_inflate_the_uncertainty_by_their_scatter():
    # two flights 1 m/s apart, each claiming 0.1 m/s: chi2/(k-1) = 50, Birge ratio ~7.1
    m = merge_cells({"a": cell(mean=(2.5, 0, 0)), "b": cell(mean=(3.5, 0, 0))}).iloc[0]
    s_int = 0.1 / math.sqrt(2)
    assert math.isclose(m["u_m_s"], 3.0)
    assert math.isclose(m["u_std_m_s"], s_int * math.sqrt(50.0), rel_tol=1e-9)
    assert math.isclose(m["u_spread_m_s"], 0.5)
    # turbulence: each flight's own variance plus the spread of their means
    assert math.isclose(m["sigma_u_m_s"], math.sqrt(0.3**2 + 0.5**2))
    assert m["disagreement"] > 1  # flights disagree beyond their own errors
    # v and w agree: not inflated
    assert math.isclose(m["v_std_m_s"], s_int)


def test_time_weights_the_mean_and_its_error():
    m = merge_cells({"long": cell(seconds=9.0, mean=(3.0, 0, 0), std=0.05),
                     "short": cell(seconds=1.0, mean=(3.1, 0, 0), std=0.2)}).iloc[0]
    assert math.isclose(m["u_m_s"], 0.9 * 3.0 + 0.1 * 3.1)
    s_int = math.sqrt((9 * 0.05) ** 2 + (1 * 0.2) ** 2) / 10
    chi2 = (3.0 - m["u_m_s"]) ** 2 / 0.05**2 + (3.1 - m["u_m_s"]) ** 2 / 0.2**2
    assert math.isclose(m["u_std_m_s"], s_int * max(1.0, math.sqrt(chi2)), rel_tol=1e-9)


@settings(max_examples=40, deadline=None)
@given(means=st.lists(st.floats(-5, 5), min_size=1, max_size=8),
       secs=st.lists(st.floats(0.05, 20), min_size=8, max_size=8),
       stds=st.lists(st.floats(0.01, 2), min_size=8, max_size=8))
def test_merged_mean_lies_among_the_flights_and_its_std_never_below_the_internal(means,
                                                                                  secs, stds):
    tables = {f"f{i}": cell(seconds=secs[i], mean=(m, 0, 0), std=stds[i])
              for i, m in enumerate(means)}
    r = merge_cells(tables).iloc[0]
    assert min(means) - 1e-9 <= r["u_m_s"] <= max(means) + 1e-9
    w = np.array(secs[:len(means)])
    s_int = math.sqrt(float(np.sum(w**2 * np.array(stds[:len(means)]) ** 2))) / w.sum()
    assert r["u_std_m_s"] >= s_int * (1 - 1e-9)
    assert r["sigma_u_m_s"] >= 0.3 * (1 - 1e-9)  # the flights' own turbulence, at least
    assert r[spread_name("u_m_s")] >= 0


def test_cells_are_kept_apart_and_the_deck_area_scored_against_the_truth():
    grid = Grid()
    a = pd.concat([cell(ix=-5, seconds=3.0, truth=(3.1, 0.2, -0.1)),
                   cell(ix=-20, seconds=3.0, truth=(3.0, 0.2, -0.1))])  # -20: off the deck
    b = cell(ix=-5, seconds=0.5, truth=(3.1, 0.2, -0.1))
    merged = merge_cells({"a": a, "b": b})
    assert len(merged) == 2
    s = score_cells(merged, grid)
    assert s["deck_cells"] == 96 and s["deck_cells_covered"] == 1
    assert math.isclose(s["deck_coverage"], 1 / 96)
    assert math.isclose(s["field_rms_deck"]["u_m_s"], 0.1)  # 3.0 estimated, 3.1 true
    assert s["cells_with_enough_data"] == 2
