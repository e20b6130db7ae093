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
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hil_sim.sensors.config import check_finite, check_nonnegative, check_positive, check_range
from hil_sim.world.ship import Ship
from hil_sim.world.turbulence import FrozenTurbulence, TurbulenceConfig
from hil_sim.world.wind.base import WindField

_RAMP_M = 0.5  # width of the wake onset at the step
_SOFT_M = 1.0  # smoothing length of softplus
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


def _softplus(x: np.ndarray) -> np.ndarray:
    return _SOFT_M * np.logaddexp(0.0, x / _SOFT_M)


def _logcosh(x: np.ndarray) -> np.ndarray:
    a = np.abs(x)
    return a + np.log1p(np.exp(-2.0 * a)) - np.log(2.0)


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

    # -- wake coordinates ----------------------------------------------------

    def wake_coordinates(self, t_s: np.ndarray, pos_ned_m: np.ndarray) -> np.ndarray:
        """(N, 3) `[s, n, h]` of NED points at times (N,)."""
        p = self.ship.ned_to_ship(t_s, pos_ned_m)
        return self._to_wake(p)

    def _to_wake(self, p_ship: np.ndarray) -> np.ndarray:
        return np.stack([p_ship @ self.e_s, p_ship @ self.e_n, -p_ship[:, 2]], axis=-1)

    def _shape(self, s: np.ndarray) -> dict[str, np.ndarray]:
        c = self.config
        sp = _softplus(s)
        ramp = 0.5 * (1.0 + np.tanh(s / _RAMP_M))
        lr = c.recirculation_length_m
        beyond = np.exp(-_softplus(s - lr) / c.deficit_decay_length_m)
        return {
            "ramp": ramp,
            "deficit": c.wake_deficit * ramp * beyond,
            "beyond": beyond,
            "h_w": self.hangar_height * (1.0 - c.wake_height_drop * np.tanh(sp / lr)),
            "delta": c.shear_layer_thickness_m + c.shear_layer_growth * sp,
            "width": self.wake_width + 2.0 * c.lateral_spread * sp,
            "edge": 0.3 + 0.1 * sp,
            "shed_env": ramp * np.exp(-sp / c.shedding_decay_length_m),
        }

    def _lateral(self, n: np.ndarray, shape: dict[str, np.ndarray]) -> np.ndarray:
        half = shape["width"] / 2
        return 0.5 * (np.tanh((n + half) / shape["edge"]) - np.tanh((n - half) / shape["edge"]))

    def _bubble(self, s: np.ndarray, h: np.ndarray) -> np.ndarray:
        """1 - rho^2 of the recirculation half-ellipse (<= 0 outside)."""
        c = self.config
        half = c.recirculation_length_m / 2
        hb = c.bubble_height_fraction * self.hangar_height
        return 1.0 - ((s - half) / half) ** 2 - (h / hb) ** 2

    def stream_function(self, s: np.ndarray, h: np.ndarray, n: np.ndarray, t: np.ndarray,
                        unsteady: bool) -> np.ndarray:
        """psi (m^2/s) per unit span in the (s, h) plane at lateral offset n."""
        sh = self._shape(s)
        return self._psi(sh, self._lateral(n, sh), s, h, t, unsteady)

    def _psi(self, sh: dict[str, np.ndarray], g: np.ndarray, s: np.ndarray, h: np.ndarray,
             t: np.ndarray, unsteady: bool) -> np.ndarray:
        c = self.config
        u = self.speed
        d, hw = sh["delta"], sh["h_w"]
        integral = 0.5 * (h - d * (_logcosh((h - hw) / d) - _logcosh(-hw / d)))
        fade = np.exp(-_softplus(h - _DISPLACEMENT_TOP_M) / _DISPLACEMENT_FADE_M)
        psi = u * (h - g * sh["deficit"] * integral * fade)
        b = self._bubble(s, h)
        psi -= np.where((b > 0) & (h > 0), g * c.reverse_flow_fraction * u * h * b * b, 0.0)
        if unsteady and c.shedding_amplitude > 0:
            dv = np.maximum(d, 0.3)
            phase = 2 * np.pi * self.shedding_hz * t - self._k_shed * s
            psi += (g * c.shedding_amplitude * u * dv * np.exp(-((h - hw) / dv) ** 2)
                    * sh["shed_env"] * np.sin(phase))
        return psi

    def sigma_m_s(self, s: np.ndarray, h: np.ndarray, n: np.ndarray) -> np.ndarray:
        """Local turbulence std (m/s) per component."""
        sh = self._shape(s)
        return self._sigma(sh, self._lateral(n, sh), s, h)

    def _sigma(self, sh: dict[str, np.ndarray], g: np.ndarray, s: np.ndarray, h: np.ndarray
               ) -> np.ndarray:
        c = self.config
        dt = sh["delta"] + 0.3
        shear = (c.shear_turbulence_intensity * np.exp(-((h - sh["h_w"]) / dt) ** 2)
                 * sh["ramp"] * sh["beyond"])
        bubble = c.bubble_turbulence_intensity * np.clip(self._bubble(s, h), 0.0, 1.0) * (h > 0)
        return self.speed * (c.ambient_turbulence_intensity + g * (shear + bubble))

    def ship_frame_velocity(self, t: np.ndarray, snh: np.ndarray, unsteady: bool,
                            turbulence: bool) -> np.ndarray:
        """(N, 3) air velocity relative to the ship, ship axes, at wake coordinates."""
        s, n, h = snh[:, 0], snh[:, 1], snh[:, 2]
        e = _DIFF_M
        sh0 = self._shape(s)
        g0 = self._lateral(n, sh0)
        shp = self._shape(s + e)
        shm = self._shape(s - e)
        u_s = (self._psi(sh0, g0, s, h + e, t, unsteady)
               - self._psi(sh0, g0, s, h - e, t, unsteady)) / (2 * e)
        w_up = -(self._psi(shp, self._lateral(n, shp), s + e, h, t, unsteady)
                 - self._psi(shm, self._lateral(n, shm), s - e, h, t, unsteady)) / (2 * e)
        if turbulence:
            fluct = self._box.advected(snh, t, self.speed)
            sig = self._sigma(sh0, g0, s, h)
            along, across, up = u_s + sig * fluct[:, 0], sig * fluct[:, 1], w_up + sig * fluct[:, 2]
        else:
            along, across, up = u_s, 0.0, w_up
        vel = np.empty((s.size, 3))
        vel[:, 0] = along * self.e_s[0] + across * self.e_n[0]
        vel[:, 1] = along * self.e_s[1] + across * self.e_n[1]
        vel[:, 2] = -up
        return vel

    def _velocity(self, t, pos, unsteady, turbulence):
        # The ship's pose once per distinct time (a local-wind call has one time for
        # all its points).
        times, index = np.unique(t, return_inverse=True)
        rot, origin, vel = self.ship.pose(times)
        rot, origin, vel = rot[index], origin[index], vel[index]
        p_ship = ((pos - origin)[:, None, :] @ rot)[:, 0, :]  # R^T (p - o)
        w_ship = self.ship_frame_velocity(t, self._to_wake(p_ship), unsteady, turbulence)
        return vel + (rot @ w_ship[:, :, None])[:, :, 0]

    def true_wind_ned(self) -> np.ndarray:
        """The true wind this relative wind implies for the ship's course and speed."""
        return self.ship.true_wind_ned(self.speed, self.config.relative_wind_heading_deg)
