"""Fixed-step RK4 integration of `HeliModel.derivatives` (batched: N trajectories at once).

Three ways in, fastest last:
    rk4_step(model, x, u, dt, w, env, params)   one step of N rows, any model
    Stepper(model, dt, env, params)             one step per call with little Python around
        .step(x, u, w, height_agl_m, dt)        it (closed-loop pilots, hil_sim's truth);
        .rates_and_measurement(x, u, w, h)      .derivatives: the model at the same inputs
    simulate(model, x0, duration_s, dt, inputs, wind, …)
        inputs/wind as callables (closed loop, a Python call per step), or as arrays
        sampled per step: then an all-kernel model integrates the whole run inside one
        compiled loop.
For an all-kernel model (`model.is_compiled`) the RK4 step itself is compiled (4
evaluations in one call); a model with numpy plugins steps through `derivatives`.
Inputs, wind and environment are held over each step (zero-order hold at its start).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from airwake.heli.model import _plain


def _rk4_numpy(model, x, u, dt, w, env, params) -> np.ndarray:
    k1 = model.derivatives(x, u, w, env, params)
    k2 = model.derivatives(x + 0.5 * dt * k1, u, w, env, params)
    k3 = model.derivatives(x + 0.5 * dt * k2, u, w, env, params)
    k4 = model.derivatives(x + dt * k3, u, w, env, params)
    return x + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def rk4_step(model, x, u, dt: float, w=None, env=None, params=None) -> np.ndarray:
    """One classical RK4 step, inputs/wind/env held over the step. x (N,S) -> (N,S)."""
    if not model.is_compiled:
        return _rk4_numpy(model, np.atleast_2d(np.asarray(x, dtype=float)), u, dt, w, env,
                          params)
    a = model._rows(x, u, w, env, params)
    out = np.empty((a.n, model.n_states))
    model.compiled.fns.rk4_rows(a.n, a.x, a.xs, a.u, a.us, a.w, a.ws, a.h, a.hs, a.om, a.oms,
                                a.p, a.ps, float(dt), out)
    return out


class Stepper:
    """RK4 steps of one model with fixed parameters, the per-call Python work cut to the
    minimum (a single row of an all-kernel model: one compiled call, no allocation but
    the result).

        stepper = Stepper(model, dt=1e-3)
        x = stepper.step(x, u, w)                 # x (S,) -> (S,), (N, S) -> (N, S)
        x = stepper.step(x, u, w, h, dt)          # this step's hub height and size
        xdot, meas = stepper.rates_and_measurement(x, u, w, h)

    u (4,) or (N|1, 4) blade-pitch commands; w (6,), (N|1, 6) eq 5.3 hub wind, or None
    (still air); h the hub height above ground/deck in m, a float or (N,) (None: `env`'s);
    dt None: the constructor's. `env` and `params` as for `HeliModel.derivatives`.
    A model with numpy stages steps through `rk4_step` (four `derivatives` calls)."""

    def __init__(self, model, dt: float | None = None, env=None, params=None) -> None:
        self.model = model
        self.dt = None if dt is None else float(dt)
        self.env = dict(env) if env else {}
        self.params = params
        a = model._rows(model.zero_state(1), np.zeros(4), None, env, params)
        # the one-row compiled path: env and params shared by every row
        self._fast = model.is_compiled and a.n == 1
        if self._fast:
            s = model.n_states
            self._rk4 = model.compiled.fns.rk4_rows
            self._h, self._om, self._p = a.h, a.om, a.p
            self._x1, self._u1, self._w1 = np.empty((1, s)), np.empty((1, 4)), np.zeros((1, 6))
            self._h1, self._out1 = np.empty(1), np.empty((1, s))
            self._row_shape = (s,)

    def _env(self, height_agl_m):
        if height_agl_m is None:
            return self.env
        return {**self.env, "height_agl_m": height_agl_m}

    def step(self, x, u, w=None, height_agl_m=None, dt: float | None = None) -> np.ndarray:
        """The state one RK4 step of `dt` after x, shaped like x."""
        if dt is None:
            dt = self.dt
            if dt is None:
                raise ValueError("Stepper.step: no step size (give dt here or to Stepper)")
        if self._fast and getattr(x, "shape", None) == self._row_shape:
            self._x1[0] = x
            self._u1[0] = u
            self._w1[0] = 0.0 if w is None else w
            h = self._h
            if height_agl_m is not None:
                self._h1[0] = height_agl_m
                h = self._h1
            self._rk4(1, self._x1, 1, self._u1, 1, self._w1, 1, h, 1, self._om, 1, self._p, 1,
                      dt, self._out1)
            return self._out1[0].copy()
        out = rk4_step(self.model, x, u, dt, w, self._env(height_agl_m), self.params)
        return out[0] if np.ndim(x) == 1 else out

    def rates_and_measurement(self, x, u, w=None, height_agl_m=None):
        """(dx/dt, predicted measurement) at x: (S,), (6,) for one row, else (N, S), (N, 6)."""
        xdot, meas = self.model.rates_and_measurement(x, u, w, self._env(height_agl_m),
                                                      self.params)
        return (xdot[0], meas[0]) if np.ndim(x) == 1 else (xdot, meas)

    def derivatives(self, x, u, w=None, height_agl_m=None) -> np.ndarray:
        """dx/dt at x, shaped like x."""
        return self.rates_and_measurement(x, u, w, height_agl_m)[0]


@dataclass
class Trajectory:
    """Samples of a simulation: t (K,), x (K,N,S), u (K,N,4), w (K,N,6)."""

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    w: np.ndarray


def _sampled(values, steps: int, width: int, name: str) -> np.ndarray:
    """(width,), (T, width) or (T, N, width) -> (T, R, width), T in {1, steps, steps+1}."""
    a = np.asarray(values, dtype=np.float64)
    if a.ndim == 1:
        a = a.reshape(1, 1, -1)
    elif a.ndim == 2:
        a = a[:, None, :]
    if a.ndim != 3 or a.shape[2] != width:
        raise ValueError(f"{name} must be ({width},), (T, {width}) or (T, N, {width}), "
                         f"got shape {np.shape(values)}")
    if a.shape[0] not in (1, steps, steps + 1):
        raise ValueError(f"{name} has {a.shape[0]} samples; expected 1, {steps} (one per "
                         f"step) or {steps + 1} (one per step and the end)")
    return _plain(a)


def simulate(
    model,
    x0,
    duration_s: float,
    dt: float,
    inputs: Callable[[float, np.ndarray], np.ndarray] | np.ndarray,
    wind: Callable[[float], np.ndarray] | np.ndarray | None = None,
    env=None,
    params=None,
    sample_every: int = 1,
) -> Trajectory:
    """Integrate from x0 (N,S) and keep every `sample_every`-th state (step 0 included).

    inputs: `inputs(t, x) -> (N|1, 4)` (closed loop allowed), or an array sampled per step
        (4,), (T, 4) or (T, N|1, 4) with T = 1, steps or steps + 1;
    wind: None (still air), `wind(t) -> (N|1, 6)` or an array like `inputs` with 6 columns.
    Both evaluated at the start of each step. With arrays for both and an all-kernel
    model, the whole run is one compiled loop; otherwise one Python iteration per step
    (never a loop over rows)."""
    x = np.atleast_2d(np.asarray(x0, dtype=float)).copy()
    steps = int(round(duration_s / dt))
    n = x.shape[0]
    if not callable(inputs) and (wind is None or not callable(wind)) and model.is_compiled:
        return _simulate_compiled(model, x, steps, dt, inputs, wind, env, params,
                                  sample_every)
    if not callable(inputs):
        u_arr = _sampled(inputs, steps, 4, "inputs")
        inputs = _sample_fn(u_arr, dt)  # noqa: F811 — same contract as a callable
    if wind is not None and not callable(wind):
        w_arr = _sampled(wind, steps, 6, "wind")
        wind = _sample_fn(w_arr, dt)
    stepper = Stepper(model, dt, env, params)
    ts, xs, us, ws = [], [], [], []
    for k in range(steps + 1):
        t = k * dt
        u = np.atleast_2d(inputs(t, x))
        w = np.zeros((1, 6)) if wind is None else np.atleast_2d(wind(t))
        if k % sample_every == 0:
            ts.append(t)
            xs.append(x.copy())
            us.append(np.broadcast_to(u, (n, 4)).copy())
            ws.append(np.broadcast_to(w, (n, 6)).copy())
        if k == steps:
            break
        x = stepper.step(x, u, w)
    return Trajectory(np.array(ts), np.array(xs), np.array(us), np.array(ws))


def _sample_fn(arr: np.ndarray, dt: float):
    def at(t, *_):
        k = min(int(round(t / dt)), arr.shape[0] - 1)
        return arr[k]

    return at


def _simulate_compiled(model, x, steps, dt, inputs, wind, env, params, every) -> Trajectory:
    n = x.shape[0]
    u = _sampled(inputs, steps, 4, "inputs")
    w = np.zeros((1, 1, 6)) if wind is None else _sampled(wind, steps, 6, "wind")
    for what, arr in (("inputs", u), ("wind", w)):
        if arr.shape[1] not in (1, n):
            raise ValueError(f"{what} has {arr.shape[1]} rows, x0 has {n}")
    a = model._rows(x, u[0], w[0], env, params)
    if a.n != n:
        raise ValueError(f"env/params have {a.n} rows, x0 has {n}")
    h = a.h.reshape(1, -1)
    om = a.om.reshape(1, -1)
    k_out = steps // every + 1
    xout = np.empty((k_out, n, model.n_states))
    model.compiled.fns.simulate_rows(
        n, a.x, a.xs, steps, float(dt), int(every),
        u, int(u.shape[0] > 1), int(u.shape[1] == n and n > 1),
        w, int(w.shape[0] > 1), int(w.shape[1] == n and n > 1),
        h, 0, a.hs, om, 0, a.oms, a.p, a.ps, xout,
    )
    idx = np.arange(k_out) * every
    t = idx * dt
    ui = np.minimum(idx, u.shape[0] - 1)
    wi = np.minimum(idx, w.shape[0] - 1)
    u_s = np.broadcast_to(u[ui], (k_out, n, 4)).copy()
    w_s = np.broadcast_to(w[wi], (k_out, n, 6)).copy()
    return Trajectory(t, xout, u_s, w_s)
