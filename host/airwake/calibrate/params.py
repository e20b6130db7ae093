"""Which model parameters a calibration fits, and their bounds.

    free = select_parameters(model, None)                 # every parameter not `fixed`
    free = select_parameters(model, ["main_rotor.*", "rigid_body.Ixx_kg_m2"])

Default: the parameters the effects do not mark `fixed` (Table 5.1's starred constants
and discrete parameters stay put). A selection names parameters as `effect.name` or
fnmatch globs (`main_rotor.*`, `*.lift_slope_per_rad`); a named `fixed` parameter is
freed on request (the user knows better), a discrete one (rotation sense, blade count)
never. A selection that matches nothing is an error naming the known parameters.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Sequence

import numpy as np

from airwake.calibrate.errors import CalibrationError


def select_parameters(model, patterns: Sequence[str] | None = None) -> np.ndarray:
    """Boolean mask (P,) over `model.parameter_names` of the parameters to fit."""
    names = model.parameter_names
    specs = model.parameter_specs()
    discrete = np.array([specs[n].choices is not None for n in names])
    if not patterns:
        return ~model.fixed_mask()
    mask = np.zeros(len(names), dtype=bool)
    for pat in patterns:
        for part in str(pat).split(","):
            part = part.strip()
            if not part:
                continue
            hits = [i for i, n in enumerate(names) if fnmatch.fnmatchcase(n, part)]
            if not hits:
                raise CalibrationError(
                    f"--params: {part!r} matches no model parameter; known: {', '.join(names)}")
            hits = [i for i in hits if not discrete[i]]
            if not hits:
                raise CalibrationError(
                    f"--params: {part!r} names only discrete parameters, which are not fitted")
            mask[hits] = True
    return mask


def fit_bounds(model, free: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bounds (lo, hi) of the free parameters, from the effects' declarations."""
    lo, hi = model.bounds()
    return lo[free], hi[free]


# Subset selection: a parameter is held when the flight would not pin it (given the ones
# before it) even to its order of magnitude (docs/calibration.md: judged at the starting
# values, a tighter threshold holds parameters that are merely far from the truth).
SUBSET_REL_STD = 1.0
SUBSET_WINDOWS = 12


def identified_subset(model, predictor, candidates: np.ndarray,
                      rel_std: float = SUBSET_REL_STD,
                      correlation_samples: float = 1.0) -> tuple[np.ndarray, list]:
    """The candidates this flight identifies, and a note per one it does not.

    Subset selection (Golub, Klema & Stewart 1976): the Jacobian of the weighted
    residuals at the starting values (forward differences, on an evenly spaced subset of
    the windows), each column the residuals' change for a relative change of its
    parameter, is factored by QR with column pivoting. The pivot order ranks the
    parameters by the new information each adds to those before it (of two degenerate
    ones the one that matters more at its value goes first: delta_0 before delta_2, which
    in hover act alike). With the residuals in noise units, 1/|R_kk| is the relative std
    the flight gives the k-th parameter once those before it are known, times
    sqrt(`correlation_samples`) for residuals correlated over that many samples (a
    low-passed flight); a parameter above `rel_std` is held at its starting value: the
    flight cannot tell it from a combination of the others (a hover flight and the
    fuselage's drag areas, the Lock number against the lift slope and profile drag).
    Returns (mask over model.parameter_names, notes)."""
    from scipy.linalg import qr

    from airwake.calibrate.lsq import _Problem
    from airwake.calibrate.residuals import WindowedPredictor

    win = predictor.windows
    if win.n_windows > SUBSET_WINDOWS:
        pick = np.unique(np.linspace(0, win.n_windows - 1, SUBSET_WINDOWS).round().astype(int))
        predictor = WindowedPredictor(model, predictor.data, win.subset(pick))
    full0 = model.parameter_vector()
    lo, hi = fit_bounds(model, candidates)
    q0 = np.clip((full0[candidates] - lo) / (hi - lo), 0.0, 1.0)
    jac = _Problem(predictor, full0, candidates, lo, hi).jac(q0)  # d r / d q
    # relative sensitivities: the residuals' change for a given fraction of each value
    # (of 1 % of its range when the value is ~0), d r / d ln p
    typical = np.maximum(np.abs(full0[candidates]), 0.01 * (hi - lo))
    jac = jac / (hi - lo) * typical
    norms = np.linalg.norm(jac, axis=0)
    names = [n for n, c in zip(model.parameter_names, candidates, strict=True) if c]
    idx = np.flatnonzero(candidates)
    mask = candidates.copy()
    notes = []
    if not np.any(norms > 0):
        return mask, notes
    _, r, piv = qr(jac, mode="economic", pivoting=True)
    diag = np.abs(np.diag(r))
    for rank, col in enumerate(piv):
        info = diag[rank] if rank < diag.size else 0.0
        std = np.sqrt(correlation_samples) / info if info > 0 else np.inf
        if norms[col] == 0 or std > rel_std:
            mask[idx[col]] = False
            why = (f"it would be known to {100 * std:.0f} % at best, given the parameters "
                   "it trades against" if np.isfinite(std) else
                   "the residuals do not depend on it")
            notes.append(f"{names[col]}: held at {full0[idx[col]]:.6g} (not identified by "
                         f"this flight: {why})")
    return mask, notes
