"""Section aerodynamics through 360 deg: the NACA 0012 tables of Sheldahl & Klimas (1981).

Source: R. E. Sheldahl, P. C. Klimas, *Aerodynamic Characteristics of Seven Symmetrical
Airfoil Sections Through 180-Degree Angle of Attack for Use in Aerodynamic Analysis of
Vertical Axis Wind Turbines*, SAND80-2114, Sandia National Laboratories, 1981 — the NACA
0012 table at Re = 360,000 (`data/naca0012_sheldahl_klimas_re360k.csv`, 0..180 deg; the
section is symmetric, so cl(-a) = -cl(a), cd(-a) = cd(a)). It covers what a rotor blade
meets: attached flow up to ~10 deg, the sharp trailing-edge stall of a 12 % section at
this Reynolds number, the post-stall flat-plate-like range, and reverse flow (|a| near
180 deg: the retreating blade's root at high advance ratio, a tail rotor in sideways
flight).

`SECTION` is the table on a uniform 0.5 deg grid over [-180, 180] deg (linear between
the published points), so the compiled lookup `section_coefficients(alpha)` is one
index computation and one linear interpolation.
"""

from __future__ import annotations

from pathlib import Path

import numba
import numpy as np

DATA = Path(__file__).resolve().parent / "data" / "naca0012_sheldahl_klimas_re360k.csv"
GRID_STEP_DEG = 0.5


def load_table(path: Path = DATA) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(alpha_deg, cl, cd) over [-180, 180] deg, mirrored from the published 0..180."""
    rows = [line.split(",") for line in path.read_text().splitlines()
            if line and not line.startswith("#") and not line.startswith("alpha")]
    a = np.array([float(r[0]) for r in rows])
    cl = np.array([float(r[1]) for r in rows])
    cd = np.array([float(r[2]) for r in rows])
    if a[0] != 0.0 or a[-1] != 180.0 or np.any(np.diff(a) <= 0):
        raise ValueError(f"{path}: alpha_deg must rise strictly from 0 to 180")
    return (np.concatenate([-a[:0:-1], a]), np.concatenate([-cl[:0:-1], cl]),
            np.concatenate([cd[:0:-1], cd]))


def _uniform_table() -> np.ndarray:
    a, cl, cd = load_table()
    grid = np.arange(-180.0, 180.0 + 0.5 * GRID_STEP_DEG, GRID_STEP_DEG)
    return np.column_stack([np.interp(grid, a, cl), np.interp(grid, a, cd)])


SECTION = _uniform_table()  # (721, 2): cl, cd at -180, -179.5, ..., 180 deg
_PER_RAD = 180.0 / np.pi / GRID_STEP_DEG


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def wrap_angle(a: float) -> float:
    """Angle in [-pi, pi)."""
    return (a + np.pi) % (2.0 * np.pi) - np.pi


@numba.njit(cache=True, fastmath=True, error_model="numpy")
def section_coefficients(alpha_rad: float, table: np.ndarray) -> tuple[float, float]:
    """(cl, cd) at any angle of attack (rad, wrapped), linear in the 0.5 deg table."""
    x = (wrap_angle(alpha_rad) + np.pi) * _PER_RAD
    i = int(x)
    if i >= table.shape[0] - 1:
        i = table.shape[0] - 2
    f = x - i
    return (table[i, 0] + f * (table[i + 1, 0] - table[i, 0]),
            table[i, 1] + f * (table[i + 1, 1] - table[i, 1]))
