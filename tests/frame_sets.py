"""Frame identities shared by the daemon and SIL test harnesses (importable from any test
directory: pyproject puts tests/ on pytest's pythonpath)."""

from __future__ import annotations

from airwake.link.messages import BOARD_IDS, BY_NAME


def recorded_frames(rec) -> set[tuple[int, int, int, int]]:
    """(origin, msg_id, seq, board_time_us) of every decoded frame in a recording."""
    out = set()
    topics = [t for t in rec.decoded_topics() if not t.startswith("/host/")]
    for topic, t in rec.tables(topics).items():
        board, name = topic.strip("/").split("/")
        origin, mid = BOARD_IDS[board], BY_NAME[name].id
        out.update(zip([origin] * len(t), [mid] * len(t), t.rows["seq"].tolist(),
                       t.rows["board_time_us"].tolist(), strict=True))
    return out
