"""The wind-field interface and the 6-parameter local wind of eq 5.3.

Every field gives the air velocity (m/s, inertial NED) at any positions and times,
vectorised, split into three parts the caller can switch off:
- mean: the time-averaged flow;
- unsteady: deterministic periodic flow (vortex shedding);
- turbulence: the frozen random fluctuations.

Local wind (eq 5.3): the external wind near the rotor hub, in the helicopter's body
frame, modelled as w(r) = v + omega x r for r relative to the hub. We obtain
(v, omega) by a least-squares fit of that model to the field sampled on a grid of
points filling the rotor-sized volume (default 1.3 x 1.3 x 0.6 m, 5 x 5 x 3 points,
body axes) — the same fit §3.4/§5.4 apply to anemometer maps, so truth and the
host's map fits agree in definition. The columns are `[v_x, v_y, v_z, w_x, w_y, w_z]`
(`truth_wind_vx_m_s ... truth_wind_wz_rad_s`).

Convention for omega (keep it consistent with the host model's eq 5.6): omega is the
rotation-like coefficient of eq 5.3, not the vorticity. For a rigid rotation
w = Omega x r the fit returns omega = Omega exactly, while the curl is 2 Omega. For a
general linear field w = v + G r (G_ij = d w_i / d r_j) the fit over a box with second
moments s_x = s_y (rotor plane) > s_z gives omega_z = (G_yx - G_xy) / 2 (half the curl)
and
    omega_x = (s_y G_zy - s_z G_yz) / (s_y + s_z),
    omega_y = (s_z G_xz - s_x G_zx) / (s_x + s_z),
weighted toward the in-plane gradients of the normal component (d w_z / dy,
-d w_z / dx), which is what the rotor disc feels in eq 5.6; a flat fit volume
(`LocalWindFit(volume_m=(1.3, 1.3, ~0))`) gives exactly those.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from hil_sim.sensors.config import check_positive
from hil_sim.world.kinematics import quat_to_dcm

LOCAL_WIND_COLUMNS = (
    "truth_wind_vx_m_s",
    "truth_wind_vy_m_s",
    "truth_wind_vz_m_s",
    "truth_wind_wx_rad_s",
    "truth_wind_wy_rad_s",
    "truth_wind_wz_rad_s",
)


@dataclass(frozen=True)
class LocalWindFit:
    """Least-squares fit of eq 5.3 over a box of points around the hub (body axes)."""

    volume_m: tuple[float, float, float] = (1.3, 1.3, 0.6)
    points: tuple[int, int, int] = (5, 5, 3)

    def __post_init__(self) -> None:
        for v in self.volume_m:
            check_positive("volume_m", v)
        for n in self.points:
            if not (isinstance(n, int) and n >= 2):
                raise ValueError(f"points = {self.points!r}: need >= 2 per axis")

    @cached_property
    def offsets_body_m(self) -> np.ndarray:
        """(M, 3) sample points relative to the hub, body axes (centred grid)."""
        axes = [np.linspace(-v / 2, v / 2, n) for v, n in zip(self.volume_m, self.points,
                                                               strict=True)]
        grid = np.meshgrid(*axes, indexing="ij")
        return np.stack([g.ravel() for g in grid], axis=-1)

    @cached_property
    def _pinv(self) -> np.ndarray:
        """(6, 3M) pseudo-inverse of the design matrix of w_j = v + omega x r_j."""
        r = self.offsets_body_m
        m = r.shape[0]
        a = np.zeros((3 * m, 6))
        for j in range(m):
            x, y, z = r[j]
            a[3 * j : 3 * j + 3, :3] = np.eye(3)
            # omega x r = -[r]x omega
            a[3 * j : 3 * j + 3, 3:] = -np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
        return np.linalg.pinv(a)

    def fit(self, w_body: np.ndarray) -> np.ndarray:
        """(N, M, 3) body-axis wind at the sample points -> (N, 6) `[v, omega]`."""
        n = w_body.shape[0]
        return w_body.reshape(n, -1) @ self._pinv.T


DEFAULT_FIT = LocalWindFit()


class WindField:
    """Base class. Subclasses implement `_velocity(t (N,), pos (N, 3), unsteady,
    turbulence) -> (N, 3)` in NED and set `kind` and `config`."""

    kind = "base"
    config: Any = None

    def _velocity(self, t: np.ndarray, pos: np.ndarray, unsteady: bool, turbulence: bool
                  ) -> np.ndarray:
        raise NotImplementedError

    def velocity_ned(self, t_s: np.ndarray | float, pos_ned_m: np.ndarray, *,
                     unsteady: bool = True, turbulence: bool = True) -> np.ndarray:
        """Air velocity (m/s, NED) at positions (N, 3) or (3,) and times (N,) or scalar."""
        pos = np.asarray(pos_ned_m, dtype=float)
        single = pos.ndim == 1
        pos2 = pos.reshape(-1, 3)
        t = np.broadcast_to(np.asarray(t_s, dtype=float), (pos2.shape[0],))
        out = self._velocity(np.ascontiguousarray(t), pos2, unsteady, turbulence)
        return out[0] if single else out

    def mean_velocity_ned(self, t_s: np.ndarray | float, pos_ned_m: np.ndarray) -> np.ndarray:
        """The time-averaged flow only (no shedding, no turbulence)."""
        return self.velocity_ned(t_s, pos_ned_m, unsteady=False, turbulence=False)

    def local_wind(
        self,
        t_s: np.ndarray | float,
        hub_pos_ned_m: np.ndarray,
        quat_wxyz: np.ndarray,
        *,
        fit: LocalWindFit = DEFAULT_FIT,
        unsteady: bool = True,
        turbulence: bool = True,
    ) -> np.ndarray:
        """Eq 5.3 local wind at the hub in body axes: (N, 6) `[vx, vy, vz, wx, wy, wz]`.

        `hub_pos_ned_m` (N, 3) or (3,), `quat_wxyz` (N, 4) or (4,) body -> NED, `t_s` (N,)
        or scalar. Returns (6,) for a single hub.
        """
        hub = np.asarray(hub_pos_ned_m, dtype=float)
        single = hub.ndim == 1
        hub = hub.reshape(-1, 3)
        n = hub.shape[0]
        q = np.broadcast_to(np.asarray(quat_wxyz, dtype=float), (n, 4))
        t = np.broadcast_to(np.asarray(t_s, dtype=float), (n,))
        rot = quat_to_dcm(q)  # body -> NED, (N, 3, 3)
        offsets = fit.offsets_body_m  # (M, 3)
        m = offsets.shape[0]
        points = hub[:, None, :] + offsets @ rot.transpose(0, 2, 1)  # (N, M, 3)
        w_ned = self._velocity(np.repeat(t, m), points.reshape(-1, 3), unsteady, turbulence)
        w_body = w_ned.reshape(n, m, 3) @ rot  # rows: R^T w
        out = fit.fit(w_body)
        return out[0] if single else out

    def describe(self) -> dict[str, Any]:
        """Plain description for metadata: the type and its settings."""
        from hil_sim.sensors.config import config_to_dict

        return {"type": self.kind, **(config_to_dict(self.config) if self.config else {})}


class HeldLocalWind:
    """Eq 5.3 local wind for a step-by-step integrator, refreshed at `rate_hz`.

    The fields vary on the rotor scale over tens of milliseconds (turbulence grid
    0.25 m convected at a few m/s: content below ~15 Hz), so a 1 kHz integrator need
    not evaluate the field every step: `held(t, hub, quat)` recomputes when t reaches
    the next update instant of a fixed grid (k / rate_hz) and otherwise returns the
    held value (zero-order hold). Use the same held value for the truth columns so
    the table records what drove the dynamics.
    """

    def __init__(self, field: WindField, rate_hz: float = 100.0, *,
                 fit: LocalWindFit = DEFAULT_FIT) -> None:
        check_positive("rate_hz", rate_hz)
        self.field = field
        self.rate_hz = rate_hz
        self.fit = fit
        self._next_t = -np.inf
        self._value = np.zeros(6)

    def __call__(self, t_s: float, hub_pos_ned_m: np.ndarray, quat_wxyz: np.ndarray
                 ) -> np.ndarray:
        if t_s >= self._next_t or t_s < self._next_t - 1.0 / self.rate_hz:
            self._value = self.field.local_wind(t_s, hub_pos_ned_m, quat_wxyz, fit=self.fit)
            self._next_t = (np.floor(t_s * self.rate_hz + 1e-9) + 1.0) / self.rate_hz
        return self._value
