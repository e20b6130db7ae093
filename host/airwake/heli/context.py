"""The evaluation context: every intermediate quantity of one batched model evaluation.

A `Context` is created by `HeliModel.evaluate` for N rows (states, inputs, winds,
environment, parameter sets broadcast together) and passed through the effects' numpy
stages; compiled (kernel) stages write the same quantities row by row. After the call it
holds the full picture (loads per effect, inflow, thrust, …), which the discrepancy
tools use to explain residuals. All arrays are float64 with a leading batch axis N;
vectors in body axes (x forward, y right, z down), SI units.

Storage: the shared quantities live in one float64 array `ctx.c` (N, K), one fixed slot
(or run of slots) per quantity (`airwake.heli.layout`); `ctx.inflow_0` is the column
view `c[:, Q.inflow_0]`, `ctx.vel_b_m_s` the (N, 3) view of three slots, and assigning
`ctx.inflow_0 = v` writes into that column (broadcast), so a numpy effect and a compiled
kernel see the same numbers. Any other attribute a numpy effect sets (`ctx.my_thing = …`)
is an ordinary Python attribute, visible to later numpy stages.

Quantities (slot name, width, unit, who writes it, meaning):
{quantities}

Also: n (batch size), x (N, S) full state (`ctx.state(effect)` gives that effect's
(N, k) view), xdot (N, S) derivatives (`ctx.set_rates(effect, rates)`), meas (N, 6)
predicted measurement in `MEAS_CHANNELS` order, loads {{effect: (F (N,3), M (N,3),
sensed)}} (`ctx.add_load(effect, F, M, sensed=True)`), inertia (Ixx, Iyy, Izz, Ixz).
air_density_kg_m3, gravity_m_s2, mass_kg and rotor_sense read as floats when every row
holds the same value (as the per-model scalars they used to be), else as (N,) arrays.
"""

from __future__ import annotations

import numpy as np

from airwake.heli.layout import OFFSETS, QUANTITIES, SCALAR_LIKE, WIDTHS

MEAS_CHANNELS = (
    "acc_x_m_s2",
    "acc_y_m_s2",
    "acc_z_m_s2",
    "pdot_rad_s2",
    "qdot_rad_s2",
    "rdot_rad_s2",
)

__doc__ = __doc__.format(quantities="\n".join(
    f"    {name} ({width})".ljust(34) + f"{unit:8s} {who:18s} {doc}"
    for name, width, unit, who, doc in QUANTITIES
))


def cross(a, b) -> np.ndarray:
    """a x b for (..., 3) arrays (np.cross is slow for small batches)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], -1)


def _slot_property(name: str) -> property:
    k, width = OFFSETS[name], WIDTHS[name]
    doc = next(q[4] for q in QUANTITIES if q[0] == name)
    if width == 1:
        if name in SCALAR_LIKE:

            def get(self):
                v = self.c[:, k]
                return float(v[0]) if v.size and bool(np.all(v == v[0])) else v
        else:

            def get(self):
                return self.c[:, k]
    elif name == "rotor_load_jac":

        def get(self):
            return self.c[:, k : k + 9].reshape(self.n, 3, 3)
    elif name == "inertia":

        def get(self):
            return tuple(self._scalar_like(self.c[:, k + j]) for j in range(4))
    else:

        def get(self):
            return self.c[:, k : k + width]

    def set_(self, value):
        if name == "inertia":  # (Ixx, Iyy, Izz, Ixz), each a float or (N,)
            v = np.stack(np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in value)), -1)
        else:
            v = np.asarray(value, dtype=float)
        if name == "rotor_load_jac" and v.ndim >= 2:
            v = v.reshape(v.shape[:-2] + (9,))
        if width == 1:
            self.c[:, k] = v
        else:
            self.c[:, k : k + width] = v

    return property(get, set_, doc=doc)


class Context:
    """Intermediate quantities of one batched evaluation (see module docstring)."""

    def __init__(self, model, x, n: int, c, xdot, loads, has_load, sensed, scratch) -> None:
        self.model = model
        self.n = n
        self.x = x
        self.c = c
        self._xdot = xdot
        self.scratch = scratch
        self._loads = loads  # (N, E, 6): force, moment per effect (model order)
        self._has_load = has_load  # (E,) 1.0 where the effect added a load
        self._sensed = sensed  # (E,) 1.0 where an accelerometer feels it
        self._cache: dict[str, object] = {}

    @staticmethod
    def _scalar_like(v):
        return float(v[0]) if v.size and bool(np.all(v == v[0])) else v

    @property
    def xdot(self) -> np.ndarray:
        """(N, S) state derivatives (compiled stages write into the same array)."""
        return self._xdot

    @xdot.setter
    def xdot(self, value) -> None:
        self._xdot[...] = value

    # -- states -------------------------------------------------------------------
    def state(self, effect: str) -> np.ndarray:
        """(N, k) view of `effect`'s own states."""
        return self.x[:, self.model.state_slice(effect)]

    def set_rates(self, effect: str, rates: np.ndarray) -> None:
        """Write d/dt of `effect`'s own states, (N, k)."""
        self.xdot[:, self.model.state_slice(effect)] = rates

    # -- loads --------------------------------------------------------------------
    def add_load(self, effect: str, force_n, moment_nm, sensed: bool = True) -> None:
        """Add a force/moment (body axes, about the CG). `sensed=False` for gravity-like
        field forces that an accelerometer does not measure."""
        e = self.model.effect_index(effect)
        self._loads[:, e, 0:3] += np.broadcast_to(force_n, (self.n, 3))
        self._loads[:, e, 3:6] += np.broadcast_to(moment_nm, (self.n, 3))
        self._has_load[e] = 1.0
        self._sensed[e] = 1.0 if sensed else 0.0

    @property
    def loads(self) -> dict[str, tuple[np.ndarray, np.ndarray, bool]]:
        """{effect: (F (N,3), M (N,3), sensed)} for the effects that added a load."""
        return {
            eff.name: (self._loads[:, e, 0:3], self._loads[:, e, 3:6], bool(self._sensed[e]))
            for e, eff in enumerate(self.model.effects)
            if self._has_load[e]
        }

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


for _name in OFFSETS:
    setattr(Context, _name, _slot_property(_name))
del _name
