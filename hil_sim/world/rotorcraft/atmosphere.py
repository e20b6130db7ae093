"""Air density and gravity of the truth world, from their standards.

- Air density from the ideal-gas law, rho = p / (R_d T), with the specific gas constant of
  dry air R_d = 287.058 J/(kg K) (ISO 2533:1975, the International Standard Atmosphere).
  The site sets temperature and pressure (a hall at 20 degC, the sea at 15 degC).
- Normal gravity on the WGS-84 ellipsoid at the site's latitude, Somigliana's closed
  form (NIMA TR8350.2, 3rd ed., 2000, eq. 4-1):
      g = g_e (1 + k sin^2 phi) / sqrt(1 - e^2 sin^2 phi),
  g_e = 9.7803253359 m/s^2, k = 0.00193185265241, e^2 = 0.00669437999013,
  less the free-air gradient 3.086e-6 (m/s^2)/m for the height above the ellipsoid.
"""

from __future__ import annotations

import math

R_DRY_AIR_J_KG_K = 287.058
KELVIN = 273.15
WGS84_GE_M_S2 = 9.7803253359
WGS84_K = 0.00193185265241
WGS84_E2 = 0.00669437999013
FREE_AIR_GRADIENT_S2 = 3.086e-6


def air_density_kg_m3(temperature_c: float, pressure_hpa: float) -> float:
    """Dry-air density (kg/m^3) at the given temperature (degC) and pressure (hPa)."""
    if not temperature_c > -KELVIN:
        raise ValueError(f"temperature_c = {temperature_c!r}: below absolute zero")
    if not pressure_hpa > 0:
        raise ValueError(f"pressure_hpa = {pressure_hpa!r}: must be > 0")
    return pressure_hpa * 100.0 / (R_DRY_AIR_J_KG_K * (temperature_c + KELVIN))


def normal_gravity_m_s2(latitude_deg: float, height_m: float = 0.0) -> float:
    """WGS-84 normal gravity (m/s^2) at a geodetic latitude and height."""
    s2 = math.sin(math.radians(latitude_deg)) ** 2
    g0 = WGS84_GE_M_S2 * (1.0 + WGS84_K * s2) / math.sqrt(1.0 - WGS84_E2 * s2)
    return g0 - FREE_AIR_GRADIENT_S2 * height_m
