"""The local linear wind models, fitted by least squares on samples in one volume.

Positions are taken about the volume's centre c (r = p - c), so the constant term is the
flow at the centre.

12-parameter model (eq 3.15), the mean flow with a full gradient:

    u(r) = A r + d,        A = [[a_x b_x c_x], [a_y b_y c_y], [a_z b_z c_z]],  d (3,)

6-parameter model (eq 5.3), a uniform flow plus a rigid rotation (the gradient's
antisymmetric part only: omega = curl(u) / 2):

    u(r) = omega x r + v

Both are ordinary least squares over the samples (n >= 4 and n >= 2 with non-coplanar
positions for a full-rank fit; a direction the samples do not spread along gets the
minimum-norm solution: no gradient along it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class LinearFit:
    """eq 3.15 about a centre: d (3,), a (3, 3) the gradient du_i/dx_j, rank (of the
    4-column design), rms_residual (3,) per component."""

    d: np.ndarray
    a: np.ndarray
    rank: int
    rms_residual: np.ndarray

    def __call__(self, r: np.ndarray) -> np.ndarray:
        """(n, 3) flow at offsets r (n, 3) from the centre."""
        return self.d + r @ self.a.T


@dataclass
class RotationFit:
    """eq 5.3 about a centre: v (3,), omega (3,), rank (of the 6-column design),
    rms_residual (3,)."""

    v: np.ndarray
    omega: np.ndarray
    rank: int
    rms_residual: np.ndarray

    def __call__(self, r: np.ndarray) -> np.ndarray:
        return self.v + np.cross(self.omega, r)


def fit_linear12(r: np.ndarray, u: np.ndarray) -> LinearFit:
    """eq 3.15 by least squares: r (n, 3) offsets from the centre, u (n, 3) flow."""
    # [1, x, y, z] [d; A^T] = u                                              (eq 3.15)
    x = np.column_stack([np.ones(len(r)), r])
    coef, _, rank, _ = np.linalg.lstsq(x, u, rcond=1e-9)
    res = u - x @ coef
    return LinearFit(coef[0], coef[1:].T.copy(), int(rank),
                     np.sqrt(np.mean(res * res, axis=0)))


def skew(r: np.ndarray) -> np.ndarray:
    """(n, 3, 3) [r]x, so that [r]x w = r x w."""
    z = np.zeros(len(r))
    return np.stack([np.stack([z, -r[:, 2], r[:, 1]], -1),
                     np.stack([r[:, 2], z, -r[:, 0]], -1),
                     np.stack([-r[:, 1], r[:, 0], z], -1)], 1)


def fit_rotation6(r: np.ndarray, u: np.ndarray) -> RotationFit:
    """eq 5.3 by least squares: r (n, 3), u (n, 3)."""
    # omega x r = -[r]x omega:   [I | -[r]x] [v; omega] = u                  (eq 5.3)
    n = len(r)
    x = np.concatenate([np.broadcast_to(np.eye(3), (n, 3, 3)), -skew(r)], axis=2)
    coef, _, rank, _ = np.linalg.lstsq(x.reshape(3 * n, 6), u.reshape(3 * n), rcond=1e-9)
    res = u - (x @ coef)
    return RotationFit(coef[:3], coef[3:], int(rank), np.sqrt(np.mean(res * res, axis=0)))
