"""What the smoother's intervals miss on still air joins every later estimate's std: a
calibrated spec carries, per wind component, the error its estimate made beyond its
posterior std on the still-air flight it was fitted on (`[calibration.
still_air_wind_error]`, plain and anchored), and the smoother's std grows by exactly that
in quadrature; the estimate itself does not move."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from airwake.cli import main
from airwake.estimate.errors import WindEstimationError
from airwake.estimate.wind import (
    STILL_AIR_BIAS_KEY,
    STILL_AIR_KEY,
    WIND_NAMES,
    estimate_wind,
    excess_error,
    still_air_wind_error,
)
from airwake.heli import load_model, save_spec, spec_calibration
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

FINITE = st.floats(-5.0, 5.0, allow_nan=False)
POSITIVE = st.floats(0.01, 3.0, allow_nan=False)


def table(t, est, std):
    cols = {"t_s": t}
    for j, n in enumerate(WIND_NAMES):
        cols[n] = est[:, j]
        cols[f"{n}_std"] = std[:, j]
    return pd.DataFrame(cols)


@settings(max_examples=60, deadline=None)
@given(arrays(float, (40, 6), elements=FINITE), arrays(float, (40, 6), elements=POSITIVE),
       arrays(float, (40, 6), elements=FINITE))
def test_the_excess_is_what_the_std_lacks_to_hold_the_errors_mean_square(est, std, truth):
    t = np.arange(40) * 0.1
    df = table(t, est, std)
    g = np.asarray(excess_error(df, truth, burn_in_s=1.0))
    keep = t >= 1.0
    e2 = np.mean((est - truth)[keep] ** 2, axis=0)
    s2 = np.mean(std[keep] ** 2, axis=0)
    assert np.all(g >= 0)
    # widened by it, the std's mean square holds the error's exactly where it fell short
    np.testing.assert_allclose(np.maximum(e2, s2), s2 + g**2, rtol=1e-9, atol=1e-12)
    # no truth: the error is the estimate itself (still air)
    np.testing.assert_allclose(excess_error(df, None, 1.0),
                               excess_error(df, np.zeros_like(est), 1.0))


def test_nan_samples_are_left_out_and_a_component_with_none_adds_nothing():
    t = np.arange(30) * 0.1
    est, std = np.full((30, 6), 0.5), np.full((30, 6), 0.1)
    est[:, 5] = np.nan
    est[5, 0] = np.nan
    g = excess_error(table(t, est, std), burn_in_s=0.0)
    np.testing.assert_allclose(g[:5], np.sqrt(0.25 - 0.01))
    assert g[5] == 0.0


def spec_with(path, excess):
    save_spec(load_model("table52"), path, description="test",
              calibration={"flight": "x", STILL_AIR_KEY: excess})
    return path


def test_the_std_grows_by_exactly_the_still_air_error_and_the_estimate_not(
        tiny_wind_file, tmp_path):
    plain_g = [0.3, 0.0, 0.1, 0.2, 0.05, 0.4]
    anchored_g = [0.0, 0.0, 0.0, 0.5, 0.25, 0.15]
    spec = spec_with(tmp_path / "g.toml", {"smoother": plain_g, "anchored": anchored_g})
    bare = tmp_path / "bare.toml"
    save_spec(load_model("table52"), bare, description="test", calibration={"flight": "x"})
    ref = estimate_wind(tiny_wind_file, bare, em_passes=2)
    anchor = ref.df.copy()
    for g, kw in ((plain_g, {}), (anchored_g, {"anchor": anchor})):
        before = ref if not kw else estimate_wind(tiny_wind_file, bare, em_passes=2, **kw)
        after = estimate_wind(tiny_wind_file, spec, em_passes=2, **kw)
        assert after.metadata[STILL_AIR_KEY] == g
        assert before.metadata[STILL_AIR_KEY] is None
        for j, n in enumerate(WIND_NAMES):
            np.testing.assert_array_equal(after.df[n], before.df[n])
            np.testing.assert_allclose(after.df[f"{n}_std"],
                                       np.hypot(before.df[f"{n}_std"], g[j]), rtol=1e-12)


def test_an_anchor_gap_takes_the_plain_entry(tiny_wind_file, tmp_path):
    plain_g = [0.3, 0.2, 0.1, 0.2, 0.05, 0.4]
    anchored_g = [0.0, 0.0, 0.0, 0.5, 0.25, 0.15]
    spec = spec_with(tmp_path / "g.toml", {"smoother": plain_g, "anchored": anchored_g})
    bare = tmp_path / "bare.toml"
    save_spec(load_model("table52"), bare, description="test", calibration={"flight": "x"})
    anchor = estimate_wind(tiny_wind_file, bare, em_passes=1).df.copy()
    t = anchor["t_s"].to_numpy()
    hole = (t > t[0] + 0.6) & (t < t[0] + 1.2)
    anchor.loc[hole, "wind_vx_m_s"] = np.nan
    before = estimate_wind(tiny_wind_file, bare, em_passes=1, anchor=anchor)
    after = estimate_wind(tiny_wind_file, spec, em_passes=1, anchor=anchor)
    gap = np.isin(after.df["t_s"].to_numpy(), t[hole])
    assert gap.sum() > 5 and after.metadata["still_air_wind_error_plain_rows"] == gap.sum()
    for j, n in enumerate(WIND_NAMES):
        want = np.hypot(before.df[f"{n}_std"], np.where(gap, plain_g[j], anchored_g[j]))
        np.testing.assert_allclose(after.df[f"{n}_std"], want, rtol=1e-12)


def test_a_bad_still_air_table_is_refused_naming_it(tiny_wind_file, tmp_path):
    spec = spec_with(tmp_path / "bad.toml", {"smoother": [0.1, 0.2, 0.3],
                                             "anchored": [0.0] * 6})
    with pytest.raises(WindEstimationError, match=r"bad\.toml: \[calibration\.still_air_"
                       r"wind_error\] smoother = \[0\.1, 0\.2, 0\.3\]"):
        estimate_wind(tiny_wind_file, spec, em_passes=1)
    spec = spec_with(tmp_path / "flat.toml", [0.1] * 6)
    with pytest.raises(WindEstimationError, match="flat.toml.*expected a table"):
        estimate_wind(tiny_wind_file, spec, em_passes=1)
    spec = spec_with(tmp_path / "neg.toml", {"smoother": [0.1] * 6,
                                             "anchored": [0.1, -0.2, 0, 0, 0, 0]})
    ref = estimate_wind(tiny_wind_file, "table52", em_passes=1)
    with pytest.raises(WindEstimationError, match=r"still_air_wind_error\] anchored"):
        estimate_wind(tiny_wind_file, spec, em_passes=1, anchor=ref.df)


def test_calibrate_writes_what_its_estimate_misses_on_the_flight(tiny_wind_file, tmp_path,
                                                                 capsys):
    out = tmp_path / "cal.toml"
    assert main(["calibrate", str(tiny_wind_file), "--model", "table52", "--max-nfev", "3",
                 "--params", "fuselage.cx_m2", "--out", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    cal = spec_calibration(out)
    # beside it, the plain estimate's steady error there and the channels that make it
    bias = cal[STILL_AIR_BIAS_KEY]
    assert report[STILL_AIR_BIAS_KEY] == bias
    assert set(bias["by_channel"]) == set(WIND_NAMES)
    assert all(len(v) == 6 for v in bias["by_channel"].values())
    np.testing.assert_allclose(bias["explained"], [sum(bias["by_channel"][n])
                                                   for n in WIND_NAMES], rtol=1e-9)
    written = cal[STILL_AIR_KEY]
    assert set(written) == {"smoother", "anchored"}
    for v in written.values():
        assert len(v) == 6 and all(x >= 0 for x in v)
    # the same measurement again, from the spec as written (its own entry left out; with
    # no table given, the spec's own: its model_error_std and _offset apply)
    again = still_air_wind_error(out, tiny_wind_file)
    np.testing.assert_allclose(again["smoother"], written["smoother"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(again["anchored"], written["anchored"], rtol=1e-9, atol=1e-12)
    # this flight is not still air (its wind is the error): the plain estimate's excess
    # is large on the components the flight's wind moves
    assert max(written["smoother"]) > 0.05
    # and the estimate with the spec carries it
    est = estimate_wind(tiny_wind_file, out, em_passes=1)
    assert est.metadata[STILL_AIR_KEY] == written["smoother"]
