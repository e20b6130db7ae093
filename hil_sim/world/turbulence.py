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
smallest eddies (default 0.25 m, a fifth of the rotor diameter).
"""

from __future__ import annotations

from dataclasses import dataclass

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
        self._strides = np.array([shape[1] * shape[2], shape[2], 1], dtype=np.int64)
        self._n = np.array(shape, dtype=np.int64)

    def field(self) -> np.ndarray:
        """The box values, (nx, ny, nz, 3)."""
        return self._flat.reshape(*self.shape, 3)

    def advected(self, pos_m: np.ndarray, t_s: np.ndarray, speed_m_s: float) -> np.ndarray:
        """Sample the box frozen-advected along its x axis at `speed_m_s`.

        `pos_m` (N, 3) are coordinates in the field's own axes (x along the
        convection), `t_s` (N,). Returns (N, 3) unit-variance fluctuations.
        """
        p = np.array(pos_m, dtype=float, copy=True)
        travel = speed_m_s * np.asarray(t_s, dtype=float)
        p[:, 0] -= travel
        # Slow lateral drift of the sampling line: no exact repetition after a box.
        p[:, 1] += travel * (GOLDEN * self.config.lateral_drift_m / self.size_m[0])
        return self.sample(p)

    def sample(self, pos_m: np.ndarray) -> np.ndarray:
        """Trilinear interpolation at (N, 3) positions (periodic), -> (N, 3)."""
        g = np.asarray(pos_m, dtype=float) / self.spacing
        i0 = np.floor(g)
        f = g - i0
        i0 = i0.astype(np.int64) % self._n
        n = g.shape[0]
        # Per axis: the two neighbouring flat-index offsets and weights, (N, 3, 2);
        # their outer products over the axes give the 8 corners in one gather.
        idx = np.empty((n, 3, 2), dtype=np.int64)
        idx[:, :, 0] = i0 * self._strides
        idx[:, :, 1] = ((i0 + 1) % self._n) * self._strides
        wts = np.empty((n, 3, 2))
        wts[:, :, 0] = 1.0 - f
        wts[:, :, 1] = f
        flat = idx[:, 0, :, None, None] + idx[:, 1, None, :, None] + idx[:, 2, None, None, :]
        weights = wts[:, 0, :, None, None] * wts[:, 1, None, :, None] * wts[:, 2, None, None, :]
        values = self._flat[flat.reshape(n, 8)]  # (N, 8, 3)
        return (values * weights.reshape(n, 8, 1)).sum(axis=1)


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
