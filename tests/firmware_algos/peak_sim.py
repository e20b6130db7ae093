"""A simple, documented LOSA line simulator for the peak-finder cross-checks.

One TSL1401 line (128 pixels, 63.5 um pitch) lit by the marker's 850 nm LED through one
slot of the module (reference §3.3.1.3):

* Shape: Fresnel diffraction of a slit of width d = 0.13 mm at h = 12 mm from the array
  (the reference's sensor height; eq 3.1 d = sqrt(2 h lambda) makes this the sharpest
  image, about one pixel wide), blurred by a Gaussian of `blur_px` (LED die size, focus,
  IR-filter/cover-glass scatter: the reference reports real peaks < 7 px wide, so
  0.6-1.2 px is the realistic range), integrated over each pixel's aperture (fill
  factor 0.9). Point-source (plane-wave) illumination.
* Exposure: `amplitude` is the peak pixel's signal above background as a fraction of the
  ADC full scale, before clipping (> 1 saturates); `background` the same for the flat
  dark/ambient level.
* Noise: photon shot noise (Poisson on signal + background electrons, full scale =
  `full_well_e` electrons), Gaussian read noise `read_noise_e`, then the ADC: counts =
  round(electrons / gain) clipped to 2^bits - 1 (8-, 10- or 12-bit).

The hil_sim optics model is the full version (geometry, three slots, LED angles); this
one only has to produce realistic single peaks.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np
from scipy.special import fresnel

PIXELS = 128
PITCH_M = 63.5e-6
SLIT_M = 0.13e-3
HEIGHT_M = 12e-3
WAVELENGTH_M = 850e-9
FILL_FACTOR = 0.9
_OVERSAMPLE = 64
_HALF_SPAN_PX = 20


def _slit_fresnel(u_m: np.ndarray) -> np.ndarray:
    """Intensity of a plane wave through a slit, Fresnel regime, at offsets u_m."""
    k = np.sqrt(2.0 / (WAVELENGTH_M * HEIGHT_M))
    s_a, c_a = fresnel(k * (-SLIT_M / 2 - u_m))
    s_b, c_b = fresnel(k * (SLIT_M / 2 - u_m))
    return (c_b - c_a) ** 2 + (s_b - s_a) ** 2


@cache
def _pixel_response(blur_px: float) -> tuple[np.ndarray, np.ndarray]:
    """(offsets px, cumulative integral) of the blurred slit image, for interpolation."""
    u = np.arange(-_HALF_SPAN_PX * _OVERSAMPLE, _HALF_SPAN_PX * _OVERSAMPLE + 1) / _OVERSAMPLE
    img = _slit_fresnel(u * PITCH_M)
    if blur_px > 0:
        g = np.exp(-0.5 * (u / blur_px) ** 2)
        img = np.convolve(img, g / g.sum(), mode="same")
    cdf = np.concatenate([[0.0], np.cumsum(img) / _OVERSAMPLE])
    edges = np.concatenate([u - 0.5 / _OVERSAMPLE, [u[-1] + 0.5 / _OVERSAMPLE]])
    # normalise so a peak centred on a pixel has value 1
    centre = np.interp(FILL_FACTOR / 2, edges, cdf) - np.interp(-FILL_FACTOR / 2, edges, cdf)
    return edges, cdf / centre


def ideal_line(centre_px: float, blur_px: float = 0.9, n: int = PIXELS) -> np.ndarray:
    """Noise-free pixel responses (peak pixel ~1 when centred), shape (n,)."""
    edges, cdf = _pixel_response(round(blur_px, 3))
    k = np.arange(n) - centre_px
    hi = np.interp(k + FILL_FACTOR / 2, edges, cdf)
    lo = np.interp(k - FILL_FACTOR / 2, edges, cdf)
    return hi - lo


@dataclass(frozen=True)
class Sensor:
    bits: int = 10
    full_well_e: float = 100_000.0
    read_noise_e: float = 100.0

    @property
    def full_scale(self) -> int:
        return (1 << self.bits) - 1


def noisy_line(
    rng: np.random.Generator,
    centre_px: float,
    amplitude: float,
    sensor: Sensor = Sensor(),
    background: float = 0.04,
    blur_px: float = 0.9,
) -> np.ndarray:
    """One simulated line as ADC counts (uint16, shape (128,))."""
    signal = ideal_line(centre_px, blur_px) * amplitude + background  # fraction of FS
    electrons = rng.poisson(np.clip(signal, 0, None) * sensor.full_well_e).astype(float)
    electrons += rng.normal(0.0, sensor.read_noise_e, PIXELS)
    gain = sensor.full_well_e / sensor.full_scale
    counts = np.clip(np.round(electrons / gain), 0, sensor.full_scale)
    return counts.astype(np.uint16)
