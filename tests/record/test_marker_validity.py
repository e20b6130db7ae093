"""`marker_valid` says where the tracked pose is a measurement (issue 22): near a LOSA
update the filter accepted, not merely near a triangulation; not where the filter fights
the LOSA (many frames gated) or has just jumped (a re-acquisition)."""

from types import SimpleNamespace

import numpy as np
from airwake.record.marker_pose import losa_aided


def _track(outcomes: dict[float, str], unresolved=()):
    t = np.array(sorted(outcomes))
    return SimpleNamespace(losa_t_s=t, losa_outcome=np.array([outcomes[x] for x in t]),
                           unresolved_t_s=np.asarray(unresolved, float))


def test_marker_is_valid_only_where_the_filter_accepted_and_agreed_with_the_losa():
    frames = {}
    rate = 1 / 320
    for k in range(int(10 / rate)):
        t = round(k * rate, 6)
        if 2.0 <= t < 3.0:
            continue  # out of view: no frame at all
        if 4.0 <= t < 5.0:
            frames[t] = "accepted" if k % 2 else "gated"  # the track fights the LOSA
        elif 6.0 <= t < 7.0:
            frames[t] = "missing"  # triangulations the filter never used
        else:
            frames[t] = "accepted"
    frames[8.5] = "reacquired"
    track = _track(frames, unresolved=[t for t in frames if 9.5 <= t < 9.8])
    rows = np.arange(0.0, 10.0, 1 / 150)
    ok = losa_aided(track, rows)

    def at(a, b):
        return ok[(rows >= a) & (rows < b)]

    assert at(0.3, 1.7).all() and at(5.3, 5.7).all() and at(7.3, 7.9).all()
    assert not at(2.3, 2.7).any()  # out of view
    assert not at(4.3, 4.7).any()  # half the frames gated: not following the marker
    assert not at(6.3, 6.7).any()  # frames never accepted
    assert not at(8.1, 8.9).any()  # a re-acquisition jumped the state
    assert not at(9.5, 9.8).any()  # an open ambiguous slot choice
    # a stray gated frame (an LED switch) does not invalidate its neighbours
    frames[1.0] = "gated"
    assert losa_aided(_track(frames), rows)[(rows > 0.8) & (rows < 1.2)].all()
