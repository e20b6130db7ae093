"""Frozen, seeded, divergence-free 3-D turbulence (von Karman or Dryden spectrum).

A `FrozenTurbulence` is a periodic box of velocity fluctuations generated once from
the config and an rng (spectral synthesis):

    u_hat(k) = sqrt(E(k) / (4 pi k^2)) * P(k) n_hat(k),   P = I - k k^T / k^2

with n_hat the Fourier transform of white noise (so Hermitian symmetry and a real
field come for free) and P the projection that makes the field divergence-free. The
energy spectrum is von Karman, E(k) ~ (k/k_e)^4 / (1 + (k/k_e)^2)^(17/6) with
k_e = 0.7468 / L, or Dryden, E ~ (kL)^4 / (1 + (kL)^2)^3, with L the longitudinal
integral length scale (`length_scale_m`); both constants make the longitudinal
integral scale of the synthesised field equal L. Each component is then scaled to
unit variance over the box, so a field multiplies it by its local sigma (m/s).

Time dependence is Taylor's frozen turbulence: a field samples the box at
`x - c t` for a convection velocity c it chooses (the mean wind). The sampling line
drifts slowly across the box (`drift` below) so a point does not see the same
stretch of box again after one box length: over one box length of advection the
lateral offset moves by 0.618 of `lateral_drift_m`, never repeating exactly.

Sampling is trilinear interpolation on the periodic grid; the grid spacing sets the
smallest eddies (default 0.25 m, a fifth of the rotor diameter). It is compiled
(numba) one point at a time, `sample_point` / `advected_point`, so the wind fields'
own kernels call it inside their loops.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numba
import numpy as np

from hil_sim.sensors.config import check_choice, check_positive

VON_KARMAN_KE_TIMES_L = 0.7468342  # k_e * L_u for the von Karman form (integral check)
GOLDEN = 0.6180339887


@dataclass(frozen=True)
class TurbulenceConfig:
    """Turbulence box: spectrum, integral length scale and grid."""

    spectrum: str = "von_karman"
    length_scale_m: float = 1.5
    grid_spacing_m: float = 0.25
    box_m: tuple[float, float, float] = (128.0, 16.0, 16.0)
    lateral_drift_m: float = 6.0

    def __post_init__(self) -> None:
        check_choice("spectrum", self.spectrum, ("von_karman", "dryden"))
        check_positive("length_scale_m", self.length_scale_m)
        check_positive("grid_spacing_m", self.grid_spacing_m)
        for v in self.box_m:
            check_positive("box_m", v)
        check_positive("lateral_drift_m", self.lateral_drift_m)
        cells = np.prod([round(b / self.grid_spacing_m) for b in self.box_m])
        if cells > 8_000_000:
            raise ValueError(
                f"box_m = {self.box_m!r} at grid_spacing_m = {self.grid_spacing_m!r}: "
                f"{cells:.0f} cells (> 8e6, too much memory)")
        if min(self.box_m) < 4 * self.length_scale_m:
            raise ValueError(
                f"box_m = {self.box_m!r}: every side must be >= 4 length scales "
                f"({4 * self.length_scale_m} m) or the large eddies are cut off")
        if self.grid_spacing_m > self.length_scale_m / 2:
            raise ValueError(
                f"grid_spacing_m = {self.grid_spacing_m!r}: must be <= length_scale_m / 2")


class TurbulenceGrid(NamedTuple):
    """A box for the compiled samplers: values (cells, 3) float32 in C order over
    (nx, ny, nz), the cell counts, the spacing (m) and the lateral drift per metre of
    advection."""

    flat: np.ndarray
    nx: int
    ny: int
    nz: int
    dx: float
    dy: float
    dz: float
    drift: float


class FrozenTurbulence:
    """A unit-variance periodic turbulence box; `sample` interpolates it."""

    def __init__(self, config: TurbulenceConfig, rng: np.random.Generator) -> None:
        self.config = config
        h = config.grid_spacing_m
        shape = tuple(max(8, int(round(b / h))) for b in config.box_m)
        self.shape = shape
        self.spacing = np.array([b / n for b, n in zip(config.box_m, shape, strict=True)])
        self.size_m = np.array(config.box_m, dtype=float)
        field = _synthesise(shape, self.spacing, config, rng)
        # (nx*ny*nz, 3) float32: one gather fetches the three components.
        self._flat = np.ascontiguousarray(field.reshape(-1, 3), dtype=np.float32)
        drift = GOLDEN * config.lateral_drift_m / self.size_m[0]
        # The box as the compiled samplers take it (also from other fields' kernels).
        self.grid = TurbulenceGrid(self._flat, *shape, *(float(d) for d in self.spacing),
                                   float(drift))

    def field(self) -> np.ndarray:
        """The box values, (nx, ny, nz, 3)."""
        return self._flat.reshape(*self.shape, 3)

    def advected(self, pos_m: np.ndarray, t_s: np.ndarray, speed_m_s: float) -> np.ndarray:
        """Sample the box frozen-advected along its x axis at `speed_m_s`.

        `pos_m` (N, 3) are coordinates in the field's own axes (x along the
        convection), `t_s` (N,). Returns (N, 3) unit-variance fluctuations.
        """
        p = np.ascontiguousarray(pos_m, dtype=float)
        t = np.ascontiguousarray(np.broadcast_to(np.asarray(t_s, dtype=float), p.shape[:1]))
        out = np.empty((p.shape[0], 3))
        advected_rows(self.grid, p, t, float(speed_m_s), out)
        return out

    def sample(self, pos_m: np.ndarray) -> np.ndarray:
        """Trilinear interpolation at (N, 3) positions (periodic), -> (N, 3)."""
        p = np.ascontiguousarray(pos_m, dtype=float)
        out = np.empty((p.shape[0], 3))
        sample_rows(self.grid, p, out)
        return out


# Trilinear interpolation on the periodic grid, one point at a time: g = p / spacing,
# corners i0 = floor(g) mod n and i0 + 1 mod n, weights 1 - f and f (f = g - floor(g))
# per axis; the value is the weighted sum of the 8 corners.


@numba.njit(cache=True, error_model="numpy")
def _corners(g: float, n: int) -> tuple[int, int, float]:
    """One axis: the two neighbouring indices and the weight of the upper one."""
    fl = math.floor(g)
    i0 = int(fl)
    if i0 < 0 or i0 >= n:  # (an integer division is slow: only when outside the box)
        i0 %= n
    i1 = i0 + 1
    return i0, 0 if i1 == n else i1, g - fl


@numba.njit(cache=True, error_model="numpy")
def sample_point(box: TurbulenceGrid, x: float, y: float, z: float
                 ) -> tuple[float, float, float]:
    """The box's (u, v, w) at one point (m, box axes), periodic trilinear."""
    ix0, ix1, fx = _corners(x / box.dx, box.nx)
    iy0, iy1, fy = _corners(y / box.dy, box.ny)
    iz0, iz1, fz = _corners(z / box.dz, box.nz)
    sx = box.ny * box.nz
    u = v = w = 0.0
    for a in range(2):
        ox = (ix0 if a == 0 else ix1) * sx
        wx = 1.0 - fx if a == 0 else fx
        for b in range(2):
            oy = (iy0 if b == 0 else iy1) * box.nz
            wxy = wx * (1.0 - fy if b == 0 else fy)
            for c in range(2):
                k = ox + oy + (iz0 if c == 0 else iz1)
                wt = wxy * (1.0 - fz if c == 0 else fz)
                u += box.flat[k, 0] * wt
                v += box.flat[k, 1] * wt
                w += box.flat[k, 2] * wt
    return u, v, w


@numba.njit(cache=True, error_model="numpy")
def advected_point(box: TurbulenceGrid, x: float, y: float, z: float, t: float,
                   speed: float) -> tuple[float, float, float]:
    """Taylor's frozen turbulence: the box at (x - c t, y + drift c t, z)."""
    travel = speed * t
    return sample_point(box, x - travel, y + travel * box.drift, z)


@numba.njit(cache=True, error_model="numpy")
def sample_rows(box: TurbulenceGrid, pos: np.ndarray, out: np.ndarray) -> None:
    for i in range(pos.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = sample_point(box, pos[i, 0], pos[i, 1], pos[i, 2])


@numba.njit(cache=True, error_model="numpy")
def advected_rows(box: TurbulenceGrid, pos: np.ndarray, t: np.ndarray, speed: float,
                  out: np.ndarray) -> None:
    for i in range(pos.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = advected_point(box, pos[i, 0], pos[i, 1],
                                                         pos[i, 2], t[i], speed)


def energy_spectrum(k: np.ndarray, config: TurbulenceConfig) -> np.ndarray:
    """Unnormalised E(k) of the configured spectrum."""
    if config.spectrum == "von_karman":
        x = k * (config.length_scale_m / VON_KARMAN_KE_TIMES_L)
        return x**4 / (1.0 + x * x) ** (17.0 / 6.0)
    x = k * config.length_scale_m
    return x**4 / (1.0 + x * x) ** 3


def _synthesise(shape: tuple[int, int, int], spacing: np.ndarray, config: TurbulenceConfig,
                rng: np.random.Generator) -> np.ndarray:
    kx = 2 * np.pi * np.fft.fftfreq(shape[0], spacing[0])
    ky = 2 * np.pi * np.fft.fftfreq(shape[1], spacing[1])
    kz = 2 * np.pi * np.fft.rfftfreq(shape[2], spacing[2])
    kvec = np.meshgrid(kx, ky, kz, indexing="ij")
    k2 = kvec[0] ** 2 + kvec[1] ** 2 + kvec[2] ** 2
    k2[0, 0, 0] = 1.0
    kmag = np.sqrt(k2)
    amp = np.sqrt(energy_spectrum(kmag, config) / (4 * np.pi * k2))
    amp[0, 0, 0] = 0.0
    noise_hat = [np.fft.rfftn(rng.standard_normal(shape)) for _ in range(3)]
    # Projection onto the plane normal to k: divergence-free.
    kdotn = sum(kvec[i] * noise_hat[i] for i in range(3)) / k2
    comps = []
    for i in range(3):
        u_hat = amp * (noise_hat[i] - kvec[i] * kdotn)
        comps.append(np.fft.irfftn(u_hat, s=shape, axes=(0, 1, 2)))
    field = np.stack(comps, axis=-1)
    field -= field.mean(axis=(0, 1, 2))
    field /= field.std(axis=(0, 1, 2))
    return field
