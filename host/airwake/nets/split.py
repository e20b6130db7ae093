"""Train / validation / test split of one flight by time, never by shuffled rows.

Neighbouring samples at 150 Hz are nearly copies of each other, so a random row split
scores a network on its training data. Two orders (`SplitConfig.order`):

- "chronological" (the default): the flight's first part trains, the part after it
  validates (early stopping, the ARX ridge) and the last part tests — a net trained on
  today's flying and used on tomorrow's. Every training row lies before every
  validation row, and every validation row before every test row.
- "blocks": the flight is cut into blocks of `block_s`; whole blocks go to validation
  and test, drawn with the seeded generator (the earlier default). The sets interleave,
  so a net is tested on flying from between its training blocks: it hides a net that
  does not carry over to later flying (docs/networks.md, "The real flight").

In both, the first `guard_s` after a change of set (the features' history reaches into
the rows before) and the flight's edge-padded start belong to no set (GUARD).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TRAIN, VAL, TEST, GUARD = 0, 1, 2, -1
ORDERS = ("chronological", "blocks")


@dataclass(frozen=True)
class SplitConfig:
    block_s: float = 5.0
    val_fraction: float = 0.15
    test_fraction: float = 0.2
    order: str = "chronological"

    def __post_init__(self) -> None:
        if not self.block_s > 0:
            raise ValueError(f"SplitConfig.block_s must be > 0, got {self.block_s!r}")
        for name in ("val_fraction", "test_fraction"):
            v = getattr(self, name)
            if not 0 <= v < 1:
                raise ValueError(f"SplitConfig.{name} must be in [0, 1), got {v!r}")
        if self.val_fraction + self.test_fraction >= 1:
            raise ValueError("SplitConfig: val_fraction + test_fraction must be < 1")
        if self.order not in ORDERS:
            raise ValueError(f"SplitConfig.order must be one of {ORDERS}, got {self.order!r}")


def split_labels(t_s: np.ndarray, config: SplitConfig, guard_s: float, rng) -> np.ndarray:
    """(T,) labels TRAIN / VAL / TEST / GUARD in the config's order (module doc); `rng`
    draws the blocks of the "blocks" order and is not used by the chronological one."""
    if config.order == "chronological":
        return chronological_split(t_s, config, guard_s)
    return block_split(t_s, config, guard_s, rng)


def chronological_split(t_s: np.ndarray, config: SplitConfig, guard_s: float) -> np.ndarray:
    """(T,) labels: the first 1 − val − test of the flight's time span TRAIN, then VAL,
    then TEST; GUARD for the first `guard_s` of the flight and after each change of set."""
    t = np.asarray(t_s, float)
    rel = t - t[0]
    span = rel[-1]
    val_from = (1.0 - config.val_fraction - config.test_fraction) * span
    test_from = (1.0 - config.test_fraction) * span
    labels = np.full(t.size, TRAIN)
    labels[rel >= val_from] = VAL
    labels[rel >= test_from] = TEST
    starts = [0.0]
    if config.val_fraction > 0:
        starts.append(val_from)
    if config.test_fraction > 0:
        starts.append(test_from)
    for s in starts:
        labels[(rel >= s) & (rel < s + guard_s)] = GUARD
    return labels


def block_split(t_s: np.ndarray, config: SplitConfig, guard_s: float, rng) -> np.ndarray:
    """(T,) labels TRAIN / VAL / TEST / GUARD for the samples at times t_s, in blocks.

    At least one block goes to each non-zero fraction when the flight has >= 3 blocks.
    """
    t = np.asarray(t_s, float)
    rel = t - t[0]
    block = np.floor(rel / config.block_s).astype(int)
    n_blocks = int(block[-1]) + 1
    labels_per_block = np.full(n_blocks, TRAIN)
    order = rng.permutation(n_blocks)
    n_test = _count(config.test_fraction, n_blocks)
    n_val = _count(config.val_fraction, n_blocks)
    labels_per_block[order[:n_test]] = TEST
    labels_per_block[order[n_test:n_test + n_val]] = VAL
    labels = labels_per_block[block]
    # a block's start is guarded where its history reaches into another set's block (and
    # at the flight's start, where the history is edge-padded)
    changed = np.r_[True, labels_per_block[1:] != labels_per_block[:-1]]
    guard = changed[block] & ((rel - block * config.block_s) < guard_s)
    labels[guard] = GUARD
    return labels


def _count(fraction: float, n_blocks: int) -> int:
    if fraction <= 0:
        return 0
    k = int(round(fraction * n_blocks))
    return max(k, 1) if n_blocks >= 3 else k
