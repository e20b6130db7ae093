"""Resamplers: pure functions (weights, rng) -> indexes, as in the `particles` library.

weights: (N,) non-negative, summing to 1 (normalised by the caller); rng: a
numpy Generator; returns (N,) int64 indexes into the particles, each in [0, N).

    systematic   one uniform offset, N evenly spaced pointers (Kitagawa 1996): the
                 count of particle i is floor(N w_i) or that + 1; lowest variance here
    stratified   one uniform per stratum [k/N, (k+1)/N)
    multinomial  N independent draws, i with probability w_i: the reference's
                 "roulette wheel" selection (§5.4.2); unbiased, the noisiest
"""

from __future__ import annotations

import numpy as np


def _cumulative(weights: np.ndarray) -> np.ndarray:
    cs = np.cumsum(np.asarray(weights, dtype=float))
    cs /= cs[-1]
    cs[-1] = 1.0  # no pointer can fall past the end through rounding
    return cs


def _pick(cs: np.ndarray, pointers: np.ndarray) -> np.ndarray:
    idx = np.searchsorted(cs, pointers, side="right")
    return np.minimum(idx, cs.size - 1).astype(np.int64)


def systematic(weights, rng: np.random.Generator) -> np.ndarray:
    """Systematic resampling: pointers (u + k)/N, u ~ U(0, 1)."""
    n = len(weights)
    return _pick(_cumulative(weights), (rng.random() + np.arange(n)) / n)


def stratified(weights, rng: np.random.Generator) -> np.ndarray:
    """Stratified resampling: pointers (u_k + k)/N, u_k ~ U(0, 1) independent."""
    n = len(weights)
    return _pick(_cumulative(weights), (rng.random(n) + np.arange(n)) / n)


def multinomial(weights, rng: np.random.Generator) -> np.ndarray:
    """Multinomial (roulette-wheel) resampling: N independent spins of the wheel."""
    n = len(weights)
    return _pick(_cumulative(weights), rng.random(n))


roulette = multinomial

RESAMPLERS = {
    "systematic": systematic,
    "stratified": stratified,
    "multinomial": multinomial,
    "roulette": multinomial,
}


def effective_sample_size(weights) -> float:
    """ESS = 1 / sum(w_i^2) for normalised weights (N when uniform, 1 when degenerate)."""
    w = np.asarray(weights, dtype=float)
    return float(1.0 / np.sum(w * w))
