"""Measurement model: the 6 acceleration channels predicted from a flight's measured states.

`predict_measurements(model, flight)` returns (T, 6): specific force at the IMU
(acc_x/y/z_m_s2, without gravity) and angular accelerations (pdot/qdot/rdot_rad_s2), from
the flight table's *measured* body states, inputs and rotor speed (equation error /
one-step-ahead). The rotor's own states (flapping, lead-lag, flybar, and any state an
effect adds: servo lag, governor, …) are not in a flight table. They are reconstructed by
running their own dynamics, forced by the measured body motion, along the flight:

    dh/dt = f_h(h, body(t), u(t), w(t), env(t))                (hidden part of derivatives)

solved for the whole time series at once by *waveform relaxation*: with A0 the Jacobian
of f_h at a representative row (eigen-decomposed once),
    h^{k+1} = LTI_A0[ f_h(h^k, t) - A0 h^k ],  h(t0) = quasi-steady,
where LTI_A0 integrates dh/dt = A0 h + g(t) exactly for g linear between samples
(first-order hold; per mode a scalar complex recursion run by scipy's lfilter, or a
parallel prefix scan for irregular time steps). Each iteration is one vectorised model
evaluation over all samples; it converges in a few iterations because A0 differs from the
true Jacobian only through the slow variation of rotor speed, inflow and advance ratio.
No quasi-steady flapping: the rotor's ~20 ms lag would otherwise show up as a false
residual at pilot-input frequencies.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from airwake.heli.context import MEAS_CHANNELS
from airwake.heli.model import INPUT_NAMES, HeliModel


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


def reconstruct_hidden(
    model: HeliModel,
    flight,
    wind=None,
    params=None,
    max_iter: int = 12,
    tol: float = 1e-9,
) -> HiddenStates:
    """Hidden-state trajectories (T, m) consistent with the flight's measured body motion
    (see the module docstring). `params` is None, one full parameter vector or a dict."""
    fa = flight if isinstance(flight, FlightArrays) else flight_arrays(model, flight)
    t, x, u, env = fa.t, fa.x.copy(), fa.u, fa.env
    n = t.size
    w = _wind_array(wind, n)
    names = model.hidden_state_names
    hid = np.array([model.state_names.index(s) for s in names], dtype=int)
    m = hid.size
    if m == 0:
        return HiddenStates(np.zeros((n, 0)), [], 0, 0.0)

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
        -> returns (K, T, 6) (one hidden-state reconstruction per set).
    hidden: precomputed hidden states (e.g. shared by many winds in a particle filter).
    """
    if params is not None and not isinstance(params, Mapping) and np.ndim(params) == 2:
        out = [predict_measurements(model, flight, wind, p, None) for p in np.asarray(params)]
        return np.stack(out)
    fa = flight if isinstance(flight, FlightArrays) else flight_arrays(model, flight)
    w = _wind_array(wind, fa.t.size)
    if hidden is None:
        hidden = reconstruct_hidden(model, fa, w, params)
    h = hidden.h if isinstance(hidden, HiddenStates) else np.asarray(hidden)
    x = fa.x.copy()
    hid = [model.state_names.index(s) for s in model.hidden_state_names]
    x[:, hid] = h
    z = model.measure(x, fa.u, w, fa.env, params)
    return (z, hidden) if return_hidden else z


CHANNELS = MEAS_CHANNELS
