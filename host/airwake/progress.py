"""Progress bars for long-running commands: a small adapter over `rich.progress`.

    bar = Progress("sim ship_airwake_b0", total=60.0, unit=" s")
    bar.update(12.5, "ESS 1400")       # done so far, in the units of `total`; extra text
    bar.finish("11.2 x real time")

Loops take any object with `update(done[, extra])` and `finish([extra])` (the simulator,
the estimators, the trainers) and never import rich themselves. Bars on one stream share
one rich live display, so two at once (a SIL run's boards and its truth world) stack
instead of fighting over the line. On a terminal the bars redraw in place with the elapsed
time and an ETA; elsewhere (CI logs, pipes) rich prints their final state once, when the
last bar on the stream has finished (or at exit), so logs stay short.
"""

from __future__ import annotations

import atexit
import sys
import threading
import time
from typing import TextIO

_lock = threading.Lock()
_displays: dict[int, _Display] = {}


class _Display:
    """One rich live display per output stream, alive while any of its bars is open."""

    def __init__(self, stream: TextIO) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, TextColumn, TimeElapsedColumn, TimeRemainingColumn
        from rich.progress import Progress as RichProgress

        self.stream = stream
        self.rich = RichProgress(
            TextColumn("{task.description}"), BarColumn(bar_width=24),
            TextColumn("{task.fields[count]}"), TextColumn("{task.percentage:>5.1f} %"),
            TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
            TextColumn("{task.fields[extra]}"),
            # stdout stays the command's own (a `--json` piped on while stderr is a tty)
            console=Console(file=stream), redirect_stdout=False, redirect_stderr=False)
        self.open = 0
        self.rich.start()

    def close_one(self) -> None:
        self.open -= 1
        if self.open <= 0:
            self.rich.stop()
            _displays.pop(id(self.stream), None)


def _stop_all() -> None:
    with _lock:
        for d in list(_displays.values()):
            d.open = 0
            d.close_one()


atexit.register(_stop_all)


class Progress:
    """Report `done / total` for a named task (updates throttled to `min_interval_s`). The
    bar appears at its first update: one made and dropped (a command that fails before its
    loop starts) leaves no trace."""

    def __init__(self, label: str, total: float, unit: str = "", stream: TextIO | None = None,
                 min_interval_s: float = 0.2, enabled: bool = True) -> None:
        self.label = label
        self.total = float(total)
        self.unit = unit
        self.min_interval_s = min_interval_s
        self.enabled = enabled
        self._stream = stream
        self._last = -float("inf")
        self._display: _Display | None = None
        self._finished = not enabled

    def _count(self, done: float) -> str:
        return f"{done:.6g}/{self.total:.6g}{self.unit}"

    def _show(self) -> _Display | None:
        """The display this bar is on (joined at the first call), None once finished."""
        if self._display is None and not self._finished:
            stream = self._stream if self._stream is not None else sys.stderr
            with _lock:
                display = _displays.get(id(stream))
                if display is None:
                    display = _displays[id(stream)] = _Display(stream)
                display.open += 1
                self._task = display.rich.add_task(self.label, total=max(self.total, 1e-12),
                                                   count=self._count(0.0), extra="")
                self._display = display
        return self._display

    def update(self, done: float, extra: str = "") -> None:
        now = time.monotonic()
        if self._finished or now - self._last < self.min_interval_s:
            return
        self._last = now
        self._show().rich.update(self._task, completed=float(done), count=self._count(done),
                                 extra=extra)

    def finish(self, extra: str = "", done: float | None = None) -> None:
        """The final state: `done` (default: all of `total`) and `extra`."""
        display = self._show()
        if display is None:
            return
        done = self.total if done is None else float(done)
        with _lock:
            display.rich.update(self._task, completed=max(done, 1e-12),
                                count=self._count(done), extra=extra)
            display.close_one()
            self._display = None
            self._finished = True
