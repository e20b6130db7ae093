"""Measurement model: the 6 acceleration channels predicted from a flight's measured states.

`predict_measurements(model, flight)` returns (T, 6): specific force at the IMU
(acc_x/y/z_m_s2, without gravity) and angular accelerations (pdot/qdot/rdot_rad_s2), from
the flight table's *measured* body states, inputs and rotor speed (equation error /
one-step-ahead). The rotor's own states (flapping, lead-lag, flybar, and any state an
effect adds: servo lag, governor, …) are not in a flight table. They are reconstructed by
running their own dynamics, forced by the measured body motion, along the flight:

    dh/dt = f_h(h, body(t), u(t), w(t), env(t))                (hidden part of derivatives)

The rotor modes are stiff next to the sampling (lag ~18 Hz at 150 Hz), so with A0 the
Jacobian of f_h at a representative row (the flight's medians; eigen-decomposed once per
parameter set) the linear part is integrated exactly between samples and the remainder
g = f_h(h) - A0 h is taken linear between samples (first-order hold):

    z_{k+1} = e^{lam dt} z_k + phi1 b_k + phi2 (b_{k+1} - b_k),   z = V^-1 h, b = V^-1 g.

For an all-kernel model this runs as one compiled pass along the flight (each step's
implicit b_{k+1} by fixed-point iteration from a linear extrapolation, typically 2-4
model evaluations per sample), for any number K of parameter sets in the same call. A
model with numpy plugins solves the same discrete equations for the whole time series
at once by *waveform relaxation* (h^{k+1} = LTI_A0[f_h(h^k) - A0 h^k], one vectorised
evaluation per iteration, scipy's lfilter per mode). Both start from the quasi-steady
hidden state at the first sample. No quasi-steady flapping: the rotor's ~20 ms lag would
otherwise show up as a false residual at pilot-input frequencies.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from airwake.heli.context import MEAS_CHANNELS
from airwake.heli.model import INPUT_NAMES, HeliModel, _plain


@dataclass
class FlightArrays:
    """What the measurement model reads from a flight: t (T,), x (T,S) with the body
    states filled (hidden states zero), u (T,4), env {name: (T,)}."""

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    env: dict


@dataclass
class HiddenStates:
    """Reconstructed hidden states h (T, m) (names in `names`), iterations used and the
    last relative change (convergence)."""

    h: np.ndarray
    names: list
    iterations: int
    change: float


def flight_arrays(model: HeliModel, flight) -> FlightArrays:
    """Columns of a FlightTable / DataFrame / mapping of arrays -> model arrays."""
    df = getattr(flight, "df", flight)
    cols = df if isinstance(df, Mapping) else {c: df[c].to_numpy() for c in df.columns}

    def get(name):
        try:
            return np.asarray(cols[name], dtype=float)
        except KeyError:
            raise KeyError(
                f"flight has no column {name!r} (needed by the measurement model)"
            ) from None

    t = get("t_s")
    x = np.zeros((t.size, model.n_states))
    for state, column in model.measured_states.items():
        if column.startswith("pos_") and column not in cols:
            continue  # position does not enter the dynamics
        x[:, model.state_names.index(state)] = get(column)
    u = np.column_stack([get(n) for n in INPUT_NAMES])
    env = {}
    for name in ("height_agl_m", "rotor_speed_rad_s"):
        if name in cols:
            env[name] = get(name)
    return FlightArrays(t, x, u, env)


def _wind_array(wind, n: int) -> np.ndarray:
    if wind is None:
        return np.zeros((n, 6))
    w = np.asarray(wind, dtype=float)
    return np.broadcast_to(w, (n, 6)) if w.ndim == 1 or w.shape[0] == 1 else w


def _jac(fun, z: np.ndarray, eps: float = 1e-7) -> np.ndarray:
    n = z.size
    step = eps * np.maximum(1.0, np.abs(z))
    pts = np.concatenate([z[None], z + np.diag(step), z - np.diag(step)])
    out = fun(pts)
    return (out[1 : n + 1] - out[n + 1 :]).T / (2.0 * step)


def _foh_coefficients(lam: np.ndarray, dt: np.ndarray):
    """exp(lam dt), and the first-order-hold input weights phi1, phi2, shapes (K, m)."""
    x = np.outer(dt, lam)
    ea = np.exp(x)
    em1 = np.expm1(x)
    small = np.abs(x) < 1e-4
    xs = np.where(small, 1.0, x)
    d = dt[:, None]
    phi1 = np.where(small, d * (1 + x / 2 + x * x / 6), d * em1 / xs)
    phi2 = np.where(small, d * (0.5 + x / 6 + x * x / 24), d * (em1 - x) / (xs * xs))
    return ea, phi1, phi2


def _lti_solve(lam, dt, b, z0) -> np.ndarray:
    """Modal solution z (T, m) of dz/dt = lam z + b(t), b linear between samples."""
    ea, phi1, phi2 = _foh_coefficients(lam, dt)
    c = phi1 * b[:-1] + phi2 * (b[1:] - b[:-1])  # (T-1, m)
    z = np.empty_like(b)
    z[0] = z0
    if dt.size and np.ptp(dt) <= 1e-9 * dt.mean():
        k = np.arange(1, dt.size + 1)[:, None]
        for j in range(lam.size):
            z[1:, j] = lfilter([1.0], [1.0, -ea[0, j]], c[:, j])
        z[1:] += np.exp(lam[None, :] * dt[0] * k) * z0[None, :]
        return z
    # irregular sampling: parallel prefix scan of the affine maps z -> a z + c
    a = ea.copy()
    cc = c.copy()
    off = 1
    while off < a.shape[0]:
        cc[off:] = a[off:] * cc[:-off] + cc[off:]
        a[off:] = a[off:] * a[:-off]
        off *= 2
    z[1:] = a * z0[None, :] + cc
    return z


def _hidden_index(model: HeliModel) -> np.ndarray:
    return np.array([model.state_names.index(s) for s in model.hidden_state_names], dtype=int)


def _rates_at(model, x_row, u_row, w_row, env_row, hid, pm, hh):
    """f_h at one body row for hidden states hh (K, r, m), parameter sets pm (K|1, P)."""
    k, r, m = hh.shape
    xx = np.repeat(x_row[None], k * r, 0)
    xx[:, hid] = hh.reshape(k * r, m)
    p = pm if pm.shape[0] == 1 else np.repeat(pm, r, axis=0)
    out = model.derivatives(xx, u_row[None], w_row[None], env_row, p)[:, hid]
    return out.reshape(k, r, m)


def _jac_sets(fun, z: np.ndarray, eps: float = 1e-7) -> np.ndarray:
    """Central-difference Jacobians (K, m, m) of fun((K, r, m)) -> (K, r, m) at z (K, m),
    one batched call."""
    k, m = z.shape
    step = eps * np.maximum(1.0, np.abs(z))
    eye = np.eye(m)[None] * step[:, None, :]
    pts = np.concatenate([z[:, None, :], z[:, None, :] + eye, z[:, None, :] - eye], axis=1)
    out = fun(pts)
    d = out[:, 1 : m + 1] - out[:, m + 1 :]  # [k, j, i] = f_i(+e_j) - f_i(-e_j)
    return np.swapaxes(d, 1, 2) / (2.0 * step[:, None, :])


def _solve(a: np.ndarray, r: np.ndarray) -> np.ndarray:
    return np.linalg.solve(a, r[..., None])[..., 0]


@dataclass
class _Linearisation:
    """Per parameter set: reference hidden state h_ref (K,m), A0 (K,m,m) and its
    eigen-decomposition, the quasi-steady start h0 (K,m) and a state scale (K,m)."""

    h_ref: np.ndarray
    a0: np.ndarray
    lam: np.ndarray
    vec: np.ndarray
    vinv: np.ndarray
    h0: np.ndarray
    scale: np.ndarray


def _linearise(model, fa: FlightArrays, w: np.ndarray, pm: np.ndarray, hid) -> _Linearisation:
    """A0 at the representative row (flight medians, h quasi-steady there, Newton) and the
    quasi-steady hidden state at the first sample, for K parameter sets at once."""
    x, u, env = fa.x, fa.u, fa.env
    k = pm.shape[0]
    m = hid.size
    xr, ur, wr = np.median(x, axis=0), np.median(u, axis=0), np.median(w, axis=0)
    er = {name: np.median(v) for name, v in env.items()}

    def f_ref(hh):
        return _rates_at(model, xr, ur, wr, er, hid, pm, hh)

    h = np.zeros((k, m))
    for _ in range(6):  # quasi-steady hidden state at the reference (Newton)
        a0 = _jac_sets(f_ref, h)
        h = h - _solve(a0, f_ref(h[:, None, :])[:, 0])
    a0 = _jac_sets(f_ref, h)
    lam, vec = np.linalg.eig(a0)
    vinv = np.linalg.inv(vec)
    e0 = {name: v[:1] for name, v in env.items()}

    def f0(hh):
        return _rates_at(model, x[0], u[0], w[0], e0, hid, pm, hh)

    h0 = h.copy()
    for _ in range(4):  # quasi-steady start at the first sample
        h0 = h0 - _solve(a0, f0(h0[:, None, :])[:, 0])
    # scale of each hidden state's variation along the flight (convergence test): one
    # Newton step from h_ref at up to 64 samples
    pick = np.unique(np.linspace(0, x.shape[0] - 1, min(64, x.shape[0])).astype(int))
    r = pick.size
    xx = np.repeat(x[pick][None], k, 0).reshape(k * r, -1)
    xx[:, hid] = np.repeat(h, r, axis=0)
    ee = {name: v[pick] if k == 1 else np.tile(v[pick], k) for name, v in env.items()}
    f = model.derivatives(xx, np.tile(u[pick], (k, 1)), np.tile(w[pick], (k, 1)), ee,
                          pm if k == 1 else np.repeat(pm, r, axis=0))[:, hid].reshape(k, r, m)
    h_qs = h[:, None, :] - np.linalg.solve(a0[:, None], f[..., None])[..., 0]
    size = np.abs(h) + np.std(h_qs, axis=1)
    # rate-like states are ~0 at every quasi-steady point: give them a floor from the
    # largest state, or their convergence test would ask for rounding-level changes
    scale = np.maximum(size, np.maximum(1e-2 * size.max(axis=1, keepdims=True), 1e-9))
    return _Linearisation(h, a0, lam, vec, vinv, h0, scale)


def _reconstruct_compiled(model, fa, w, pm, tol, max_iter):
    """(h (K, T, m), measurement (K, T, 6), iterations, change) for K parameter sets."""
    hid = _hidden_index(model)
    lin = _linearise(model, fa, w, pm, hid)
    k, m = lin.h0.shape
    nt = fa.t.size
    if w.strides[0] == 0:  # one wind for the whole flight
        w = w[:1]
    a = model._rows(fa.x[:1], fa.u[:1], w, fa.env, None)
    w = a.w
    ws, hs, oms = int(w.shape[0] > 1), int(a.h.size > 1), int(a.om.size > 1)
    hout = np.empty((k, nt, m))
    mout = np.empty((k, nt, 6))
    stats = np.zeros((k, 3))
    model.compiled.fns.hidden_pass(
        k, nt, _plain(fa.t), _plain(fa.x), _plain(fa.u), w, ws, a.h, hs, a.om, oms,
        _plain(pm), int(pm.shape[0] > 1), np.ascontiguousarray(lin.lam, dtype=complex),
        np.ascontiguousarray(lin.vec, dtype=complex),
        np.ascontiguousarray(lin.vinv, dtype=complex), np.ascontiguousarray(lin.a0, dtype=float),
        np.ascontiguousarray(lin.h0), np.ascontiguousarray(lin.scale), float(tol),
        max(int(max_iter), 2), hout, mout, stats,
    )
    return hout, mout, int(stats[:, 0].max()), float(stats[:, 1].max())


def reconstruct_hidden(
    model: HeliModel,
    flight,
    wind=None,
    params=None,
    max_iter: int = 12,
    tol: float = 1e-9,
) -> HiddenStates:
    """Hidden-state trajectories (T, m) consistent with the flight's measured body motion
    (see the module docstring). `params` is None, one full parameter vector or a dict.
    max_iter/tol: iterations per sample (compiled pass) or per sweep (relaxation) and the
    relative change that ends them."""
    fa = flight if isinstance(flight, FlightArrays) else flight_arrays(model, flight)
    n = fa.t.size
    w = _wind_array(wind, n)
    names = model.hidden_state_names
    if not names:
        return HiddenStates(np.zeros((n, 0)), [], 0, 0.0)
    if model.is_compiled:
        pm = model._param_matrix(params)
        if pm.shape[0] != 1:
            raise ValueError("reconstruct_hidden takes one parameter set; "
                             "use predict_measurements for (K, P) sets")
        h, _z, it, change = _reconstruct_compiled(model, fa, w, pm, tol, max_iter)
        return HiddenStates(h[0], names, it, change)
    return _reconstruct_relaxation(model, fa, w, params, max_iter, tol)


def _reconstruct_relaxation(model, fa, w, params, max_iter, tol) -> HiddenStates:
    """Waveform relaxation over the whole flight (models with numpy stages)."""
    t, x, u, env = fa.t, fa.x.copy(), fa.u, fa.env
    n = t.size
    names = model.hidden_state_names
    hid = _hidden_index(model)
    m = hid.size

    def rates(xx, uu, ww, ee):
        return model.derivatives(xx, uu, ww, ee, params)[:, hid]

    # representative row: medians of the flight
    xr = np.median(x, axis=0)
    ur = np.median(u, axis=0)
    wr = np.median(w, axis=0)
    er = {k: np.median(v) for k, v in env.items()}

    def f_ref(hh):
        xx = np.repeat(xr[None], hh.shape[0], 0)
        xx[:, hid] = hh
        return rates(xx, ur[None], wr[None], er)

    h = np.zeros(m)
    for _ in range(6):  # quasi-steady hidden state at the reference (Newton)
        a0 = _jac(f_ref, h)
        h = h - np.linalg.solve(a0, f_ref(h[None])[0])
    a0 = _jac(f_ref, h)
    lam, vec = np.linalg.eig(a0)
    vinv = np.linalg.inv(vec)

    # quasi-steady start at the first sample
    e0 = {k: v[:1] for k, v in env.items()}

    def f0(hh):
        xx = np.repeat(x[:1], hh.shape[0], 0)
        xx[:, hid] = hh
        return rates(xx, u[:1], w[:1], e0)

    h0 = h.copy()
    for _ in range(4):
        h0 = h0 - np.linalg.solve(a0, f0(h0[None])[0])

    dt = np.diff(t)
    hs = np.repeat(h0[None], n, 0)
    scale = np.maximum(np.abs(h), 1e-6)
    change = np.inf
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 — `it` is reported
        x[:, hid] = hs
        g = rates(x, u, w, env) - hs @ a0.T
        b = g @ vinv.T
        z = _lti_solve(lam, dt, b, vinv @ h0)
        new = np.real(z @ vec.T)
        change = float(np.max(np.abs(new - hs) / (np.std(new, axis=0) + scale)))
        hs = new
        if change < tol:
            break
    return HiddenStates(hs, names, it, change)


def predict_measurements(
    model: HeliModel,
    flight,
    wind=None,
    params=None,
    hidden: HiddenStates | np.ndarray | None = None,
    return_hidden: bool = False,
):
    """Predicted measurement (T, 6), channels `MEAS_CHANNELS`.

    flight: FlightTable, DataFrame or mapping with t_s, the inputs, body states,
        rotor_speed_rad_s (optional) and height_agl_m (optional).
    wind: None (still air), (6,) constant or (T, 6) eq 5.3 wind per sample.
    params: None, a full parameter vector (P,), a dict, or (K, P) parameter sets
        -> returns (K, T, 6) (one hidden-state reconstruction per set; an all-kernel
        model runs all K in one compiled pass, no Python loop over K).
    hidden: precomputed hidden states (e.g. shared by many winds in a particle filter).
    return_hidden: also return the HiddenStates (h (T, m), or (K, T, m) for K sets).
    """
    fa = flight if isinstance(flight, FlightArrays) else flight_arrays(model, flight)
    w = _wind_array(wind, fa.t.size)
    sets = params is not None and not isinstance(params, Mapping) and np.ndim(params) == 2
    if hidden is None and model.is_compiled and model.hidden_state_names:
        pm = model._param_matrix(params)
        h, z, it, change = _reconstruct_compiled(model, fa, w, pm, 1e-9, 12)
        if sets:
            hs = HiddenStates(h, model.hidden_state_names, it, change)
            return (z, hs) if return_hidden else z
        hs = HiddenStates(h[0], model.hidden_state_names, it, change)
        return (z[0], hs) if return_hidden else z[0]
    if sets:
        out = [predict_measurements(model, fa, w, p, None, True) for p in np.asarray(params)]
        z = np.stack([o[0] for o in out])
        if return_hidden:
            hs = HiddenStates(np.stack([o[1].h for o in out]), model.hidden_state_names,
                              max(o[1].iterations for o in out),
                              max(o[1].change for o in out))
            return z, hs
        return z
    if hidden is None:
        hidden = reconstruct_hidden(model, fa, w, params)
    h = hidden.h if isinstance(hidden, HiddenStates) else np.asarray(hidden)
    x = fa.x.copy()
    x[:, _hidden_index(model)] = h
    z = model.measure(x, fa.u, w, fa.env, params)
    return (z, hidden) if return_hidden else z


def windowed_measurements(model: HeliModel, x, u, env, idx, params, h_ref, a_t, a_inv_t,
                          e_t, p1_t, p2_t, wind=None, newton: int = 4):
    """Predicted measurement (K, W, L, 6) of K parameter sets over the windows idx (W, L)
    of a flight, the hidden states propagated along each window by the calibration's
    exponential time differencing (`airwake.calibrate.hidden.HiddenPropagator`: its
    reference states h_ref (K, m) and its matrices, each (K, m, m) and transposed: A^T,
    (A^-1)^T, E^T, (Phi1 + Phi2/dt)^T, (Phi2/dt)^T), in one compiled pass; None for a
    model with numpy stages (the caller steps it in Python).

    x (N, S) with the body states filled, u (N, 4), env {name: (N,)}, params (K, P),
    wind None (still air) or one (6,) wind for every row."""
    if not model.is_compiled:
        return None
    pm = model._param_matrix(params)
    k = pm.shape[0]
    idx = np.ascontiguousarray(idx, dtype=np.int64)
    w = None if wind is None else np.asarray(wind, dtype=float).reshape(1, 6)
    a = model._rows(x[:1], u[:1], w, env, None)  # the environment arrays, or one default
    z = np.empty((k, idx.shape[0], idx.shape[1], 6))

    def mats(m):
        return np.ascontiguousarray(m, dtype=float)

    model.compiled.fns.windows_pass(
        k, idx, _plain(np.asarray(x, dtype=float)), _plain(np.asarray(u, dtype=float)),
        a.w, 0, a.h, int(a.h.size > 1), a.om, int(a.om.size > 1), _plain(pm), int(k > 1),
        mats(h_ref), mats(a_t), mats(a_inv_t), mats(e_t), mats(p1_t), mats(p2_t),
        int(newton), z)
    return z


CHANNELS = MEAS_CHANNELS
