"""Truth ground/deck effect: Hayden's empirical fit, a wake-footprint forward-flight fade,
the thrust-consistent inflow and a finite deck.

Sources:
- Hayden, J. S. (1976), "The Effect of the Ground on Helicopter Hovering Power
  Required", 32nd Annual Forum of the American Helicopter Society: a fit to flight-test
  hover data at constant thrust,
      P_IGE / P_OGE = 1 / (A + B (2R/z)^2),   A = 0.9926, B = 0.0379,
  z the rotor height above the ground. Taken here as the induced-velocity ratio at
  constant thrust (induced power = T v_i) and divided by its own far value 1/A so that
  it is exactly 1 out of ground effect (the host model is calibrated there):
      k_H(z) = v_IGE / v_OGE = A / (A + B (2R/z)^2)            (k_H = 0.867 at z = R)
- Wake skew angle (Coleman, Feingold & Stempin 1945, NACA ARR L5E10):
  tan chi = mu / lambda_t, lambda_t the total inflow through the disk. Our own geometric
  fade on it: the wake column leaves the disk skewed by chi and meets the ground
  displaced downstream by d = z tan chi; only the part of the disk whose wake footprint
  still lies under the disk feels the ground's blockage, the overlap share of two
  circles of radius R at distance d (1 in hover, 0 for d >= 2R):
      c(d) = (2/pi) (acos(s) - s sqrt(1 - s^2)),   s = d / 2R
  Reduction of the induced velocity: Delta = (1 - k_H) c.
- Thrust consistency: Hayden's ratio is at *constant thrust*; at fixed blade pitch the
  lower inflow raises the thrust, which needs more inflow. With C_T affine in lambda_0
  (dC_T/dlambda_0 = J_00 < 0, the rotor's load Jacobian) and momentum theory
  lambda_0 = C_T / (2 V_T) (dlambda_0/dC_T = 1 / (2 V_T + 2 lambda_0 lambda_t / V_T)),
  the fixed-pitch solution of lambda' = k lambda_OGE(C_T(lambda')) linearised about the
  host's out-of-ground inflow lambda_s is
      lambda' = k lambda_s (1 - a) / (1 - k a),   a = J_00 dlambda_0/dC_T,  k = 1 - Delta
- Finite deck (`deck_height_equivalent`, world side): on a ship the parts of the disk
  over the deck, the hangar roof and the sea each have their own ground distance; the
  disk-mean reduction mean_i Delta(z_i) is passed to the rotor as the height z_eq with
  Delta(z_eq) = that mean, so the effect falls as the disk moves off the deck edge.
"""

from __future__ import annotations

import math

import numpy as np
from airwake.heli.effects.base import Effect, Parameter
from airwake.heli.kernel import Q, kernel, kernel_function

HAYDEN_INTERCEPT = 0.9926
HAYDEN_SLOPE = 0.0379


def hayden_power_ratio(height_over_radius, intercept: float = HAYDEN_INTERCEPT,
                       slope: float = HAYDEN_SLOPE):
    """Hayden's P_IGE/P_OGE at constant thrust (as published, not normalised)."""
    zr = np.asarray(height_over_radius, dtype=float)
    return 1.0 / (intercept + slope * (2.0 / zr) ** 2)


@kernel_function
def footprint_overlap(d_over_radius):
    """Share of the disk area over its own wake footprint displaced by d (circles of
    radius 1 at distance d): 1 at d = 0, 0 from d = 2."""
    s = 0.5 * d_over_radius
    if s >= 1.0:
        return 0.0
    s = max(s, 0.0)
    return (2.0 / math.pi) * (math.acos(s) - s * math.sqrt(1.0 - s * s))


class GroundEffect(Effect):
    """Hayden's ground effect, thrust-consistent, faded by the wake footprint (inflow
    stage; module docstring). Reads height_agl_m (the ground-plane height: on a ship the
    deck-averaged equivalent), advance_ratio, axial_flow_ratio, rotor_load_jac."""

    name = "hil_hayden_ground_effect"
    PARAMETERS = (
        Parameter("power_ratio_intercept", HAYDEN_INTERCEPT, "-", (0.8, 1.2), "Hayden 1976 A"),
        Parameter("power_ratio_slope", HAYDEN_SLOPE, "-", (0.0, 0.2), "Hayden 1976 B"),
        Parameter("min_height_ratio", 0.4, "-", (0.2, 2.0), "fit held below this z/R",
                  fixed=True),
        Parameter("rotor_radius_m", 0.6645, "m", (0.2, 1.5), "truth main rotor R", fixed=True),
    )

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        radius = p.rotor_radius_m
        z = q[Q.height_agl_m]
        if not z > 0.0:  # NaN or at/below the ground: no ground plane known
            return
        zr = max(z / radius, p.min_height_ratio)
        image = p.power_ratio_slope * (2.0 / zr) ** 2
        if image == 0.0:  # z = +inf: out of ground effect, exactly
            return
        k_hayden = p.power_ratio_intercept / (p.power_ratio_intercept + image)
        lam0 = q[Q.inflow_0]
        lam_t = lam0 + q[Q.axial_flow_ratio]
        mu = q[Q.advance_ratio]
        if lam_t <= 1e-6:  # no wake carried down to the ground (vortex ring, windmill)
            return
        cover = footprint_overlap(zr * mu / lam_t)  # d/R = (z/R) tan chi
        if cover == 0.0:  # the wake meets the ground behind the disk
            return
        k = 1.0 - (1.0 - k_hayden) * cover
        v_t = math.sqrt(mu * mu + lam_t * lam_t)
        dlam_dct = 1.0 / (2.0 * v_t + 2.0 * lam0 * lam_t / v_t)
        a = q[Q.rotor_load_jac] * dlam_dct
        q[Q.inflow_0] = k * lam0 * (1.0 - a) / (1.0 - k * a)

    def rest_state(self, u: np.ndarray, ctx) -> np.ndarray:
        return np.zeros(0)

    def linear_values(self) -> dict:
        return {}


def hayden_reduction(height_over_radius, intercept: float = HAYDEN_INTERCEPT,
                     slope: float = HAYDEN_SLOPE) -> np.ndarray:
    """Delta(z) = 1 - k_H(z): the share of the induced velocity the ground removes."""
    zr = np.asarray(height_over_radius, dtype=float)
    image = slope * (2.0 / zr) ** 2
    return image / (intercept + image)


def equivalent_height_over_radius(reduction, intercept: float = HAYDEN_INTERCEPT,
                                  slope: float = HAYDEN_SLOPE) -> np.ndarray:
    """The inverse of `hayden_reduction`: z/R with Delta(z) = reduction (inf for 0)."""
    d = np.asarray(reduction, dtype=float)
    with np.errstate(divide="ignore"):
        zr = 2.0 * np.sqrt(slope * (1.0 - d) / (intercept * np.maximum(d, 1e-300)))
    return np.where(d > 0, zr, np.inf)


# Disk sample points for the deck average: 3 rings (r/R = 0.35, 0.7, 0.95) x 8 azimuths
# plus the hub, area-weighted.
_RINGS = np.array([0.35, 0.7, 0.95])
_AZ = np.arange(8) * (2.0 * np.pi / 8)
DISK_POINTS = np.concatenate([[[0.0, 0.0]], np.array(
    [[r * np.cos(a), r * np.sin(a)] for r in _RINGS for a in _AZ])])
_RING_AREA = np.diff(np.r_[0.0, 0.5 * (_RINGS[:-1] + _RINGS[1:]), 1.0] ** 2)
DISK_WEIGHTS = np.concatenate([[_RING_AREA[0] * 0.25], np.repeat(
    np.r_[_RING_AREA[0] * 0.75, _RING_AREA[1:]] / 8.0, 8)])


def deck_height_equivalent(heights_m: np.ndarray, radius_m: float, config) -> float:
    """Equivalent ground-plane height (m) for a disk whose sample points (DISK_POINTS)
    stand `heights_m` above what is under each (deck, hangar roof, sea): the height at
    which Hayden's reduction equals its disk-weighted mean (module docstring)."""
    zr = np.maximum(np.asarray(heights_m, float) / radius_m, config.min_height_ratio)
    mean = float(DISK_WEIGHTS @ hayden_reduction(zr, config.power_ratio_intercept,
                                                 config.power_ratio_slope))
    return float(equivalent_height_over_radius(mean, config.power_ratio_intercept,
                                               config.power_ratio_slope)) * radius_m
