"""`airwake windmap RECORDING`: a recording lacking what the map needs is refused in one
line naming it (the export itself is tested in tests/record)."""

import pandas as pd
import pytest
from airwake.record.flight_builder import BuiltFlight
from airwake.windmap.commands import _checked_export
from airwake.windmap.errors import WindMapError

STREAMS = {"marker/imu": 10, "losa/losa_peaks": 10}


def test_recording_without_anemometer_names_the_stream():
    built = BuiltFlight(pd.DataFrame({"t_s": [0.0, 1.0], "marker_pos_n_m": [0.0, 0.0]}),
                        {"streams": STREAMS})
    with pytest.raises(WindMapError, match="no marker/anemometer frames") as e:
        _checked_export("REC", built)
    assert "\n" not in str(e.value)


def test_recording_without_marker_pose_gives_the_exporters_reason():
    reason = "no marker pose: the recording lacks losa/losa_peaks"
    built = BuiltFlight(pd.DataFrame({"t_s": [0.0], "anemo_u_m_s": [1.0]}),
                        {"streams": STREAMS, "marker_pose": {"reason": reason}})
    with pytest.raises(WindMapError, match="lacks losa/losa_peaks"):
        _checked_export("REC", built)
