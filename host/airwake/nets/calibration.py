"""Turbulence calibration of the residual std (reference §4.4.1): a straight line
turbulence_m_s = slope · resid_std + offset fitted with RANSAC (Fischler & Bolles 1981),
because the residual std is noisy and a few cells are far off the line.

    fit = ransac_line(x, y, rng=np.random.default_rng(0))
    fit.slope, fit.offset, fit.inliers

The reference's slope is 0.021 m·s/rad for the norm of the roll/pitch angular-acceleration
residuals' local std (rad/s²) against the wind's turbulence (m/s), offset 0.83 m/s (left
out outdoors: relative distributions only). For a rate net the slope is in m/rad.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

REFERENCE_SLOPE_M_S_PER_RAD = 0.021  # §4.4.1, angular-acceleration residuals
REFERENCE_OFFSET_M_S = 0.83


@dataclass(frozen=True)
class LineFit:
    """slope, offset; inliers (n,) bool; threshold (the inlier band, |y − fit| <=);
    points used."""

    slope: float
    offset: float
    inliers: np.ndarray
    threshold: float
    points: int

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return self.slope * np.asarray(x, float) + self.offset

    def to_dict(self) -> dict:
        d = asdict(self)
        d["inliers"] = int(np.sum(self.inliers))
        return d


def _least_squares(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    a = np.column_stack([x, np.ones_like(x)])
    (slope, offset), *_ = np.linalg.lstsq(a, y, rcond=None)
    return float(slope), float(offset)


def ransac_line(x, y, rng: np.random.Generator, iterations: int = 500,
                threshold: float | None = None, min_inlier_fraction: float = 0.3) -> LineFit:
    """RANSAC line y ≈ slope x + offset: draw 2 points, count points within `threshold`
    of their line, keep the largest consensus (ties: smaller residual), refit it by least
    squares. `threshold` defaults to the median absolute deviation of y (scikit-learn's
    choice). Raises ValueError with fewer than 3 finite points or no consensus."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y)
    xs, ys = x[ok], y[ok]
    n = xs.size
    if n < 3:
        raise ValueError(f"RANSAC needs >= 3 finite points, got {n}")
    if threshold is None:
        threshold = float(np.median(np.abs(ys - np.median(ys))))
        threshold = threshold if threshold > 0 else float(np.std(ys)) or 1e-12
    best, best_key = None, (-1, np.inf)
    for _ in range(int(iterations)):
        i, j = rng.choice(n, size=2, replace=False)
        if xs[i] == xs[j]:
            continue
        slope = (ys[j] - ys[i]) / (xs[j] - xs[i])
        offset = ys[i] - slope * xs[i]
        r = np.abs(ys - (slope * xs + offset))
        inl = r <= threshold
        key = (int(inl.sum()), float(r[inl].sum()))
        if key[0] > best_key[0] or (key[0] == best_key[0] and key[1] < best_key[1]):
            best, best_key = inl, key
    if best is None or best.sum() < max(2, min_inlier_fraction * n):
        raise ValueError(f"RANSAC found no line holding {min_inlier_fraction:.0%} of {n} points")
    slope, offset = _least_squares(xs[best], ys[best])
    inliers = np.zeros(x.size, bool)
    inliers[np.flatnonzero(ok)[best]] = True
    return LineFit(slope, offset, inliers, float(threshold), int(n))
