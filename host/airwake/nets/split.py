"""Time-block split: train / validation / test blocks of one flight, never shuffled rows.

Neighbouring samples at 150 Hz are nearly copies of each other, so a random row split
scores a network on its training data. Instead the flight is cut into blocks of
`block_s`; whole blocks go to validation and test (drawn with the seeded generator);
the first `guard_s` of a block that follows a block of another set (the features'
history reaches into the block before) and the flight's edge-padded start belong to no set.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TRAIN, VAL, TEST, GUARD = 0, 1, 2, -1


@dataclass(frozen=True)
class SplitConfig:
    block_s: float = 5.0
    val_fraction: float = 0.15
    test_fraction: float = 0.2

    def __post_init__(self) -> None:
        if not self.block_s > 0:
            raise ValueError(f"SplitConfig.block_s must be > 0, got {self.block_s!r}")
        for name in ("val_fraction", "test_fraction"):
            v = getattr(self, name)
            if not 0 <= v < 1:
                raise ValueError(f"SplitConfig.{name} must be in [0, 1), got {v!r}")
        if self.val_fraction + self.test_fraction >= 1:
            raise ValueError("SplitConfig: val_fraction + test_fraction must be < 1")


def block_split(t_s: np.ndarray, config: SplitConfig, guard_s: float, rng) -> np.ndarray:
    """(T,) labels TRAIN / VAL / TEST / GUARD for the samples at times t_s.

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
