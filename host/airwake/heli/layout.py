"""The context schema: every shared intermediate quantity of one model evaluation, with its
fixed slot in a context row.

One evaluation of N rows keeps its intermediates in a float64 array `c` (N, K): row i
holds row i's quantities, each at a fixed slot (vectors occupy consecutive slots). The
numpy `Context` exposes the columns as attributes (`ctx.inflow_0` is `c[:, Q.inflow_0]`,
`ctx.vel_b_m_s` is `c[:, Q.vel_b_m_s:Q.vel_b_m_s + 3]`); compiled kernels index a row
directly (`q[Q.inflow_0]`, `q[Q.vel_b_m_s + 2]`). The layout does not depend on which
effects a model has, so a kernel compiles once for every model.

`Q` is a namedtuple of slot indices (numba freezes it as constants). To share a new
quantity between effects, append a line to `QUANTITIES` (never reorder: the frozen
reference fixture and user code read names, kernels read indices) and regenerate
docs/effects.md. A quantity only one effect uses belongs in that effect's SCRATCH.
"""

from __future__ import annotations

from collections import namedtuple

# name, width, unit, written by, meaning
QUANTITIES: tuple[tuple[str, int, str, str, str], ...] = (
    # model core (from the state, inputs, wind and environment arrays)
    ("vel_b_m_s", 3, "m/s", "core", "body velocity u, v, w"),
    ("omega_b_rad_s", 3, "rad/s", "core", "body rates p, q, r"),
    ("roll_rad", 1, "rad", "core", "Euler roll"),
    ("pitch_rad", 1, "rad", "core", "Euler pitch"),
    ("yaw_rad", 1, "rad", "core", "Euler yaw"),
    ("delta_col_rad", 1, "rad", "core/inputs", "collective command (inputs stage may transform)"),
    ("delta_lat_rad", 1, "rad", "core/inputs", "lateral cyclic command"),
    ("delta_lon_rad", 1, "rad", "core/inputs", "longitudinal cyclic command"),
    ("delta_ped_rad", 1, "rad", "core/inputs", "tail blade-pitch command"),
    ("wind_v_m_s", 3, "m/s", "core", "eq 5.3 wind at the hub: translation v"),
    ("wind_w_rad_s", 3, "rad/s", "core", "eq 5.3 wind: rotation-like coefficient omega"),
    ("height_agl_m", 1, "m", "core", "rotor hub above ground/deck (+inf when unknown)"),
    ("rotor_speed_meas_rad_s", 1, "rad/s", "core", "measured rotor speed (NaN if none)"),
    # environment stage
    ("air_density_kg_m3", 1, "kg/m^3", "atmosphere", "air density (default 1.225)"),
    ("gravity_m_s2", 1, "m/s^2", "gravity", "gravity (default 9.80665)"),
    ("mass_kg", 1, "kg", "rigid_body", "mass"),
    ("inertia", 4, "kg m^2", "rigid_body", "Ixx, Iyy, Izz, Ixz"),
    ("wind_origin_m", 3, "m", "main_rotor", "point the eq 5.3 wind refers to (hub), from CG"),
    ("rotor_sense", 1, "-", "main_rotor", "+1 counter-clockwise / -1 clockwise from above"),
    # rotor speed, hub kinematics (rotor_setup)
    ("rotor_speed_rad_s", 1, "rad/s", "main_rotor", "main-rotor speed used"),
    ("hub_air_velocity_m_s", 3, "m/s", "main_rotor", "air velocity relative to the hub, body"),
    ("advance_ratio", 1, "-", "main_rotor", "mu = |in-plane air velocity| / (Omega R)"),
    ("axial_flow_ratio", 1, "-", "main_rotor", "mu_z = down-flow through the disk / (Omega R)"),
    ("tip_speed_m_s", 1, "m/s", "main_rotor", "Omega R"),
    ("hub_air_velocity_rotor_m_s", 3, "m/s", "main_rotor", "hub air velocity in the rotor frame"),
    ("rel_rotation_rotor_rad_s", 3, "rad/s", "main_rotor",
     "wind rotation minus body rates, rotor frame"),
    ("body_rates_rotor_rad_s", 3, "rad/s", "main_rotor", "body rates in the rotor frame"),
    # blade pitch
    ("swash_c", 1, "rad", "main_rotor", "swashplate cyclic, rotor frame cos psi"),
    ("swash_s", 1, "rad", "main_rotor", "swashplate cyclic, rotor frame sin psi"),
    ("theta_0", 1, "rad", "main_rotor", "main-blade collective pitch"),
    ("theta_c", 1, "rad", "main_rotor/flybar", "main-blade cyclic pitch, cos psi"),
    ("theta_s", 1, "rad", "main_rotor/flybar", "main-blade cyclic pitch, sin psi"),
    # rotor loading and inflow
    ("rotor_load_base", 3, "-", "main_rotor", "C_T, m_c, m_s at zero inflow"),
    ("rotor_load_jac", 9, "-", "main_rotor", "d[C_T, m_c, m_s]/d[l0, lc, ls], row-major 3x3"),
    ("inflow_0", 1, "-", "pitt_peters_inflow", "mean induced inflow / (Omega R)"),
    ("inflow_c", 1, "-", "pitt_peters_inflow", "inflow harmonic cos psi (x rbar)"),
    ("inflow_s", 1, "-", "pitt_peters_inflow", "inflow harmonic sin psi (x rbar)"),
    # rotor results
    ("thrust_n", 1, "N", "main_rotor", "main-rotor thrust"),
    ("thrust_coeff", 1, "-", "main_rotor", "C_T"),
    ("rotor_torque_nm", 1, "N m", "main_rotor", "aerodynamic rotor torque"),
    ("rotor_wake_m_s", 1, "m/s", "main_rotor", "downwash on fuselage and fins"),
    ("flapping_rad", 3, "rad", "main_rotor", "beta_0, beta_c, beta_s"),
    ("tail_pitch_rad", 1, "rad", "tail_rotor", "tail blade pitch"),
    ("tail_thrust_n", 1, "N", "tail_rotor", "tail thrust (along -y)"),
    ("tail_inflow", 1, "-", "tail_rotor", "tail induced inflow"),
    ("tail_wash_m_s", 1, "m/s", "tail_rotor", "tail-rotor wake speed along +y"),
    # totals the body dynamics reads (summed over the effects' loads before body_dynamics)
    ("force_n", 3, "N", "model", "sum of all loads' forces, body axes"),
    ("moment_nm", 3, "N m", "model", "sum of all loads' moments about the CG"),
    ("sensed_force_n", 3, "N", "model", "sum of the forces an accelerometer feels"),
    # measurement (body_dynamics writes it, measurement-stage effects transform it)
    ("meas", 6, "-", "rigid_body", "acc_x/y/z_m_s2 (specific force), pdot/qdot/rdot_rad_s2"),
)

# defaults written into every row before the stages run (all other slots start at 0)
DEFAULTS = {
    "air_density_kg_m3": 1.225,
    "gravity_m_s2": 9.80665,
    "rotor_sense": 1.0,
}

# quantities the old API exposed as per-model scalars: the Context returns a float when
# every row holds the same value (numpy plugins may rely on scalar broadcasting)
SCALAR_LIKE = ("air_density_kg_m3", "gravity_m_s2", "mass_kg", "rotor_sense")


def _slots():
    names, widths, offsets = [], {}, {}
    k = 0
    for name, width, *_ in QUANTITIES:
        names.append(name)
        widths[name] = width
        offsets[name] = k
        k += width
    return names, widths, offsets, k


NAMES, WIDTHS, OFFSETS, N_SLOTS = _slots()
Slots = namedtuple("Slots", NAMES)
Q = Slots(*(OFFSETS[n] for n in NAMES))
