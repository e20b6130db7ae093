"""WGS-84 latitude/longitude/height <-> local NED metres, exactly through ECEF.

Used by the flight-table builder to turn INS positions into `pos_*_m` about an origin
(the table's metadata names it). Same maths as the simulator's geodesy, written here so
the host does not import the simulator.
"""

from __future__ import annotations

import numpy as np

WGS84_A_M = 6378137.0
WGS84_F = 1.0 / 298.257223563
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)


def lla_to_ecef(lla: np.ndarray) -> np.ndarray:
    """(..., 3) `[lat_deg, lon_deg, h_m]` -> ECEF metres."""
    lla = np.asarray(lla, dtype=float)
    lat = np.radians(lla[..., 0])
    lon = np.radians(lla[..., 1])
    h = lla[..., 2]
    n = WGS84_A_M / np.sqrt(1.0 - WGS84_E2 * np.sin(lat) ** 2)
    return np.stack([(n + h) * np.cos(lat) * np.cos(lon),
                     (n + h) * np.cos(lat) * np.sin(lon),
                     (n * (1.0 - WGS84_E2) + h) * np.sin(lat)], axis=-1)


def ned_basis(origin_lla) -> np.ndarray:
    """(3, 3) rows: north, east, down unit vectors in ECEF at the origin."""
    lat = np.radians(origin_lla[0])
    lon = np.radians(origin_lla[1])
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])


def lla_to_ned(lla: np.ndarray, origin_lla) -> np.ndarray:
    """(..., 3) `[lat_deg, lon_deg, h_m]` -> NED metres about `origin_lla`."""
    d = lla_to_ecef(lla) - lla_to_ecef(np.asarray(origin_lla, dtype=float))
    return d @ ned_basis(origin_lla).T
