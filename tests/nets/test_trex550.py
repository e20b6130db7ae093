"""The real T-REX 550 flight (../shared/peers/trex550, a Pixhawk log with only normalised
sticks, rates and attitude; NaN elsewhere): the loader takes the partial table as it is,
and a net trained on its hover (touchdown cut off) is scored on held-out blocks.
Skipped where the shared folder is absent; nothing is copied into the repository."""

from pathlib import Path

import numpy as np
import pytest
from airwake.nets import AdamWConfig, evaluate_net, load_net_flight, train_net

TREX = Path(__file__).resolve().parents[2].parent / "shared" / "peers" / "trex550"
TABLE = TREX / "flight_table_tested.csv"
pytestmark = pytest.mark.skipif(not TABLE.is_file(), reason=f"{TABLE} not present")


def test_partial_real_table_loads_from_normalised_sticks():
    f = load_net_flight(TABLE)
    assert f.input_source == "rc_norm" and 120 < f.rate_hz < 125
    assert len(f) > 13000 and np.all(np.isfinite(f.rates_rad_s))


def test_rate_net_on_the_hover_beats_persistence_on_held_out_blocks():
    # the gyro's sample-to-sample noise is about as large as the rates: repeating the
    # previous sample doubles its variance, a net that averages it must do better
    flight = load_net_flight(TABLE).crop(32.0, 100.0)  # in the air: before the touchdown
    net = train_net([flight], target="rates", seed=0, adamw=AdamWConfig(max_epochs=40))
    rep = evaluate_net(net, [flight])
    test = rep["overall"]["measured"]
    assert rep["flights"][0]["scored"].startswith("test blocks") and rep["overall"]["rows"] > 1000
    for axis in "pqr":
        assert test["net"][axis]["rms"] < test["persistence"][axis]["rms"]
