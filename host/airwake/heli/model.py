"""`HeliModel`: an ordered list of effects evaluated as one batched pipeline.

    model = HeliModel([Atmosphere(), RigidBody(), Gravity(), MainRotor(), PittPetersInflow(),
                       Flybar(), TailRotor(), Fuselage(), Empennage()])
    xdot = model.derivatives(x, u, w, env)          # (N, S)
    z = model.measure(x, u, w, env)                 # (N, 6): acc_x/y/z, pdot/qdot/rdot

Shapes: x (N, S) full state (`model.state_names`), u (N, 4) blade-pitch commands
(`INPUT_NAMES`), w (N, 6) eq 5.3 wind [v_x v_y v_z w_x w_y w_z] (body axes, at the hub),
env a mapping of (N,) arrays (`height_agl_m`, `rotor_speed_rad_s`), params None, a full
parameter vector (P,) or per-row matrix (N, P) in `parameter_names` order, or a dict
{"effect.param": value or (N,) array}. Any of them may be given for one row and is
broadcast to N.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from types import SimpleNamespace

import numpy as np

from airwake.heli.context import MEAS_CHANNELS, Context
from airwake.heli.effects.base import STAGES, Effect

INPUT_NAMES = ("delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad")
WIND_NAMES = (
    "wind_vx_m_s",
    "wind_vy_m_s",
    "wind_vz_m_s",
    "wind_wx_rad_s",
    "wind_wy_rad_s",
    "wind_wz_rad_s",
)
ENV_NAMES = ("height_agl_m", "rotor_speed_rad_s")
BODY_EFFECT = "rigid_body"


class HeliModel:
    """An ordered, named list of effects (see module docstring)."""

    def __init__(self, effects: Sequence[Effect]) -> None:
        effects = list(effects)
        names = [e.name for e in effects]
        for e in effects:
            if not isinstance(e, Effect):
                raise TypeError(f"HeliModel takes Effect instances, got {e!r}")
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"effect(s) listed twice: {dup}")
        body = [e for e in effects if getattr(type(e), "body_dynamics", None)]
        if len(body) > 1:
            raise ValueError("a model needs at most one effect with body_dynamics")
        for e in effects:
            missing = [r for r in e.REQUIRES if r not in names]
            if missing:
                raise ValueError(f"effect '{e.name}' requires effect(s) {missing} in the model")
        self.effects: tuple[Effect, ...] = tuple(effects)
        self._by_name = dict(zip(names, effects, strict=True))
        # state layout
        self._slices: dict[str, slice] = {}
        self.state_names: list[str] = []
        for e in effects:
            start = len(self.state_names)
            self.state_names += [f"{e.name}.{s.name}" for s in e.STATES]
            self._slices[e.name] = slice(start, len(self.state_names))
        self.n_states = len(self.state_names)
        # parameter layout
        self.parameter_names: list[str] = []
        self._param_specs = []
        for e in effects:
            for p in e.PARAMETERS:
                self.parameter_names.append(f"{e.name}.{p.name}")
                self._param_specs.append(p)
        self._stage_calls = [
            (stage, [(e, getattr(e, stage)) for e in effects if getattr(type(e), stage, None)])
            for stage in STAGES
        ]
        self._stage_calls = [(s, c) for s, c in self._stage_calls if c]

    # -- composition and naming ----------------------------------------------------------
    @property
    def effect_names(self) -> list[str]:
        return [e.name for e in self.effects]

    def __getitem__(self, name: str) -> Effect:
        return self._by_name[name]

    def __contains__(self, name: str) -> bool:
        return name in self._by_name

    def __add__(self, other) -> HeliModel:
        more = list(other.effects) if isinstance(other, HeliModel) else [other]
        return HeliModel(list(self.effects) + more)

    def without(self, *names: str) -> HeliModel:
        return HeliModel([e for e in self.effects if e.name not in names])

    def replace(self, effect: Effect) -> HeliModel:
        """The same model with the effect of the same name replaced (or appended)."""
        if effect.name in self._by_name:
            return HeliModel([effect if e.name == effect.name else e for e in self.effects])
        return self + effect

    def __repr__(self) -> str:
        return f"HeliModel({self.effect_names})"

    def __eq__(self, other):
        if not isinstance(other, HeliModel):
            return NotImplemented
        return self.effects == other.effects

    __hash__ = None

    def state_slice(self, effect: str) -> slice:
        return self._slices[effect]

    def state_index(self, name: str) -> int:
        """Index of a state by full name ('rigid_body.p_rad_s') or flight-table column."""
        if name in self.state_names:
            return self.state_names.index(name)
        return self.state_names.index(f"{BODY_EFFECT}.{name}")

    @property
    def measured_states(self) -> dict[str, str]:
        """Full state name -> flight-table column, for states a flight table measures."""
        out = {}
        for e in self.effects:
            for s, c in e.MEASURED_STATES.items():
                out[f"{e.name}.{s}"] = c
        return out

    @property
    def hidden_state_names(self) -> list[str]:
        m = self.measured_states
        return [s for s in self.state_names if s not in m]

    # -- parameter vector (for fitting) ------------------------------------------------
    def parameter_vector(self) -> np.ndarray:
        return np.array([v for e in self.effects for v in e.parameters().values()], dtype=float)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        lo = np.array([p.bounds[0] for p in self._param_specs], dtype=float)
        hi = np.array([p.bounds[1] for p in self._param_specs], dtype=float)
        return lo, hi

    def fixed_mask(self) -> np.ndarray:
        """True for parameters normally held fixed (Table 5.1's starred entries, discrete)."""
        return np.array([p.fixed or p.choices is not None for p in self._param_specs])

    def parameter_specs(self) -> dict[str, object]:
        return dict(zip(self.parameter_names, self._param_specs, strict=True))

    def with_parameters(self, values) -> HeliModel:
        """A new model with parameters from a full vector (P,) or a {'effect.param': v} dict.
        Values are validated (ValueError naming effect, parameter and value)."""
        if isinstance(values, Mapping):
            updates = dict(values)
            unknown = sorted(set(updates) - set(self.parameter_names))
            if unknown:
                raise ValueError(f"unknown parameter(s) {unknown}")
        else:
            vec = np.asarray(values, dtype=float)
            if vec.shape != (len(self.parameter_names),):
                raise ValueError(
                    f"parameter vector has shape {vec.shape}, "
                    f"expected ({len(self.parameter_names)},)"
                )
            updates = dict(zip(self.parameter_names, vec.tolist(), strict=True))
        new = []
        for e in self.effects:
            mine = {
                k.split(".", 1)[1]: v for k, v in updates.items() if k.split(".", 1)[0] == e.name
            }
            new.append(e.with_values(**mine) if mine else e)
        return HeliModel(new)

    def _param_views(self, params, n: int) -> dict[str, SimpleNamespace]:
        views = {e.name: e.params() for e in self.effects}
        if params is None:
            return views
        if isinstance(params, Mapping):
            items = params.items()
        else:
            arr = np.asarray(params, dtype=float)
            if arr.shape[-1] != len(self.parameter_names):
                raise ValueError(
                    f"params has {arr.shape[-1]} columns, expected {len(self.parameter_names)}"
                )
            if arr.ndim == 1:
                items = zip(self.parameter_names, arr.tolist(), strict=True)
            else:
                items = zip(self.parameter_names, arr.T, strict=True)
        for key, v in items:
            eff, pname = key.split(".", 1)
            if eff not in views:
                raise ValueError(f"unknown parameter {key!r}")
            if isinstance(v, np.ndarray) and v.ndim == 1 and v.shape[0] != n:
                v = np.broadcast_to(v, (n,))
            setattr(views[eff], pname, v)
        return views

    # -- evaluation ----------------------------------------------------------------------
    def evaluate(self, x, u, w=None, env=None, params=None) -> Context:
        """Run every stage on a batch; returns the Context with all intermediates."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        u = np.atleast_2d(np.asarray(u, dtype=float))
        w = np.zeros((1, 6)) if w is None else np.atleast_2d(np.asarray(w, dtype=float))
        if x.shape[1] != self.n_states:
            raise ValueError(f"state has {x.shape[1]} columns, model has {self.n_states} states")
        if u.shape[1] != 4 or w.shape[1] != 6:
            raise ValueError(f"inputs must be (N,4) and wind (N,6), got {u.shape} and {w.shape}")
        n = max(x.shape[0], u.shape[0], w.shape[0])
        if params is not None and not isinstance(params, Mapping):
            pa = np.asarray(params)
            if pa.ndim == 2:
                n = max(n, pa.shape[0])
        if env:
            for v in env.values():
                n = max(n, np.size(v) if np.ndim(v) else 1)
        x = np.broadcast_to(x, (n, self.n_states)).copy() if x.shape[0] != n else x
        u = np.broadcast_to(u, (n, 4)) if u.shape[0] != n else u
        w = np.broadcast_to(w, (n, 6)) if w.shape[0] != n else w

        ctx = Context(self, x, n)
        ctx.delta_col_rad = u[:, 0]
        ctx.delta_lat_rad = u[:, 1]
        ctx.delta_lon_rad = u[:, 2]
        ctx.delta_ped_rad = u[:, 3]
        ctx.wind_v_m_s = w[:, 0:3]
        ctx.wind_w_rad_s = w[:, 3:6]
        env = env or {}
        unknown = sorted(set(env) - set(ENV_NAMES))
        if unknown:
            raise ValueError(f"unknown environment input(s) {unknown}; expected {list(ENV_NAMES)}")
        ctx.height_agl_m = np.broadcast_to(
            np.asarray(env.get("height_agl_m", np.inf), dtype=float), (n,)
        )
        ctx.rotor_speed_meas_rad_s = np.broadcast_to(
            np.asarray(env.get("rotor_speed_rad_s", np.nan), dtype=float), (n,)
        )
        if BODY_EFFECT in self._by_name:
            b = ctx.state(BODY_EFFECT)
            ctx.vel_b_m_s = b[:, 3:6]
            ctx.roll_rad, ctx.pitch_rad, ctx.yaw_rad = b[:, 6], b[:, 7], b[:, 8]
            ctx.omega_b_rad_s = b[:, 9:12]
        else:
            ctx.vel_b_m_s = np.zeros((n, 3))
            ctx.omega_b_rad_s = np.zeros((n, 3))
            ctx.roll_rad = ctx.pitch_rad = ctx.yaw_rad = np.zeros(n)
        views = self._param_views(params, n)
        for _stage, calls in self._stage_calls:
            for eff, method in calls:
                method(ctx, views[eff.name])
        return ctx

    def derivatives(self, x, u, w=None, env=None, params=None) -> np.ndarray:
        """dx/dt, (N, S)."""
        return self.evaluate(x, u, w, env, params).xdot

    def measure(self, x, u, w=None, env=None, params=None) -> np.ndarray:
        """Predicted measurement (N, 6) in `MEAS_CHANNELS` order, from the full state."""
        return self.evaluate(x, u, w, env, params).meas

    MEAS_CHANNELS = MEAS_CHANNELS

    def zero_state(self, n: int = 1) -> np.ndarray:
        return np.zeros((n, self.n_states))
