"""Progress bars (airwake/progress.py, on rich): the call shape every loop uses, bars that
share a stream, nothing written when disabled, the campaign's per-step counts."""

import io

from airwake.campaign.display import CampaignDisplay
from airwake.progress import Progress


def test_two_bars_on_one_stream_print_their_final_state_once_both_finish():
    out = io.StringIO()  # not a terminal: rich prints the final state, no redraws
    a = Progress("sil ship", 10.0, " s", stream=out, min_interval_s=0.0)
    b = Progress("truth world", 4.0, " s", stream=out, min_interval_s=0.0)
    for i in range(5):
        a.update(i, f"frame {i}")
        b.update(i / 2)
    b.finish()
    assert out.getvalue() == ""  # a is still running
    a.finish("11.2 x real time")
    lines = out.getvalue().splitlines()
    assert len(lines) == 2
    assert lines[0].startswith("sil ship") and "10/10 s" in lines[0]
    assert "11.2 x real time" in lines[0]
    assert lines[1].startswith("truth world") and "4/4 s" in lines[1]


def test_disabled_bar_writes_nothing_and_accepts_the_calls():
    out = io.StringIO()
    p = Progress("quiet", 3, stream=out, enabled=False)
    p.update(1, "x")
    p.finish("done")
    assert out.getvalue() == ""


def test_campaign_display_counts_done_running_failed_and_earlier_results():
    out = io.StringIO()
    d = CampaignDisplay({"estimate": 4, "map": 4}, {"estimate": 1}, stream=out)
    for _ in range(3):
        d.started("estimate")
    d.finished({"step": "estimate", "status": "done"})
    d.finished({"step": "estimate", "status": "failed"})
    assert d._text("estimate") == "2 done, 1 running, 1 failed (1 from earlier runs)"
    d.finished({"step": "map", "status": "skipped"})
    d.close()
    text = out.getvalue()
    assert "estimate" in text and "3/4" in text  # 2 done + 1 failed of 4
    assert "1 skipped" in text
