"""The wind fields' numpy implementation as it stood before they were compiled (commit
402bb0c: hil_sim/world/turbulence.py, hil_sim/world/wind/{airwake,fans,simple}.py, and
Ship.pose from the ship's numpy motion), kept frozen as the oracle of
tests/hil_sim/test_wind_compiled.py.

The compiled kernels must give these values to rounding (the difference quotients of
the airwake's stream function amplify an ulp of psi to ~1e-11 m/s). The functions read
the field's own parameters and turbulence box, so they hold for any seed and any numpy
version. A deliberate change of a field's maths changes it here too, in the same commit.
"""

from __future__ import annotations

import numpy as np

from hil_sim.world.kinematics import euler_to_dcm
from hil_sim.world.turbulence import GOLDEN

# -- turbulence.py: FrozenTurbulence.advected / sample -------------------------------


def advected(box, pos_m, t_s, speed_m_s):
    p = np.array(pos_m, dtype=float, copy=True)
    travel = speed_m_s * np.asarray(t_s, dtype=float)
    p[:, 0] -= travel
    p[:, 1] += travel * (GOLDEN * box.config.lateral_drift_m / box.size_m[0])
    return sample(box, p)


def sample(box, pos_m):
    g = np.asarray(pos_m, dtype=float) / box.spacing
    i0 = np.floor(g)
    f = g - i0
    n_cells = np.array(box.shape, dtype=np.int64)
    strides = np.array([box.shape[1] * box.shape[2], box.shape[2], 1], dtype=np.int64)
    i0 = i0.astype(np.int64) % n_cells
    n = g.shape[0]
    idx = np.empty((n, 3, 2), dtype=np.int64)
    idx[:, :, 0] = i0 * strides
    idx[:, :, 1] = ((i0 + 1) % n_cells) * strides
    wts = np.empty((n, 3, 2))
    wts[:, :, 0] = 1.0 - f
    wts[:, :, 1] = f
    flat = idx[:, 0, :, None, None] + idx[:, 1, None, :, None] + idx[:, 2, None, None, :]
    weights = wts[:, 0, :, None, None] * wts[:, 1, None, :, None] * wts[:, 2, None, None, :]
    values = box.field().reshape(-1, 3)[flat.reshape(n, 8)]
    return (values * weights.reshape(n, 8, 1)).sum(axis=1)


# -- ship.py: Ship.pose (from the numpy motion the other Ship methods still use) -------


def ship_pose(ship, t):
    rot = euler_to_dcm(ship._sines(t)[0])
    pos, vel, _ = ship._centre(t)
    return rot, pos - rot @ ship._rc, vel


# -- wind/airwake.py ---------------------------------------------------------------------

_RAMP_M = 0.5
_SOFT_M = 1.0
_DIFF_M = 1e-3
_DISPLACEMENT_TOP_M = 3.0
_DISPLACEMENT_FADE_M = 6.0


def _softplus(x):
    return _SOFT_M * np.logaddexp(0.0, x / _SOFT_M)


def _logcosh(x):
    a = np.abs(x)
    return a + np.log1p(np.exp(-2.0 * a)) - np.log(2.0)


def _shape(f, s):
    c = f.config
    sp = _softplus(s)
    ramp = 0.5 * (1.0 + np.tanh(s / _RAMP_M))
    lr = c.recirculation_length_m
    beyond = np.exp(-_softplus(s - lr) / c.deficit_decay_length_m)
    return {
        "ramp": ramp,
        "deficit": c.wake_deficit * ramp * beyond,
        "beyond": beyond,
        "h_w": f.hangar_height * (1.0 - c.wake_height_drop * np.tanh(sp / lr)),
        "delta": c.shear_layer_thickness_m + c.shear_layer_growth * sp,
        "width": f.wake_width + 2.0 * c.lateral_spread * sp,
        "edge": 0.3 + 0.1 * sp,
        "shed_env": ramp * np.exp(-sp / c.shedding_decay_length_m),
    }


def _lateral(n, shape):
    half = shape["width"] / 2
    return 0.5 * (np.tanh((n + half) / shape["edge"]) - np.tanh((n - half) / shape["edge"]))


def _bubble(f, s, h):
    c = f.config
    half = c.recirculation_length_m / 2
    hb = c.bubble_height_fraction * f.hangar_height
    return 1.0 - ((s - half) / half) ** 2 - (h / hb) ** 2


def stream_function(f, s, h, n, t, unsteady):
    sh = _shape(f, s)
    return _psi(f, sh, _lateral(n, sh), s, h, t, unsteady)


def _psi(f, sh, g, s, h, t, unsteady):
    c = f.config
    u = f.speed
    d, hw = sh["delta"], sh["h_w"]
    integral = 0.5 * (h - d * (_logcosh((h - hw) / d) - _logcosh(-hw / d)))
    fade = np.exp(-_softplus(h - _DISPLACEMENT_TOP_M) / _DISPLACEMENT_FADE_M)
    psi = u * (h - g * sh["deficit"] * integral * fade)
    b = _bubble(f, s, h)
    psi -= np.where((b > 0) & (h > 0), g * c.reverse_flow_fraction * u * h * b * b, 0.0)
    if unsteady and c.shedding_amplitude > 0:
        dv = np.maximum(d, 0.3)
        phase = 2 * np.pi * f.shedding_hz * t - f._k_shed * s
        psi += (g * c.shedding_amplitude * u * dv * np.exp(-((h - hw) / dv) ** 2)
                * sh["shed_env"] * np.sin(phase))
    return psi


def sigma_m_s(f, s, h, n):
    sh = _shape(f, s)
    return _sigma(f, sh, _lateral(n, sh), s, h)


def _sigma(f, sh, g, s, h):
    c = f.config
    dt = sh["delta"] + 0.3
    shear = (c.shear_turbulence_intensity * np.exp(-((h - sh["h_w"]) / dt) ** 2)
             * sh["ramp"] * sh["beyond"])
    bubble = c.bubble_turbulence_intensity * np.clip(_bubble(f, s, h), 0.0, 1.0) * (h > 0)
    return f.speed * (c.ambient_turbulence_intensity + g * (shear + bubble))


def ship_frame_velocity(f, t, snh, unsteady, turbulence):
    s, n, h = snh[:, 0], snh[:, 1], snh[:, 2]
    e = _DIFF_M
    sh0 = _shape(f, s)
    g0 = _lateral(n, sh0)
    shp = _shape(f, s + e)
    shm = _shape(f, s - e)
    u_s = (_psi(f, sh0, g0, s, h + e, t, unsteady)
           - _psi(f, sh0, g0, s, h - e, t, unsteady)) / (2 * e)
    w_up = -(_psi(f, shp, _lateral(n, shp), s + e, h, t, unsteady)
             - _psi(f, shm, _lateral(n, shm), s - e, h, t, unsteady)) / (2 * e)
    if turbulence:
        fluct = advected(f._box, snh, t, f.speed)
        sig = _sigma(f, sh0, g0, s, h)
        along, across, up = u_s + sig * fluct[:, 0], sig * fluct[:, 1], w_up + sig * fluct[:, 2]
    else:
        along, across, up = u_s, 0.0, w_up
    vel = np.empty((s.size, 3))
    vel[:, 0] = along * f.e_s[0] + across * f.e_n[0]
    vel[:, 1] = along * f.e_s[1] + across * f.e_n[1]
    vel[:, 2] = -up
    return vel


def to_wake(f, p_ship):
    return np.stack([p_ship @ f.e_s, p_ship @ f.e_n, -p_ship[:, 2]], axis=-1)


def airwake_velocity(f, t, pos, unsteady, turbulence):
    times, index = np.unique(t, return_inverse=True)
    rot, origin, vel = ship_pose(f.ship, times)
    rot, origin, vel = rot[index], origin[index], vel[index]
    p_ship = ((pos - origin)[:, None, :] @ rot)[:, 0, :]
    w_ship = ship_frame_velocity(f, t, to_wake(f, p_ship), unsteady, turbulence)
    return vel + (rot @ w_ship[:, :, None])[:, :, 0]


# -- wind/fans.py -------------------------------------------------------------------------


def fan_jet(f, pos, fan):
    c = f.config
    origin, axis = f.fans[fan]
    rel = pos - origin
    x = rel @ axis
    radial = rel - np.outer(x, axis)
    r = np.linalg.norm(radial, axis=1)
    big_x = np.maximum(x + f.x0, 0.5 * f.x0)
    fade = 0.5 * (1.0 + np.tanh((x + 0.25 * c.fan_diameter_m) / (0.08 * c.fan_diameter_m)))
    u_c = c.exit_speed_m_s * f.x0 / big_x
    r_half = c.spreading_rate * big_x
    xi = np.log(2.0) * (r / r_half) ** 2
    e = np.exp(-xi)
    safe_xi = np.where(xi > 1e-9, xi, 1.0)
    frac = np.where(xi > 1e-9, -np.expm1(-xi) / safe_xi, 1.0 - xi / 2)
    u_x = u_c * e
    u_r_over_r = -(u_c / (2.0 * big_x)) * (frac - 2.0 * e)
    swirl = (c.swirl_fraction * c.exit_speed_m_s * (f.x0 / big_x) ** 2 / r_half) * e
    vel = (np.outer(u_x, axis) + u_r_over_r[:, None] * radial
           + swirl[:, None] * np.cross(axis, radial))
    return vel * fade[:, None], u_c * fade, xi


def fans_velocity(f, t, pos, unsteady, turbulence):
    c = f.config
    out = np.zeros_like(pos)
    for fan in (0, 1):
        vel, u_c, xi = fan_jet(f, pos, fan)
        out += vel
        if turbulence and c.turbulence_intensity > 0:
            axes = f.frames[fan]
            local = (pos - f.fans[fan][0]) @ axes.T + f._box_offsets[fan]
            fluct = advected(f._box, local, t, c.convection_fraction * c.exit_speed_m_s)
            sigma = c.turbulence_intensity * u_c * np.exp(-xi / 2.25)
            out += sigma[:, None] * (fluct @ axes)
    if turbulence and c.ambient_sigma_m_s > 0:
        fluct = advected(f._box, pos + f._box_offsets[2], t, 0.3)
        out += c.ambient_sigma_m_s * fluct
    return out


# -- wind/simple.py -----------------------------------------------------------------------


def uniform_velocity(f, t, pos, unsteady, turbulence):
    out = np.broadcast_to(f._mean, pos.shape).copy()
    if turbulence and f._box is not None:
        local = pos @ f._axes.T
        fluct = advected(f._box, local, t, f._speed)
        out += f._sigma * (fluct @ f._axes)
    return out


VELOCITY = {
    "ship_airwake": airwake_velocity,
    "fans_indoor": fans_velocity,
    "uniform": uniform_velocity,
    "still_air": lambda f, t, pos, unsteady, turbulence: np.zeros((pos.shape[0], 3)),
}
