"""Live progress of a campaign in the terminal: one bar per step with how many of its
tasks are done, running and failed, the elapsed time and an ETA (`airwake.progress`,
rich). Tasks found finished in the store count as done from the start ("cached")."""

from __future__ import annotations

import threading
from collections import Counter

from airwake.progress import Progress

ORDER = ("export", "calibrate", "still_air_net", "estimate", "map", "report", "merge")


class CampaignDisplay:
    """Counts per step, drawn as `airwake.progress.Progress` bars (thread-safe: the
    Dask client reports starts from its own thread)."""

    def __init__(self, totals: dict, cached: dict, enabled: bool = True, stream=None) -> None:
        self._lock = threading.Lock()
        self.counts = {s: Counter(done=cached.get(s, 0), cached=cached.get(s, 0))
                       for s in ORDER if totals.get(s)}
        self.totals = totals
        width = max((len(s) for s in self.counts), default=0)
        self.bars = {s: Progress(f"{s:<{width}}", totals[s], stream=stream, enabled=enabled,
                                 min_interval_s=0.0)
                     for s in self.counts}
        for s in self.counts:
            self._draw(s)

    def _text(self, step: str) -> str:
        c = self.counts[step]
        text = f"{c['done']} done, {c['running']} running, {c['failed']} failed"
        if c["skipped"]:
            text += f", {c['skipped']} skipped"
        if c["cached"]:
            text += f" ({c['cached']} from earlier runs)"
        return text

    def _draw(self, step: str) -> None:
        c = self.counts[step]
        self.bars[step].update(c["done"] + c["failed"] + c["skipped"], self._text(step))

    def started(self, step: str) -> None:
        with self._lock:
            if step in self.counts:
                self.counts[step]["running"] += 1
                self._draw(step)

    def finished(self, record: dict) -> None:
        step = record["step"]
        with self._lock:
            c = self.counts[step]
            ran = not record.get("cached") and record["status"] != "skipped"
            if ran and c["running"] > 0:
                c["running"] -= 1
            c[record["status"]] += 1
            if record.get("cached") and record["status"] == "done":
                c["cached"] += 1
            self._draw(step)

    def close(self) -> None:
        with self._lock:
            for step, bar in self.bars.items():
                c = self.counts[step]
                c["running"] = 0
                bar.finish(self._text(step), done=c["done"] + c["failed"] + c["skipped"])
