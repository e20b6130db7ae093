"""The air velocities a wind net was trained over (`airwake.nets.air_envelope`): joint
cells, flown long enough, and the share of a flight inside them."""

import json

import numpy as np
import pytest
from airwake.nets.air_envelope import CELL_M_S, air_envelope, inside_share
from hypothesis import given, settings
from hypothesis import strategies as st

RATE = 150.0


def _hold(points, seconds):
    """Rows holding each air velocity of `points` for `seconds` at RATE."""
    return np.repeat(np.asarray(points, float), int(seconds * RATE), axis=0)


@settings(max_examples=50)
@given(st.lists(st.tuples(*[st.floats(-8, 8)] * 3), min_size=1, max_size=6),
       st.tuples(*[st.floats(-0.24, 0.24)] * 3))
def test_held_states_and_their_neighbours_are_inside_far_ones_are_not(points, nudge):
    env = json.loads(json.dumps(air_envelope(_hold(points, 1.5), RATE)))  # JSON-safe
    assert inside_share(env, np.asarray(points)) == 1.0
    # less than one cell away: still inside
    assert inside_share(env, np.asarray(points) + np.asarray(nudge)) == 1.0
    # more than two cells from every flown state along an axis: outside
    far = np.asarray(points).max(axis=0) + (2.5 * CELL_M_S, 0.0, 0.0)
    far[1:] = np.asarray(points)[0, 1:]
    assert inside_share(env, far[None]) == 0.0


def test_it_is_joint_and_counts_only_what_was_held():
    # 3 m/s forward, and 1.5 m/s sideways, each flown alone: both together is not
    rows = np.concatenate([_hold([(3.0, 0.0, 0.0)], 2.0), _hold([(0.0, 1.5, 0.0)], 2.0),
                           _hold([(-2.0, -2.0, 0.0)], 0.1)])  # passed through, not held
    env = air_envelope(rows, RATE)
    assert inside_share(env, np.array([[3.0, 0.0, 0.0], [0.0, 1.5, 0.0]])) == 1.0
    assert inside_share(env, np.array([[3.0, 1.5, 0.0]])) == 0.0
    assert inside_share(env, np.array([[-2.0, -2.0, 0.0]])) == 0.0
    assert inside_share(env, np.array([[3.0, 0.0, 0.0], [3.0, 1.5, 0.0]])) == 0.5
    # non-finite rows are no samples; none at all is no share
    assert inside_share(env, np.array([[np.nan, 0.0, 0.0], [3.0, 0.0, 0.0]])) == 1.0
    assert np.isnan(inside_share(env, np.full((2, 3), np.nan)))


def test_bad_input_is_named():
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        air_envelope(np.zeros((5, 2)), RATE)
    with pytest.raises(ValueError, match="rate"):
        air_envelope(np.zeros((5, 3)), 0.0)
