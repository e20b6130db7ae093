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

Speed: every effect stage written as a compiled kernel (`airwake.heli.kernel`) runs in one
generated, numba-compiled function per effect composition (`airwake.heli.codegen`);
`derivatives`, `measure` and `rates_and_measurement` of an all-kernel model keep only one
context row in memory. A model with numpy stages (user plugins) runs stage by stage on
the full `Context`, each kernel stage through its own compiled loop
(`airwake.heli.codegen.staged`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from types import SimpleNamespace

import numpy as np

from airwake.heli import codegen
from airwake.heli.codegen import staged
from airwake.heli.context import MEAS_CHANNELS, Context
from airwake.heli.effects.base import Effect
from airwake.heli.layout import N_SLOTS
from airwake.heli.pipeline import BODY_EFFECT

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
_NO_WIND = np.zeros((1, 6))
_NO_HEIGHT = np.full(1, np.inf)
_NO_ROTOR_SPEED = np.full(1, np.nan)


def _plain(a: np.ndarray) -> np.ndarray:
    """C-contiguous and writeable: the one array type the compiled functions are compiled
    for (a read-only or strided view would compile a second machine-code variant)."""
    if a.flags.c_contiguous and a.flags.writeable:
        return a
    return np.array(a, dtype=np.float64, order="C")


class _Rows:
    """Model inputs normalised for the compiled functions: each array keeps a leading row
    axis of 1 or n, with its stride (0 or 1)."""

    __slots__ = ("n", "x", "xs", "u", "us", "w", "ws", "h", "hs", "om", "oms", "p", "ps")


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
        for i, e in enumerate(effects):
            late = [a for a in e.AFTER if a in names[i + 1:]]
            if late:
                raise ValueError(f"effect '{e.name}' must come after {late} in the model "
                                 f"(it adds to what they write); move it later in `effects`")
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
        self._pindex = {k: j for j, k in enumerate(self.parameter_names)}
        self._index = {e.name: i for i, e in enumerate(effects)}
        self._default_params = np.ascontiguousarray(self.parameter_vector()[None, :])
        self._compiled = None

    # -- composition and naming ----------------------------------------------------------
    @property
    def effect_names(self) -> list[str]:
        return [e.name for e in self.effects]

    def __getitem__(self, name: str) -> Effect:
        return self._by_name[name]

    def __contains__(self, name: str) -> bool:
        return name in self._by_name

    def __add__(self, other) -> HeliModel:
        """The model with `other` (an effect or a model's effects) added: appended, but
        before the trailing effects that declare KEEP_LAST (e.g. dynamic_inflow, which
        lags the total inflow of the effects before it), unless they are KEEP_LAST too."""
        more = list(other.effects) if isinstance(other, HeliModel) else [other]
        effects = list(self.effects)
        end = len(effects)
        if not all(getattr(e, "KEEP_LAST", False) for e in more):
            while end > 0 and getattr(effects[end - 1], "KEEP_LAST", False):
                end -= 1
        return HeliModel(effects[:end] + more + effects[end:])

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

    def effect_index(self, effect: str) -> int:
        return self._index[effect]

    @property
    def compiled(self) -> codegen.Compiled:
        """The composition's compiled pipeline (generated and compiled on first use)."""
        if self._compiled is None:
            self._compiled = codegen.compiled(self)
        return self._compiled

    @property
    def is_compiled(self) -> bool:
        """True when every stage of every effect is a compiled kernel (fastest paths:
        lean evaluation, compiled RK4 and hidden-state pass)."""
        return self.compiled.pure

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

    def _param_matrix(self, params) -> np.ndarray:
        """params -> (1 or N, P) C-contiguous float64 matrix in `parameter_names` order."""
        if params is None:
            return self._default_params
        if isinstance(params, Mapping):
            cols = {}
            rows = 1
            for key, v in params.items():
                try:
                    j = self._pindex[key]
                except KeyError:
                    raise ValueError(f"unknown parameter {key!r}") from None
                a = np.asarray(v, dtype=float)
                if a.ndim > 1:
                    raise ValueError(f"parameter {key!r} must be a value or an (N,) array")
                if a.ndim == 1 and a.shape[0] != 1:
                    if rows not in (1, a.shape[0]):
                        raise ValueError(f"parameter {key!r} has {a.shape[0]} rows, others {rows}")
                    rows = a.shape[0]
                cols[j] = a
            pm = np.repeat(self._default_params, rows, 0)
            for j, a in cols.items():
                pm[:, j] = a
            return pm
        pm = np.asarray(params, dtype=float)
        if pm.shape[-1] != len(self.parameter_names):
            raise ValueError(
                f"params has {pm.shape[-1]} columns, expected {len(self.parameter_names)}"
            )
        if pm.ndim == 1:
            pm = pm.reshape(1, -1)
        elif pm.ndim != 2:
            raise ValueError(f"params must be (P,) or (N, P), got shape {pm.shape}")
        return np.ascontiguousarray(pm)

    def _rows(self, x, u, w, env, params) -> _Rows:
        a = _Rows()
        x = np.asarray(x, dtype=np.float64)
        if x.ndim == 1:
            x = x.reshape(1, -1)
        u = np.asarray(u, dtype=np.float64)
        if u.ndim == 1:
            u = u.reshape(1, -1)
        if w is None:
            w = _NO_WIND
        else:
            w = np.asarray(w, dtype=np.float64)
            if w.ndim == 1:
                w = w.reshape(1, -1)
        if x.ndim != 2 or x.shape[1] != self.n_states:
            raise ValueError(
                f"state has {x.shape[-1] if x.ndim else 0} columns, "
                f"model has {self.n_states} states"
            )
        if u.ndim != 2 or w.ndim != 2 or u.shape[1] != 4 or w.shape[1] != 6:
            raise ValueError(f"inputs must be (N,4) and wind (N,6), got {u.shape} and {w.shape}")
        h, om = _NO_HEIGHT, _NO_ROTOR_SPEED
        if env:
            unknown = sorted(set(env) - set(ENV_NAMES))
            if unknown:
                raise ValueError(
                    f"unknown environment input(s) {unknown}; expected {list(ENV_NAMES)}"
                )
            if "height_agl_m" in env:
                h = np.asarray(env["height_agl_m"], dtype=np.float64).reshape(-1)
            if "rotor_speed_rad_s" in env:
                om = np.asarray(env["rotor_speed_rad_s"], dtype=np.float64).reshape(-1)
        pm = self._param_matrix(params)
        n = max(x.shape[0], u.shape[0], w.shape[0], h.shape[0], om.shape[0], pm.shape[0])
        for what, arr in (("state", x), ("inputs", u), ("wind", w), ("height_agl_m", h),
                          ("rotor_speed_rad_s", om), ("params", pm)):
            if arr.shape[0] not in (1, n):
                raise ValueError(f"{what} has {arr.shape[0]} rows, cannot broadcast to {n}")
        a.n = n
        a.x, a.xs = _plain(x), int(x.shape[0] == n)
        a.u, a.us = _plain(u), int(u.shape[0] == n)
        a.w, a.ws = _plain(w), int(w.shape[0] == n)
        a.h, a.hs = _plain(h), int(h.shape[0] == n)
        a.om, a.oms = _plain(om), int(om.shape[0] == n)
        a.p, a.ps = _plain(pm), int(pm.shape[0] == n)
        return a

    def _param_views(self, params, n: int) -> dict[str, SimpleNamespace]:
        """Per-effect parameter namespaces for numpy stages: floats, or (N,) arrays."""
        views = {e.name: e.params() for e in self.effects}
        if params is None:
            return views
        if isinstance(params, Mapping):
            items = params.items()
        else:
            arr = np.asarray(params, dtype=float)
            if arr.ndim == 1:
                items = zip(self.parameter_names, arr.tolist(), strict=True)
            else:
                items = zip(self.parameter_names, arr.T, strict=True)
        for key, v in items:
            eff, pname = key.split(".", 1)
            if isinstance(v, np.ndarray) and v.ndim == 1 and v.shape[0] != n:
                v = np.broadcast_to(v, (n,))
            setattr(views[eff], pname, v)
        return views

    # -- evaluation ----------------------------------------------------------------------
    def evaluate(self, x, u, w=None, env=None, params=None) -> Context:
        """Run every stage on a batch; returns the Context with all intermediates."""
        a = self._rows(x, u, w, env, params)
        comp = self.compiled
        n = a.n
        xfull = a.x if a.xs or n == 1 else np.repeat(a.x, n, 0)
        c = np.empty((n, N_SLOTS))
        loads = np.empty((n, len(self.effects), 6))
        scratch = np.empty((n, comp.n_scratch))
        xdot = np.empty((n, self.n_states))
        meas = np.empty((n, 6))
        has, sensed = comp.has_load.copy(), comp.sensed.copy()
        ctx = Context(self, xfull, n, c, xdot, loads, has, sensed, scratch)
        if comp.pure:
            comp.fns.evaluate_rows(n, c, 1, xfull, 1, xdot, meas, loads, scratch, a.u, a.us,
                                   a.w, a.ws, a.h, a.hs, a.om, a.oms, a.p, a.ps)
            return ctx
        views = None
        for step in comp.steps:
            if step.kind == "kernel":
                step.fn(n, c, xfull, xdot, loads, scratch, a.p, a.ps, *step.offsets)
            elif step.kind == "numpy":
                if views is None:
                    views = self._param_views(params, n)
                eff = self.effects[step.effect_index]
                step.fn(eff, ctx, views[eff.name])
            elif step.kind == "totals":
                staged.load_totals(n, c, loads, has, sensed)
            else:  # init
                staged.core_init(n, c, xfull, xdot, loads, a.u, a.us, a.w, a.ws, a.h, a.hs,
                                 a.om, a.oms, step.effect_index)
        return ctx

    def rates_and_measurement(self, x, u, w=None, env=None, params=None):
        """(dx/dt (N, S), predicted measurement (N, 6)) without keeping the intermediates
        (one context row in memory for an all-kernel model)."""
        comp = self.compiled
        if not comp.pure:
            ctx = self.evaluate(x, u, w, env, params)
            return ctx.xdot, ctx.meas.copy()
        a = self._rows(x, u, w, env, params)
        n = a.n
        xdot = np.empty((n, self.n_states))
        meas = np.empty((n, 6))
        comp.fns.evaluate_rows(n, np.empty((1, N_SLOTS)), 0, a.x, a.xs, xdot, meas,
                               np.empty((1, len(self.effects), 6)),
                               np.empty((1, comp.n_scratch)), a.u, a.us, a.w, a.ws, a.h, a.hs,
                               a.om, a.oms, a.p, a.ps)
        return xdot, meas

    def derivatives(self, x, u, w=None, env=None, params=None) -> np.ndarray:
        """dx/dt, (N, S)."""
        return self.rates_and_measurement(x, u, w, env, params)[0]

    def measure(self, x, u, w=None, env=None, params=None) -> np.ndarray:
        """Predicted measurement (N, 6) in `MEAS_CHANNELS` order, from the full state."""
        return self.rates_and_measurement(x, u, w, env, params)[1]

    MEAS_CHANNELS = MEAS_CHANNELS

    def zero_state(self, n: int = 1) -> np.ndarray:
        return np.zeros((n, self.n_states))
