"""Ship airwake behind a hangar step (§2.1, §4.5.1), a kinematic model in the ship frame.

Coordinates: the relative wind (speed U, heading beta from the bow, + starboard) blows
along e_s = -(cos beta, sin beta, 0) in the ship frame. A point is described by
s = downstream distance from the step along e_s, n = lateral offset, and
h = height above the deck plane.

Mean flow and vortex shedding come from one stream function in the (s, h) plane (so
they are divergence-free in that plane; u_s = d psi / dh, w_up = -d psi / ds, taken by
central differences):

    psi = U [h - g D(s) I(h; s)] + g psi_bubble + g psi_shed

- wake deficit D(s) = D0 * ramp(s) * exp(-softplus(s - L_r) / L_d): starts at the
  step, holds through the recirculation zone, decays with distance beyond it (its
  displacement flow — downwash where the wake recovers — fades above ~3 m); profile
  phi = (1 - tanh((h - H_w(s)) / delta(s))) / 2 (a shear layer at height H_w that starts
  at the hangar top and sinks toward reattachment, thickness delta = delta0 + a s),
  I = integral of phi dh (closed form with log-cosh);
- recirculation bubble: psi_b = -K U h (1 - rho^2)^2 inside the half-ellipse
  rho^2 = ((s - L_r/2) / (L_r/2))^2 + (h / H_b)^2 < 1 (length L_r, default 7.5 m:
  the 5-10 m aft of the step the brief and §4.5.1 give), giving reversed flow
  ~(K - (1 - D0)) U near the deck and flow-along at its top;
- vortex shedding: a train of shear-layer vortices,
  psi_v = A U delta_v exp(-((h - H_w) / delta_v)^2) E(s) sin(2 pi f t - k s), with
  f = St U / H_hangar (St = 0.25: 0.5 Hz at 3 m/s over a 1.5 m hangar; §4.5.1 gives
  0.544 Hz for 3.2 m/s), convected at c U (k = 2 pi f / (c U)), decaying downstream;
- g(s, n): a smoothed top-hat across the wake width (the hangar's projected width
  normal to the wind, spreading downstream).

Turbulence: the frozen box (turbulence.py) aligned with (s, n, h), advected at U, times
a local sigma = U [TI_ambient + g (TI_shear exp(-((h - H_w) / delta_t)^2) E_t(s)
+ TI_bubble B(s, h))] — strongest in the shear layer, present in the bubble, decaying
downstream.

In NED: v = v_ship(t) + R_ship(t) w_ship (the wake moves and tilts with the ship).
Simplifications (documented, not hidden): no lateral (n) mean velocity, no side-edge
vortices for oblique wind, the wake rotated rigidly with beta.

Evaluation: compiled (numba), one point at a time — the ship's pose once per distinct
time, the wake coordinates, the five-point stencil of psi, the box — as the
blade-element truth samples it on its body grid every few milliseconds. The numpy
version it replaced is kept as the tests' reference (tests/hil_sim/wind_reference.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numba
import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive, check_range
from hil_sim.world.ship import Ship
from hil_sim.world.turbulence import (
    FrozenTurbulence,
    TurbulenceConfig,
    TurbulenceGrid,
    advected_point,
)
from hil_sim.world.wind import increments as inc
from hil_sim.world.wind.base import WindField

_SOFT_M = 1.0  # smoothing length of softplus
_RAMP_M = _SOFT_M / 2  # width of the wake onset at the step (SOFT / 2: see _column)
_DIFF_M = 1e-3  # central-difference step of the stream function
_DISPLACEMENT_TOP_M = 3.0  # the wake's displacement flow fades above this height ...
_DISPLACEMENT_FADE_M = 6.0  # ... over this length (no vertical wind far above the ship)


def _airwake_turbulence() -> TurbulenceConfig:
    return TurbulenceConfig(length_scale_m=1.0, grid_spacing_m=0.25, box_m=(128.0, 16.0, 16.0))


@dataclass(frozen=True)
class ShipAirwakeConfig:
    """Airwake settings; hangar size and ship motion come from the `Ship`."""

    relative_wind_speed_m_s: float = 3.0
    relative_wind_heading_deg: float = 0.0
    recirculation_length_m: float = 7.5
    bubble_height_fraction: float = 0.8
    reverse_flow_fraction: float = 0.4
    wake_deficit: float = 1.0
    deficit_decay_length_m: float = 15.0
    shear_layer_thickness_m: float = 0.15
    shear_layer_growth: float = 0.08
    wake_height_drop: float = 0.3
    lateral_spread: float = 0.1
    strouhal_number: float = 0.25
    shedding_amplitude: float = 0.15
    shedding_convection_fraction: float = 0.6
    shedding_decay_length_m: float = 12.0
    ambient_turbulence_intensity: float = 0.05
    shear_turbulence_intensity: float = 0.25
    bubble_turbulence_intensity: float = 0.15
    turbulence: TurbulenceConfig = field(default_factory=_airwake_turbulence)

    def __post_init__(self) -> None:
        check_positive("relative_wind_speed_m_s", self.relative_wind_speed_m_s)
        check_range("relative_wind_heading_deg", self.relative_wind_heading_deg, -90.0, 90.0)
        for name in ("recirculation_length_m", "bubble_height_fraction",
                     "deficit_decay_length_m", "shear_layer_thickness_m", "strouhal_number",
                     "shedding_convection_fraction", "shedding_decay_length_m"):
            check_positive(name, getattr(self, name))
        for name in ("reverse_flow_fraction", "shear_layer_growth", "lateral_spread",
                     "shedding_amplitude", "ambient_turbulence_intensity",
                     "shear_turbulence_intensity", "bubble_turbulence_intensity"):
            check_nonnegative(name, getattr(self, name))
        check_range("wake_deficit", self.wake_deficit, 0.0, 1.5)
        check_range("wake_height_drop", self.wake_height_drop, 0.0, 0.9)
        check_finite("relative_wind_heading_deg", self.relative_wind_heading_deg)


class AirwakeParams(NamedTuple):
    """What the compiled maths reads: the config's values, derived sizes, reciprocals."""

    speed: float  # U, m/s
    hangar_height: float
    wake_width: float
    recirculation_length: float  # L_r
    inv_recirculation_length: float
    bubble_half_length: float  # L_r / 2
    inv_bubble_half_length: float
    inv_bubble_height: float
    reverse_flow_fraction: float
    wake_deficit: float
    inv_deficit_decay_length: float
    shear_layer_thickness: float
    shear_layer_growth: float
    wake_height_drop: float
    lateral_spread: float
    shedding: float  # A U (0: no shedding)
    inv_shedding_decay_length: float
    omega_shed: float  # 2 pi f, rad/s
    k_shed: float  # rad/m
    cos_k_diff: float  # cos, sin of k_shed * DIFF (the phase step to s +- DIFF)
    sin_k_diff: float
    ambient_ti: float
    shear_ti: float
    bubble_ti: float
    e_s_x: float  # e_s, e_n in ship axes (horizontal)
    e_s_y: float
    e_s_z: float
    e_n_x: float
    e_n_y: float
    e_n_z: float


def _airwake_params(f: ShipAirwake) -> AirwakeParams:
    c = f.config
    lr = c.recirculation_length_m
    shedding = c.shedding_amplitude * f.speed
    return AirwakeParams(*(float(v) for v in (
        f.speed, f.hangar_height, f.wake_width, lr, 1.0 / lr, lr / 2, 2 / lr,
        1.0 / (c.bubble_height_fraction * f.hangar_height), c.reverse_flow_fraction,
        c.wake_deficit, 1.0 / c.deficit_decay_length_m, c.shear_layer_thickness_m,
        c.shear_layer_growth, c.wake_height_drop, c.lateral_spread, shedding,
        1.0 / c.shedding_decay_length_m, 2 * np.pi * f.shedding_hz, f._k_shed,
        math.cos(f._k_shed * _DIFF_M), math.sin(f._k_shed * _DIFF_M),
        c.ambient_turbulence_intensity, c.shear_turbulence_intensity,
        c.bubble_turbulence_intensity, *f.e_s, *f.e_n)))


class WakeColumn(NamedTuple):
    """The wake at one s for a lateral offset n (module doc): its profile, the factors of
    psi that depend on s, n and t only, and the values a stencil neighbour steps from."""

    s: float
    ramp: float
    beyond: float  # decay past the bubble
    g: float  # g(s, n)
    h_w: float  # shear-layer height H_w(s)
    delta: float  # shear-layer thickness delta(s)
    inv_delta: float
    g_deficit: float  # g D(s)
    ground: float  # ln cosh(y), y = -H_w / delta: the integral I from h = 0
    inv_dv: float  # 1 / shedding-vortex size
    shed: float  # g A U dv E(s) sin(2 pi f t - k s); 0 without shedding
    # ... at x = s / SOFT: exp(-|x|), softplus and sigmoid of x and of x - L_r / SOFT,
    # tanh(sp / L_r), the two lateral tanh arguments and values, exp(-sp / L_shed), y
    x: float
    em: float
    sp: float
    sig: float
    x_lr: float
    sp_lr: float
    sig_lr: float
    x_hw: float
    t_hw: float
    xa: float
    ta: float
    xb: float
    tb: float
    shed_decay: float
    y: float
    t_ground: float


# The maths of the module doc, one point at a time (numba). Its cost is the exponentials
# and logarithms (a library call each in a scalar loop), so the stencil of the central
# differences (s, h +- DIFF), (s +- DIFF, h) takes its neighbours' values from the
# centre's by the addition theorems of increments.py, and tanh costs one exp. The values
# equal the numpy version's (tests/hil_sim/wind_reference.py) to ~1e-11 m/s: the
# difference quotients turn an ulp of psi into that.

_INV_2DIFF = 1.0 / (2 * _DIFF_M)


# Inlined where it is called (numba IR): as a call, its ~60 arguments and 27 results
# cost a fifth of the airwake's time; compiling takes ~5 s longer (once, cached).
@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST, inline="always")
def _column(s: float, n: float, shedding: bool, sin_phase: float, p: AirwakeParams,
            near=None) -> WakeColumn:
    """The wake at s for lateral offset n; with shedding, sin_phase = sin(2 pi f t - k s).
    Given `near`, the column at a nearby s, its values step from near's."""
    x = s / _SOFT_M
    x_lr = (s - p.recirculation_length) / _SOFT_M
    if near is None:
        em = math.exp(-abs(x))
        sp, sig = inc.softplus(x, em)
        sp_lr, sig_lr = inc.softplus(x_lr, math.exp(-abs(x_lr)))
        beyond = math.exp(-_SOFT_M * sp_lr * p.inv_deficit_decay_length)
    else:
        em = near.em * inc.exp_small(abs(near.x) - abs(x))
        sp, sig = inc.softplus_step(near.sp, near.sig, near.x, x)
        sp_lr, sig_lr = inc.softplus_step(near.sp_lr, near.sig_lr, near.x_lr, x_lr)
        beyond = near.beyond * inc.exp_small(
            -_SOFT_M * (sp_lr - near.sp_lr) * p.inv_deficit_decay_length)
    em2 = em * em
    ramp = 0.5 * (1.0 + inc.tanh_of(s, em2 * em2))  # tanh(s / RAMP): exp(-2|s| / RAMP) = em^4
    sp_m = _SOFT_M * sp  # softplus(s), m
    x_hw = sp_m * p.inv_recirculation_length
    t_hw = inc.tanh(x_hw) if near is None else inc.tanh_step(near.t_hw, near.x_hw, x_hw)
    h_w = p.hangar_height * (1.0 - p.wake_height_drop * t_hw)
    delta = p.shear_layer_thickness + p.shear_layer_growth * sp_m
    # g(s, n): the smoothed top-hat across the wake width
    half = (p.wake_width + 2.0 * p.lateral_spread * sp_m) / 2
    inv_edge = 1.0 / (0.3 + 0.1 * sp_m)
    xa, xb = (n + half) * inv_edge, (n - half) * inv_edge
    if near is None:
        ta, tb = inc.tanh(xa), inc.tanh(xb)
    else:
        ta, tb = inc.tanh_step(near.ta, near.xa, xa), inc.tanh_step(near.tb, near.xb, xb)
    g = 0.5 * (ta - tb)
    dv = max(delta, 0.3)
    shed_decay = shed = 0.0
    if shedding:
        if near is None:
            shed_decay = math.exp(-sp_m * p.inv_shedding_decay_length)
        else:
            shed_decay = near.shed_decay * inc.exp_small(
                -(sp_m - _SOFT_M * near.sp) * p.inv_shedding_decay_length)
        shed = g * p.shedding * dv * (ramp * shed_decay) * sin_phase
    inv_delta = 1.0 / delta
    y = -h_w * inv_delta
    if near is None:
        ground, t_ground = inc.logcosh(y)
    else:
        ground, t_ground = inc.logcosh_step(near.ground, near.t_ground, near.y, y)
    return WakeColumn(s, ramp, beyond, g, h_w, delta, inv_delta,
                      g * p.wake_deficit * ramp * beyond, ground, 1.0 / dv, shed,
                      x, em, sp, sig, x_lr, sp_lr, sig_lr, x_hw, t_hw, xa, ta, xb, tb,
                      shed_decay, y, t_ground)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _bubble(s: float, h: float, p: AirwakeParams) -> float:
    """1 - rho^2 of the recirculation half-ellipse (<= 0 outside)."""
    return (1.0 - ((s - p.bubble_half_length) * p.inv_bubble_half_length) ** 2
            - (h * p.inv_bubble_height) ** 2)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _psi_at(col: WakeColumn, h: float, fade: float, lc: float, gauss: float,
            p: AirwakeParams) -> float:
    """psi = U [h - g D(s) I(h; s) fade(h)] + g psi_bubble + g psi_shed (module doc),
    I = (h - delta [ln cosh((h - H_w) / delta) - ln cosh(-H_w / delta)]) / 2; lc is that
    first ln cosh, gauss = exp(-((h - H_w) / dv)^2)."""
    u = p.speed
    integral = 0.5 * (h - col.delta * (lc - col.ground))
    psi = u * (h - col.g_deficit * integral * fade)
    b = _bubble(col.s, h, p)
    if b > 0 and h > 0:
        psi -= col.g * p.reverse_flow_fraction * u * h * b * b
    if col.shed != 0.0:
        psi += col.shed * gauss
    return psi


class Centre(NamedTuple):
    """At the stencil's centre (s, h): ln cosh and tanh of z = (h - H_w) / delta, the
    vortex Gaussian exp(-w^2) of w = (h - H_w) / dv."""

    z: float
    lc: float
    tz: float
    w: float
    gauss: float


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _psi_near(col: WakeColumn, h: float, fade: float, c: Centre, p: AirwakeParams
              ) -> float:
    """psi at a stencil point, its ln cosh and Gaussian stepped from the centre's."""
    z = (h - col.h_w) * col.inv_delta
    lc = inc.logcosh_step(c.lc, c.tz, c.z, z)[0]
    gauss = 0.0
    if col.shed != 0.0:
        w = (h - col.h_w) * col.inv_dv
        gauss = c.gauss * inc.exp_small(-(w - c.w) * (w + c.w))
    return _psi_at(col, h, fade, lc, gauss, p)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _fade(h: float) -> tuple[float, float, float, float]:
    """The displacement flow's fade with height, exp(-softplus(h - TOP) / FADE), and the
    softplus argument, value and sigmoid a neighbour steps from."""
    y = (h - _DISPLACEMENT_TOP_M) / _SOFT_M
    sp, sig = inc.softplus(y, math.exp(-abs(y)))
    return math.exp(-_SOFT_M * sp / _DISPLACEMENT_FADE_M), y, sp, sig


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _fade_near(h: float, fade0: float, y0: float, sp0: float, sig0: float) -> float:
    y = (h - _DISPLACEMENT_TOP_M) / _SOFT_M
    sp = inc.softplus_step(sp0, sig0, y0, y)[0]
    return fade0 * inc.exp_small(-_SOFT_M * (sp - sp0) / _DISPLACEMENT_FADE_M)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _psi(s: float, n: float, h: float, t: float, unsteady: bool, p: AirwakeParams) -> float:
    shedding = unsteady and p.shedding > 0
    col = _column(s, n, shedding, math.sin(p.omega_shed * t - p.k_shed * s), p)
    lc = inc.logcosh((h - col.h_w) * col.inv_delta)[0]
    gauss = math.exp(-((h - col.h_w) * col.inv_dv) ** 2)
    return _psi_at(col, h, _fade(h)[0], lc, gauss, p)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _sigma(col: WakeColumn, h: float, p: AirwakeParams) -> float:
    """Local turbulence std (m/s) per component."""
    dt = col.delta + 0.3
    shear = p.shear_ti * math.exp(-((h - col.h_w) / dt) ** 2) * col.ramp * col.beyond
    bubble = p.bubble_ti * min(max(_bubble(col.s, h, p), 0.0), 1.0) * (1.0 if h > 0 else 0.0)
    return p.speed * (p.ambient_ti + col.g * (shear + bubble))


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _ship_frame_point(s: float, n: float, h: float, t: float, unsteady: bool,
                      turbulence: bool, p: AirwakeParams, box: TurbulenceGrid
                      ) -> tuple[float, float, float]:
    """Air velocity relative to the ship (ship axes) at wake coordinates (s, n, h):
    u_s = d psi / dh, w_up = -d psi / ds by central differences on the stencil
    (s, h +- DIFF), (s +- DIFF, h), plus sigma times the box advected at U."""
    e = _DIFF_M
    shedding = unsteady and p.shedding > 0
    sin0 = sin_p = sin_m = 0.0
    if shedding:  # sin(phi), sin(phi -+ k DIFF) at s +- DIFF
        phase = p.omega_shed * t - p.k_shed * s
        sin0, cos0 = math.sin(phase), math.cos(phase)
        sin_p = sin0 * p.cos_k_diff - cos0 * p.sin_k_diff
        sin_m = sin0 * p.cos_k_diff + cos0 * p.sin_k_diff
    col0 = _column(s, n, shedding, sin0, p)
    col_p = _column(s + e, n, shedding, sin_p, p, col0)
    col_m = _column(s - e, n, shedding, sin_m, p, col0)
    fade, y, sp, sig = _fade(h)
    z = (h - col0.h_w) * col0.inv_delta
    lc, tz = inc.logcosh(z)
    w = (h - col0.h_w) * col0.inv_dv
    c = Centre(z, lc, tz, w, math.exp(-w * w) if shedding else 0.0)
    u_s = (_psi_near(col0, h + e, _fade_near(h + e, fade, y, sp, sig), c, p)
           - _psi_near(col0, h - e, _fade_near(h - e, fade, y, sp, sig), c, p)) * _INV_2DIFF
    w_up = -(_psi_near(col_p, h, fade, c, p) - _psi_near(col_m, h, fade, c, p)) * _INV_2DIFF
    along, across, up = u_s, 0.0, w_up
    if turbulence:
        fs, fn, fh = advected_point(box, s, n, h, t, p.speed)
        sig_t = _sigma(col0, h, p)
        along, across, up = u_s + sig_t * fs, sig_t * fn, w_up + sig_t * fh
    return (along * p.e_s_x + across * p.e_n_x, along * p.e_s_y + across * p.e_n_y, -up)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _ship_frame_rows(t, snh, unsteady, turbulence, p, box, out):
    for i in range(t.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = _ship_frame_point(
            snh[i, 0], snh[i, 1], snh[i, 2], t[i], unsteady, turbulence, p, box)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _stream_function_rows(s, h, n, t, unsteady, p, out):
    for i in range(s.shape[0]):
        out[i] = _psi(s[i], n[i], h[i], t[i], unsteady, p)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _sigma_rows(s, h, n, p, out):
    for i in range(s.shape[0]):
        out[i] = _sigma(_column(s[i], n[i], False, 0.0, p), h[i], p)


@numba.njit(cache=True, error_model="numpy", fastmath=inc.FAST)
def _velocity_rows(t, pos, pose_index, rot, origin, vel, unsteady, turbulence, p, box, out):
    """v = v_ship + R w_ship(s, n, h) with p_ship = R^T (pos - origin), the ship's
    pose (rot (K, 3, 3) ship -> NED, origin, vel (K, 3)) at row pose_index[i]."""
    for i in range(t.shape[0]):
        k = pose_index[i]
        dx = pos[i, 0] - origin[k, 0]
        dy = pos[i, 1] - origin[k, 1]
        dz = pos[i, 2] - origin[k, 2]
        px = dx * rot[k, 0, 0] + dy * rot[k, 1, 0] + dz * rot[k, 2, 0]
        py = dx * rot[k, 0, 1] + dy * rot[k, 1, 1] + dz * rot[k, 2, 1]
        pz = dx * rot[k, 0, 2] + dy * rot[k, 1, 2] + dz * rot[k, 2, 2]
        s = px * p.e_s_x + py * p.e_s_y + pz * p.e_s_z
        n = px * p.e_n_x + py * p.e_n_y + pz * p.e_n_z
        wx, wy, wz = _ship_frame_point(s, n, -pz, t[i], unsteady, turbulence, p, box)
        for j in range(3):
            out[i, j] = vel[k, j] + (rot[k, j, 0] * wx + rot[k, j, 1] * wy
                                     + rot[k, j, 2] * wz)


@numba.njit(cache=True, error_model="numpy")
def _runs(t):
    """(times (K,), index (N,)): one entry per run of equal consecutive times."""
    index = np.empty(t.shape[0], dtype=np.int64)
    starts = np.empty(t.shape[0])
    k = -1
    for i in range(t.shape[0]):
        if k < 0 or t[i] != starts[k]:
            k += 1
            starts[k] = t[i]
        index[i] = k
    return starts[: k + 1].copy(), index


class ShipAirwake(WindField):
    kind = "ship_airwake"

    def __init__(self, config: ShipAirwakeConfig, rng: np.random.Generator,
                 ship: Ship | None = None) -> None:
        self.config = config
        self.ship = ship or Ship()
        c = config
        sc = self.ship.config
        beta = np.radians(c.relative_wind_heading_deg)
        self.e_s = -np.array([np.cos(beta), np.sin(beta), 0.0])
        self.e_n = np.array([np.sin(beta), -np.cos(beta), 0.0])
        self.e_up = np.array([0.0, 0.0, -1.0])
        self.speed = c.relative_wind_speed_m_s
        self.hangar_height = sc.hangar_height_m
        self.wake_width = (sc.hangar_width_m * abs(np.cos(beta))
                           + sc.hangar_length_m * abs(np.sin(beta)))
        self.shedding_hz = c.strouhal_number * self.speed / sc.hangar_height_m
        self._k_shed = 2 * np.pi * self.shedding_hz / (c.shedding_convection_fraction * self.speed)
        self._box = FrozenTurbulence(c.turbulence, rng)
        self._params = _airwake_params(self)

    # -- wake coordinates ----------------------------------------------------

    def wake_coordinates(self, t_s: np.ndarray, pos_ned_m: np.ndarray) -> np.ndarray:
        """(N, 3) `[s, n, h]` of NED points at times (N,)."""
        p = self.ship.ned_to_ship(t_s, pos_ned_m)
        return self._to_wake(p)

    def _to_wake(self, p_ship: np.ndarray) -> np.ndarray:
        return np.stack([p_ship @ self.e_s, p_ship @ self.e_n, -p_ship[:, 2]], axis=-1)

    def stream_function(self, s: np.ndarray, h: np.ndarray, n: np.ndarray, t: np.ndarray,
                        unsteady: bool) -> np.ndarray:
        """psi (m^2/s) per unit span in the (s, h) plane at lateral offset n."""
        args = [np.ascontiguousarray(a, dtype=float).ravel()
                for a in np.broadcast_arrays(s, h, n, t)]
        out = np.empty(args[0].size)
        _stream_function_rows(*args, bool(unsteady), self._params, out)
        return out.reshape(np.broadcast_shapes(np.shape(s), np.shape(h), np.shape(n),
                                               np.shape(t)))

    def sigma_m_s(self, s: np.ndarray, h: np.ndarray, n: np.ndarray) -> np.ndarray:
        """Local turbulence std (m/s) per component."""
        args = [np.ascontiguousarray(a, dtype=float).ravel() for a in np.broadcast_arrays(s, h, n)]
        out = np.empty(args[0].size)
        _sigma_rows(*args, self._params, out)
        return out.reshape(np.broadcast_shapes(np.shape(s), np.shape(h), np.shape(n)))

    def ship_frame_velocity(self, t: np.ndarray, snh: np.ndarray, unsteady: bool,
                            turbulence: bool) -> np.ndarray:
        """(N, 3) air velocity relative to the ship, ship axes, at wake coordinates."""
        snh = np.ascontiguousarray(snh, dtype=float)
        t = np.ascontiguousarray(np.broadcast_to(np.asarray(t, dtype=float), snh.shape[:1]))
        out = np.empty((snh.shape[0], 3))
        _ship_frame_rows(t, snh, bool(unsteady), bool(turbulence), self._params,
                         self._box.grid, out)
        return out

    def _velocity(self, t, pos, unsteady, turbulence):
        # The ship's pose once per run of equal times (a local-wind call has one time
        # for all its points, the blade-element grid one per snapshot).
        times, index = _runs(t)
        rot, origin, vel = self.ship.pose(times)
        out = np.empty((t.shape[0], 3))
        _velocity_rows(t, np.ascontiguousarray(pos), index, rot, origin, vel, bool(unsteady),
                       bool(turbulence), self._params, self._box.grid, out)
        return out

    def true_wind_ned(self) -> np.ndarray:
        """The true wind this relative wind implies for the ship's course and speed."""
        return self.ship.true_wind_ned(self.speed, self.config.relative_wind_heading_deg)
