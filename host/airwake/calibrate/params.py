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
