"""WGS-84 conversions between the simulator's local NED frame and latitude/longitude/height.

The world runs in a flat local NED frame anchored at an origin `(lat_deg, lon_deg,
height_m)`; GNSS-based sensors (VN200 position, Piksi POS_LLH) report geodetic
coordinates. The conversion goes through ECEF exactly (no flat-earth approximation),
so NED -> LLA -> NED round-trips to well below a millimetre over many kilometres.
"""

from __future__ import annotations

import numpy as np

WGS84_A_M = 6378137.0
WGS84_F = 1.0 / 298.257223563
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)

# Default origin: the Severn River off the US Naval Academy, Annapolis (YP676 trials area
# of the reference's ship flights), height 0 m on the ellipsoid.
DEFAULT_ORIGIN_LLA = (38.9784, -76.4800, 0.0)


def lla_to_ecef(lla: np.ndarray) -> np.ndarray:
    """(..., 3) `[lat_deg, lon_deg, h_m]` -> ECEF metres."""
    lla = np.asarray(lla, dtype=float)
    lat = np.radians(lla[..., 0])
    lon = np.radians(lla[..., 1])
    h = lla[..., 2]
    n = WGS84_A_M / np.sqrt(1.0 - WGS84_E2 * np.sin(lat) ** 2)
    return np.stack(
        [
            (n + h) * np.cos(lat) * np.cos(lon),
            (n + h) * np.cos(lat) * np.sin(lon),
            (n * (1.0 - WGS84_E2) + h) * np.sin(lat),
        ],
        axis=-1,
    )


def ecef_to_lla(ecef: np.ndarray) -> np.ndarray:
    """(..., 3) ECEF metres -> `[lat_deg, lon_deg, h_m]` (fixed-point iteration, < 1e-9 rad)."""
    ecef = np.asarray(ecef, dtype=float)
    x, y, z = ecef[..., 0], ecef[..., 1], ecef[..., 2]
    lon = np.arctan2(y, x)
    p = np.hypot(x, y)
    lat = np.arctan2(z, p * (1.0 - WGS84_E2))
    h = np.zeros_like(p)
    for _ in range(6):
        n = WGS84_A_M / np.sqrt(1.0 - WGS84_E2 * np.sin(lat) ** 2)
        h = p / np.cos(lat) - n
        lat = np.arctan2(z, p * (1.0 - WGS84_E2 * n / (n + h)))
    return np.stack([np.degrees(lat), np.degrees(lon), h], axis=-1)


def _ned_basis(origin_lla: tuple[float, float, float]) -> np.ndarray:
    """Rows: north, east, down unit vectors in ECEF at the origin."""
    lat = np.radians(origin_lla[0])
    lon = np.radians(origin_lla[1])
    sl, cl = np.sin(lat), np.cos(lat)
    so, co = np.sin(lon), np.cos(lon)
    return np.array(
        [
            [-sl * co, -sl * so, cl],
            [-so, co, 0.0],
            [-cl * co, -cl * so, -sl],
        ]
    )


def ned_to_lla(pos_ned_m: np.ndarray, origin_lla=DEFAULT_ORIGIN_LLA) -> np.ndarray:
    """(..., 3) local NED metres -> `[lat_deg, lon_deg, h_m]`."""
    basis = _ned_basis(origin_lla)
    ecef = lla_to_ecef(np.asarray(origin_lla, float)) + np.asarray(pos_ned_m, float) @ basis
    return ecef_to_lla(ecef)


def lla_to_ned(lla: np.ndarray, origin_lla=DEFAULT_ORIGIN_LLA) -> np.ndarray:
    """(..., 3) `[lat_deg, lon_deg, h_m]` -> local NED metres."""
    basis = _ned_basis(origin_lla)
    d = lla_to_ecef(lla) - lla_to_ecef(np.asarray(origin_lla, float))
    return d @ basis.T
