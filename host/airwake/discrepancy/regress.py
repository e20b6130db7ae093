"""Least squares of the residual on regressors, with the statistics the diagnosis reports:
in-sample explained variance (ERR-style share of the weighted residual sum of squares),
time-block cross-validated explained variance, a partial-F test whose denominator degrees
of freedom are the residual's *effective* sample size, and canonical correlations between
regressor subspaces (can two candidates be told apart on this flight?).

Shapes: y (n, C) residual rows (masked, in the analysis band), X (n, C, J) regressors (the
candidate's sensitivities, same rows/channels), w (C,) channel weights (1/noise^2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats


@dataclass
class LinearFit:
    coef: np.ndarray  # (J,)
    explained: float  # 1 - SSE_after/SSE_before (weighted, all channels)
    explained_channels: np.ndarray  # (C,)
    cv_explained: float  # the same, out of sample (time blocks)
    cv_channels: np.ndarray  # (C,)
    explained_rms: np.ndarray  # (C,) sqrt of the explained mean square per channel
    f_stat: float
    p_value: float
    n_eff: float
    condition: float  # condition number of the standardised regressors


def _stack(y, x, w):
    sw = np.sqrt(w)
    ys = (y * sw).reshape(-1)
    xs = (x * sw[None, :, None]).reshape(-1, x.shape[2])
    return ys, xs


# a regressor keeping less than this share of its energy in a fit's rows says nothing
# there (a candidate that acts only in the block a cross-validation fold leaves out)
SILENT_SHARE = 1e-9


def _solve(g, b, full_diag=None):
    """Least squares from normal equations with a tiny ridge (scale-aware). A regressor
    silent in these rows (its diagonal <= SILENT_SHARE of `full_diag`, its energy over the
    whole fit; none given: exactly zero) gets coefficient 0: the rows say nothing of it
    (solving for it anyway gives a coefficient of ~1e150 and an overflow)."""
    dg = np.diag(g)
    ref = dg if full_diag is None else np.asarray(full_diag, dtype=float)
    live = (dg > 0) & (dg > SILENT_SHARE * ref)
    a = np.zeros(g.shape[0])
    if not live.any():
        return a
    d = np.sqrt(dg[live])
    gs = g[np.ix_(live, live)] / np.outer(d, d)
    a[live] = np.linalg.lstsq(gs + 1e-10 * np.eye(d.size), b[live] / d, rcond=None)[0] / d
    return a


def condition_number(x: np.ndarray) -> float:
    """Condition number of the column-standardised (n, J) matrix."""
    if x.shape[1] == 0:
        return 1.0
    sd = x.std(0)
    ok = sd > 0
    if not ok.any():
        return float("inf")
    z = (x[:, ok] - x[:, ok].mean(0)) / sd[ok]
    s = np.linalg.svd(z, compute_uv=False)
    return float(s[0] / max(s[-1], 1e-300)) if ok.all() else float("inf")


def linear_fit(y: np.ndarray, x: np.ndarray, w: np.ndarray, blocks: list[np.ndarray],
               n_eff: float) -> LinearFit:
    """Fit y ~ X a (weighted), with CV over the row blocks and the partial-F test."""
    n, c = y.shape
    j = x.shape[2]
    ys, xs = _stack(y, x, w)
    g = xs.T @ xs
    b = xs.T @ ys
    a = _solve(g, b)
    fitted = np.einsum("ncj,j->nc", x, a)
    sse0_c = np.sum(y * y, 0)
    sse1_c = np.sum((y - fitted) ** 2, 0)
    sse0 = float(np.sum(sse0_c * w))
    sse1 = float(np.sum(sse1_c * w))
    explained = 1.0 - sse1 / sse0 if sse0 > 0 else 0.0
    expl_c = np.where(sse0_c > 0, 1.0 - sse1_c / np.maximum(sse0_c, 1e-300), 0.0)
    expl_rms = np.sqrt(np.maximum(sse0_c - sse1_c, 0.0) / n)
    # time-block cross-validation: fit without block k, score on block k
    cv0 = np.zeros(c)
    cv1 = np.zeros(c)
    grams = []
    for blk in blocks:
        yb, xb = _stack(y[blk], x[blk], w)
        grams.append((xb.T @ xb, xb.T @ yb))
    for blk, (gb, bb) in zip(blocks, grams, strict=True):
        ab = _solve(g - gb, b - bb, np.diag(g))
        fb = np.einsum("ncj,j->nc", x[blk], ab)
        cv0 += np.sum(y[blk] ** 2, 0)
        cv1 += np.sum((y[blk] - fb) ** 2, 0)
    cv_explained = 1.0 - float(np.sum(cv1 * w)) / float(np.sum(cv0 * w)) if cv0.any() else 0.0
    cv_c = np.where(cv0 > 0, 1.0 - cv1 / np.maximum(cv0, 1e-300), 0.0)
    f_stat, p = partial_f(sse0, sse1, j, n_eff)
    return LinearFit(a, explained, expl_c, cv_explained, cv_c, expl_rms, f_stat, p, n_eff,
                     condition_number(xs))


def partial_f(sse0: float, sse1: float, j: int, n_eff: float) -> tuple[float, float]:
    """F = ((SSE0 - SSE1)/J) / (SSE1/(N_eff - J)) and its upper-tail p-value."""
    dof = max(n_eff - j, 1.0)
    if sse1 <= 0:
        return float("inf"), 0.0
    f = max(sse0 - sse1, 0.0) / j / (sse1 / dof)
    return float(f), float(stats.f.sf(f, j, dof))


def canonical_correlations(xa: np.ndarray, xb: np.ndarray) -> np.ndarray:
    """Canonical correlations between the column spaces of xa (n, Ja) and xb (n, Jb)
    (centred): singular values of Qa^T Qb."""
    def basis(x):
        x = x - x.mean(0)
        keep = np.linalg.norm(x, axis=0) > 0
        if not keep.any():
            return np.zeros((x.shape[0], 0))
        q, r = np.linalg.qr(x[:, keep])
        d = np.abs(np.diag(r))
        return q[:, d > 1e-10 * d.max()]
    qa, qb = basis(xa), basis(xb)
    if qa.shape[1] == 0 or qb.shape[1] == 0:
        return np.zeros(0)
    return np.clip(np.linalg.svd(qa.T @ qb, compute_uv=False), 0.0, 1.0)
