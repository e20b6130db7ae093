"""Truth wake recirculation: a ground vortex and its image induce downwash on the disk.

Observation (Curtiss, H. C., Sun, M., Putman, W. F. & Hanker, E. J. (1984), "Rotor
aerodynamics in ground effect at low advance ratios", Journal of the American
Helicopter Society 29(1): 48-55): at low speed near the ground the rotor's wall jet
running forward against the oncoming air separates and rolls up into a "ground
vortex" upstream of the rotor; as the speed rises the vortex moves aft, under the
leading edge and the disk, and is finally swept behind the rotor. While it sits under
the front of the disk the rotor re-ingests its own wake: induced power rises and a
nose-up/roll moment appears.

Model (our own potential-flow idealisation of that picture): a straight spanwise line
vortex of circulation Gamma at x_v ahead of the hub (along the oncoming air) and height
y_c above the ground, with its image (-Gamma at -y_c) so the ground is a streamline, and
a viscous core r_c (Scully-type 1/(r^2 + r_c^2)). Its downwash at a disk point x
(upstream positive) at hub height z:

    w(x) = -(Gamma / 2 pi) (x - x_v) [1 / (dx^2 + (z - y_c)^2 + r_c^2)
                                       - 1 / (dx^2 + (z + y_c)^2 + r_c^2)]

(positive down: between the vortex and the hub the wall jet's return flow comes down
through the disk). Strength and place from the wall jet, mu* = V / v_h (V the in-plane
air speed at the hub, v_h = Omega R sqrt(C_T / 2) the hover induced velocity):

    Gamma = k v_h R (1 - (mu*/mu_s)^2)^2 exp(-z / (h_e R))    (0 for mu* >= mu_s)
    x_v   = x_0 R / mu*,   y_c = c_h z,   r_c = c_r R

(the wall jet's reach against the oncoming air falls as 1/V; the vortex is gone when
the wake meets the ground behind the disk, mu* >= mu_s; a higher rotor feeds a weaker
wall jet). The disk mean and the upstream gradient of w (chord-weighted Gauss-Chebyshev
quadrature across the disk, 12 stations) are added to lambda_0 and, along the oncoming
flow, to lambda_c / lambda_s: a thrust loss and a disk tilt at low height and low
speed, none in hover (the vortex is infinitely far) and none at speed.
"""

from __future__ import annotations

import math

import numpy as np
from airwake.heli.effects.base import Effect, Parameter
from airwake.heli.kernel import Q, kernel

N_STATIONS = 12
_THETA = np.arange(1, N_STATIONS + 1) * np.pi / (N_STATIONS + 1)
STATIONS = np.cos(_THETA)  # x/R across the disk, upstream positive
WEIGHTS = 2.0 / (N_STATIONS + 1) * np.sin(_THETA) ** 2  # disk-area mean: sum = 1


class GroundVortexRecirculation(Effect):
    """Ground-vortex downwash on the disk (inflow stage; module docstring)."""

    name = "hil_ground_vortex"
    PARAMETERS = (
        Parameter("circulation_ratio", 2.0, "-", (0.0, 10.0), "k = Gamma / (v_h R)"),
        Parameter("position_ratio", 1.0, "-", (0.2, 5.0), "x_0: x_v / R at V = v_h"),
        Parameter("sweep_ratio", 2.0, "-", (0.5, 5.0), "mu_s: V / v_h with no vortex"),
        Parameter("core_height_ratio", 0.4, "-", (0.05, 0.9), "c_h = y_c / z"),
        Parameter("core_radius_ratio", 0.1, "-", (0.01, 1.0), "c_r = r_c / R"),
        Parameter("decay_height_ratio", 2.0, "-", (0.2, 10.0), "h_e: wall-jet decay / R"),
        Parameter("rotor_radius_m", 0.6645, "m", (0.2, 1.5), "truth main rotor R", fixed=True),
    )
    STATIONS = STATIONS
    WEIGHTS = WEIGHTS

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        z = q[Q.height_agl_m]
        if not (z > 0.0 and math.isfinite(z)):
            return
        radius = p.rotor_radius_m
        tip = q[Q.rotor_speed_rad_s] * radius
        j = q[Q.rotor_load_jac:Q.rotor_load_jac + 9]
        ct = (q[Q.rotor_load_base] + j[0] * q[Q.inflow_0] + j[1] * q[Q.inflow_c]
              + j[2] * q[Q.inflow_s])
        if not (ct > 0.0 and tip > 0.0):
            return
        v_h = tip * math.sqrt(0.5 * ct)
        vx = q[Q.hub_air_velocity_rotor_m_s]
        vy = q[Q.hub_air_velocity_rotor_m_s + 1]
        speed = math.hypot(vx, vy)
        mu_star = speed / v_h
        if mu_star <= 1e-3 or mu_star >= p.sweep_ratio:
            return
        form = (1.0 - (mu_star / p.sweep_ratio) ** 2) ** 2
        gamma = (p.circulation_ratio * v_h * radius * form
                 * math.exp(-z / (p.decay_height_ratio * radius)))
        x_v = p.position_ratio * radius / mu_star
        y_c = p.core_height_ratio * z
        rc2 = (p.core_radius_ratio * radius) ** 2
        above = (z - y_c) ** 2 + rc2
        image = (z + y_c) ** 2 + rc2
        mean = 0.0
        moment = 0.0
        for i in range(N_STATIONS):
            x = STATIONS[i]
            dx = x * radius - x_v
            w = -gamma / (2.0 * math.pi) * dx * (1.0 / (dx * dx + above)
                                                  - 1.0 / (dx * dx + image))
            mean += WEIGHTS[i] * w
            moment += WEIGHTS[i] * w * x
        d0 = mean / tip
        grad = 4.0 * moment / tip  # upstream gradient per rbar (mean of x^2 is 1/4)
        # upstream unit vector u_up = -v/|v|; e_r(psi) = (-cos psi, sin psi) (rotor frame)
        q[Q.inflow_0] = q[Q.inflow_0] + d0
        q[Q.inflow_c] = q[Q.inflow_c] + grad * vx / speed
        q[Q.inflow_s] = q[Q.inflow_s] - grad * vy / speed

    def rest_state(self, u: np.ndarray, ctx) -> np.ndarray:
        return np.zeros(0)

    def linear_values(self) -> dict:
        return {}
