"""The evaluation context: every intermediate quantity of one batched model evaluation.

A `Context` is created by `HeliModel.evaluate` for N rows (states, inputs, winds,
environment, parameter sets broadcast together) and passed through the effects'
stages. Effects read what earlier stages produced and write their own results; after
the call it holds the full picture (loads per effect, inflow, thrust, …), which the
discrepancy tools use to explain residuals. All arrays are float64 with a leading
batch axis N; vectors in body axes (x forward, y right, z down), SI units.

Quantities (who sets them):
    n                        batch size
    x (N, S)                 full state; ctx.state(effect) gives that effect's (N, k) slice
    vel_b_m_s (N,3)          body velocity u, v, w                        (model core)
    omega_b_rad_s (N,3)      body rates p, q, r                           (model core)
    roll_rad, pitch_rad, yaw_rad (N,)                                     (model core)
    delta_col_rad, delta_lat_rad, delta_lon_rad, delta_ped_rad (N,)
                             pilot blade-pitch commands (input stage may transform them)
    wind_v_m_s (N,3), wind_w_rad_s (N,3)
                             eq 5.3 local wind at the rotor hub: w(r) = w × r + v, r from hub
    height_agl_m (N,)        rotor hub above ground/deck (+inf when unknown)
    rotor_speed_meas_rad_s (N,)  measured rotor speed (NaN where not measured)
    air_density_kg_m3        (atmosphere)          gravity_m_s2   (gravity)
    mass_kg, inertia         (rigid_body; inertia = (Ixx, Iyy, Izz, Ixz))
    wind_origin_m (3,)/(N,3) point the eq 5.3 wind refers to (main rotor hub), rel. CG
    rotor_speed_rad_s (N,)   main rotor speed used (rotor_speed stage)
    rotor_sense              +1 counter-clockwise / -1 clockwise seen from above (main_rotor)
    hub_air_velocity_m_s (N,3) air velocity relative to the moving hub, body axes
    advance_ratio, axial_flow_ratio (N,)  mu = |in-plane|/(Omega R), mu_z = down-flow/(Omega R)
    theta_0, theta_c, theta_s (N,)   main-blade pitch, rotor frame harmonics (blade_pitch)
    swash_c, swash_s (N,)    swashplate cyclic (before flybar mixing)
    tail_pitch_rad (N,)      tail blade pitch
    inflow_0, inflow_c, inflow_s (N,)   Pitt-Peters inflow harmonics (inflow stage)
    thrust_n, thrust_coeff, rotor_torque_nm, rotor_wake_m_s (N,)   (main_rotor forces)
    tail_thrust_n, tail_wash_m_s (N,)                               (tail_rotor)
    loads                    {effect name: (F (N,3), M (N,3), sensed: bool)}
    xdot (N, S)              state derivatives (state_rates + body_dynamics)
    meas (N, 6)              predicted measurement, channels MEAS_CHANNELS
"""

from __future__ import annotations

import numpy as np

MEAS_CHANNELS = (
    "acc_x_m_s2",
    "acc_y_m_s2",
    "acc_z_m_s2",
    "pdot_rad_s2",
    "qdot_rad_s2",
    "rdot_rad_s2",
)


def cross(a, b) -> np.ndarray:
    """a x b for (..., 3) arrays (np.cross is slow for small batches)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], -1)


class Context:
    """Intermediate quantities of one batched evaluation (see module docstring)."""

    def __init__(self, model, x, n: int) -> None:
        self.model = model
        self.n = n
        self.x = x
        self.xdot = np.zeros_like(x)
        self.loads: dict[str, tuple[np.ndarray, np.ndarray, bool]] = {}
        self.meas = np.zeros((n, len(MEAS_CHANNELS)))
        self.air_density_kg_m3 = 1.225
        self.gravity_m_s2 = 9.80665
        self.wind_origin_m = np.zeros(3)
        self.rotor_sense = 1.0
        self._cache: dict[str, object] = {}

    # -- states -------------------------------------------------------------------
    def state(self, effect: str) -> np.ndarray:
        """(N, k) view of `effect`'s own states."""
        sl = self.model.state_slice(effect)
        return self.x[:, sl]

    def set_rates(self, effect: str, rates: np.ndarray) -> None:
        """Write d/dt of `effect`'s own states, (N, k)."""
        self.xdot[:, self.model.state_slice(effect)] = rates

    # -- loads --------------------------------------------------------------------
    def add_load(self, effect: str, force_n, moment_nm, sensed: bool = True) -> None:
        """Add a force/moment (body axes, about the CG). `sensed=False` for gravity-like
        field forces that an accelerometer does not measure."""
        f = np.broadcast_to(force_n, (self.n, 3))
        m = np.broadcast_to(moment_nm, (self.n, 3))
        if effect in self.loads:
            f0, m0, s0 = self.loads[effect]
            f, m = f0 + f, m0 + m
        self.loads[effect] = (f, m, sensed)

    def total_load(self, sensed_only: bool = False) -> tuple[np.ndarray, np.ndarray]:
        f = np.zeros((self.n, 3))
        m = np.zeros((self.n, 3))
        for fi, mi, sensed in self.loads.values():
            if sensed or not sensed_only:
                f = f + fi
                m = m + mi
        return f, m

    # -- kinematics helpers ---------------------------------------------------------
    def air_velocity_at(self, r_m) -> np.ndarray:
        """Air velocity relative to the body point r (body axes, from CG), (N,3):
        eq 5.3 wind at r minus the point's velocity v_H + omega_H x r."""
        r = np.asarray(r_m, dtype=float)
        rel = r - self.wind_origin_m
        wind = self.wind_v_m_s + cross(self.wind_w_rad_s, rel)
        return wind - (self.vel_b_m_s + cross(self.omega_b_rad_s, r))

    def meas_dict(self) -> dict[str, np.ndarray]:
        return {c: self.meas[:, i] for i, c in enumerate(MEAS_CHANNELS)}
