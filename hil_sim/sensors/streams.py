"""What a simulated device emits: time-stamped byte chunks or logic edges.

`ByteStream` carries packets (VN200 binary, SBP frames, ASCII lines) with the time
each one starts leaving the device; `EdgeStream` carries rising/falling edges on
numbered input pins (RC PWM, tail-servo PWM, rotor IR pulses). The boards layer feeds
these to the native firmware through its HAL (bytes paced at `baud`, edges as
input-capture events).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

UART_BITS_PER_BYTE = 10  # 8N1: start + 8 data + stop


@dataclass(frozen=True, eq=False)
class ByteStream:
    """K chunks: chunk i is `data[offsets[i]:offsets[i+1]]`, first byte out at `t_s[i]`.

    `t_s` (K,) increasing, s; `offsets` (K+1,) int64; `baud` the line rate the
    device uses (None where the link is not a UART, e.g. SPI).
    """

    t_s: np.ndarray
    data: bytes
    offsets: np.ndarray
    baud: int | None = None

    def __post_init__(self) -> None:
        t = np.asarray(self.t_s, dtype=float)
        off = np.asarray(self.offsets, dtype=np.int64)
        if off.shape != (t.size + 1,) or (off.size and (off[0] != 0 or off[-1] != len(self.data))):
            raise ValueError("ByteStream: offsets must be (K+1,) from 0 to len(data)")
        object.__setattr__(self, "t_s", t)
        object.__setattr__(self, "offsets", off)

    @classmethod
    def from_chunks(
        cls, t_s: Sequence[float] | np.ndarray, chunks: Sequence[bytes], baud: int | None = None
    ) -> ByteStream:
        lengths = np.fromiter((len(c) for c in chunks), dtype=np.int64, count=len(chunks))
        offsets = np.concatenate([[0], np.cumsum(lengths)])
        return cls(np.asarray(t_s, dtype=float), b"".join(chunks), offsets, baud)

    @classmethod
    def from_fixed_size(
        cls, t_s: np.ndarray, packets: np.ndarray, baud: int | None = None
    ) -> ByteStream:
        """From a (K, L) uint8 array of equal-length packets (the bulk-encoded fast path)."""
        k, length = packets.shape
        return cls(np.asarray(t_s, float), packets.tobytes(), np.arange(k + 1) * length, baud)

    def __len__(self) -> int:
        return self.t_s.size

    def chunk(self, i: int) -> bytes:
        return self.data[self.offsets[i] : self.offsets[i + 1]]

    def __iter__(self) -> Iterator[tuple[float, bytes]]:
        for i in range(len(self)):
            yield float(self.t_s[i]), self.chunk(i)

    def end_times_s(self) -> np.ndarray:
        """When each chunk's last byte has left the device at `baud` (t_s if no baud)."""
        if self.baud is None:
            return self.t_s.copy()
        return self.t_s + np.diff(self.offsets) * UART_BITS_PER_BYTE / self.baud

    def bytes_per_s(self) -> float:
        """Mean throughput over the stream's span (for link budgets)."""
        if len(self) < 2:
            return 0.0
        return len(self.data) / float(self.t_s[-1] - self.t_s[0])


def merge_byte_streams(streams: Sequence[ByteStream]) -> ByteStream:
    """Interleave several devices' chunks on one line, in time order (stable)."""
    chunks: list[bytes] = []
    times: list[float] = []
    for s in streams:
        for t, c in s:
            times.append(t)
            chunks.append(c)
    order = np.argsort(np.asarray(times), kind="stable")
    bauds = {s.baud for s in streams}
    baud = bauds.pop() if len(bauds) == 1 else None
    return ByteStream.from_chunks(np.asarray(times)[order], [chunks[i] for i in order], baud)


@dataclass(frozen=True, eq=False)
class EdgeStream:
    """E logic edges in time order: `t_s` (E,), `channel` (E,) int (0-based pin index),
    `rising` (E,) bool (True = low->high)."""

    t_s: np.ndarray
    channel: np.ndarray
    rising: np.ndarray

    def __post_init__(self) -> None:
        t = np.asarray(self.t_s, dtype=float)
        ch = np.asarray(self.channel, dtype=np.int64)
        up = np.asarray(self.rising, dtype=bool)
        if not (t.shape == ch.shape == up.shape and t.ndim == 1):
            raise ValueError("EdgeStream: t_s, channel and rising must be equal-length 1-D arrays")
        order = np.argsort(t, kind="stable")
        object.__setattr__(self, "t_s", t[order])
        object.__setattr__(self, "channel", ch[order])
        object.__setattr__(self, "rising", up[order])

    def __len__(self) -> int:
        return self.t_s.size

    def pulse_widths_s(self, channel: int) -> tuple[np.ndarray, np.ndarray]:
        """(rise times, high durations) of one channel, pairing each rise with the next fall.

        A decoder like the base board's input capture would do the same.
        """
        sel = self.channel == channel
        t = self.t_s[sel]
        up = self.rising[sel]
        rises: list[float] = []
        widths: list[float] = []
        start = None
        for ti, ui in zip(t, up, strict=True):
            if ui:
                start = ti
            elif start is not None:
                rises.append(start)
                widths.append(ti - start)
                start = None
        return np.asarray(rises), np.asarray(widths)


def sample_times(
    t_start_s: float,
    t_end_s: float,
    rate_hz: float,
    phase_s: float = 0.0,
    clock_ppm: float = 0.0,
) -> np.ndarray:
    """Sample instants of a free-running device clock falling in [t_start_s, t_end_s).

    The device ticks at `t_k = (phase_s + k / rate_hz) * (1 + clock_ppm * 1e-6)` for
    integer k, an absolute grid: consecutive windows [a, b), [b, c) give consecutive
    samples with none lost or repeated, so a flight can be sampled in chunks.
    """
    scale = 1.0 + clock_ppm * 1e-6
    k0 = int(np.ceil((t_start_s / scale - phase_s) * rate_hz - 1e-9))
    k1 = int(np.ceil((t_end_s / scale - phase_s) * rate_hz - 1e-9))
    k = np.arange(k0, max(k0, k1))
    return (phase_s + k / rate_hz) * scale
