"""Progress lines for long-running commands, written to stderr.

On a terminal the line is rewritten in place; otherwise (CI logs, pipes) one line
is printed at most every `min_interval_s` seconds so logs stay short.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO


class Progress:
    """Report `done / total` for a named task, throttled."""

    def __init__(
        self,
        label: str,
        total: float,
        unit: str = "",
        stream: TextIO | None = None,
        min_interval_s: float = 1.0,
        enabled: bool = True,
    ) -> None:
        self.label = label
        self.total = float(total)
        self.unit = unit
        self.stream = stream if stream is not None else sys.stderr
        self.min_interval_s = min_interval_s
        self.enabled = enabled
        self._t0 = time.monotonic()
        self._last = -float("inf")
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def update(self, done: float, extra: str = "") -> None:
        now = time.monotonic()
        if not self.enabled or now - self._last < self.min_interval_s:
            return
        self._last = now
        self._write(done, extra, final=False)

    def finish(self, extra: str = "") -> None:
        if self.enabled:
            self._write(self.total, extra, final=True)

    def _write(self, done: float, extra: str, final: bool) -> None:
        elapsed = time.monotonic() - self._t0
        frac = done / self.total if self.total > 0 else 1.0
        eta = elapsed * (1 - frac) / frac if 0 < frac < 1 else 0.0
        text = (
            f"{self.label}: {done:.6g}/{self.total:.6g}{self.unit} ({100 * frac:5.1f} %)"
            f" {elapsed:6.1f} s elapsed"
        )
        if not final and frac < 1:
            text += f", ~{eta:.0f} s left"
        if extra:
            text += f" — {extra}"
        if self._tty:
            self.stream.write("\r\x1b[2K" + text + ("\n" if final else ""))
        else:
            self.stream.write(text + "\n")
        self.stream.flush()
