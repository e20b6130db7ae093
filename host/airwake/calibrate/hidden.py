"""Hidden rotor states propagated per row: the measurement model for many parameter
sets (calibration) or many winds (particle filter) at once, one model evaluation per
time step.

The body states come from the flight table; the rotor's own states h (flapping,
lead-lag, flybar, and any state an added effect declares) are not measured. They obey

    dh/dt = f_h(h, body(t), u(t), w, env(t); params)

and are stiff (lag modes at ~50 Hz, lightly damped) next to the 150 Hz sampling, so an
explicit step at the table rate is unstable. Per parameter set k we linearise once,
A_k = d f_h/dh at a representative row (flight medians, h at its quasi-steady value),
and integrate the linear part exactly (exponential time differencing); the nonlinear
remainder g = f_h - A_k h is taken linear over each step:

    h(t_n + dt) = E h_n + Phi1 g_n + (Phi2/dt) (g_{n+1} - g_n)
    E = e^{A dt},  Phi1 = int_0^dt e^{A(dt-s)} ds,  Phi2 = int_0^dt e^{A(dt-s)} s ds

(E, Phi1, Phi2 from one matrix exponential of the block matrix [[A, I, 0], [0, 0, I],
[0, 0, 0]] dt, Van Loan's method). g_{n+1} needs h at n+1, so each step is a
predictor-corrector in PEC mode with a single model evaluation:

    predict   h^p_{n+1} = E h_n + Phi1 g_n + (Phi2/dt) (g_n - g_{n-1})   (extrapolated)
    evaluate  g_{n+1}, z_{n+1} at h^p_{n+1}      <- the one model call of the step
    correct   h_{n+1}   = E h_n + Phi1 g_n + (Phi2/dt) (g_{n+1} - g_n)   (trapezoid)

The same evaluation gives the predicted measurement z_{n+1}. On model-generated data
this matches `airwake.heli.measurement.predict_measurements` (whole-flight waveform
relaxation, first-order hold): qdot/pdot differences ~0.002 rad/s^2, 100x below sensor
noise; the predictor alone (ETD2, no correction) is ~8x worse. Start: h quasi-steady
(Newton on f_h = 0 with A_k) at the first row.

Running forward in time lets it carry per-row states (particles with their own wind
history) and short windows (calibration on many parameter sets in one batch).
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm


def single_blas_thread():
    """Context: BLAS on one thread. The loops here multiply many small matrices; a
    multi-threaded BLAS spends more time waking threads than computing (5x slower on a
    busy 2-core machine), and the filter's budget is one core."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - a declared dependency
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")


def evaluate_rates_and_measurement(model, x, u, w, env, params):
    """(dx/dt (N,S), z (N,6)) from one batched model evaluation."""
    fast = getattr(model, "rates_and_measurement", None)
    if fast is not None:
        return fast(x, u, w, env, params)
    ctx = model.evaluate(x, u, w, env, params)
    return ctx.xdot, ctx.meas


def hidden_indices(model) -> np.ndarray:
    return np.array([model.state_names.index(s) for s in model.hidden_state_names], dtype=int)


def etd2_matrices(a: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """E, Phi1, Phi2/dt for a batch of matrices a (K, m, m) (see module docstring)."""
    k, m, _ = a.shape
    c = np.zeros((k, 3 * m, 3 * m))
    eye = np.eye(m)
    c[:, :m, :m] = a * dt
    c[:, :m, m : 2 * m] = eye * dt
    c[:, m : 2 * m, 2 * m :] = eye * dt
    big = expm(c)
    # expm(C dt), C = [[A, I, 0], [0, 0, I], [0, 0, 0]]: x' = A x + a, a' = b, b' = 0
    # -> x(dt) = E x0 + Phi1 a0 + Phi2 b (top row of blocks)
    return big[:, :m, :m], big[:, :m, m : 2 * m], big[:, :m, 2 * m :] / dt


@dataclass
class RowBatch:
    """Per-step inputs for R rows of K parameter sets: x (K*R, S) with the body part
    filled, u (K*R, 4), w (K*R, 6) or (1, 6), env {name: (K*R,)}."""

    x: np.ndarray
    u: np.ndarray
    w: np.ndarray
    env: dict


class HiddenPropagator:
    """ETD2 propagation of the hidden states of K parameter sets x R rows each.

    model: HeliModel; dt: step (s); params: None (the model's own values) or (K, P) full
    parameter vectors; reference: (x_ref (S,), u_ref (4,), w_ref (6,), env_ref {name:
    float}) the representative row A_k is taken at. Shapes: h (K, R, m).
    """

    NEWTON_ITERATIONS = 5
    QUASI_STEADY_ITERATIONS = 4  # Newton steps to a window's / filter's quasi-steady start
    # `valid` (K,): False for a parameter set whose rotor dynamics could not be linearised
    # (non-finite or singular Jacobian); its rows still run, on a stand-in A = -I.

    def __init__(self, model, dt: float, params=None, reference=None) -> None:
        self.model = model
        self.dt = float(dt)
        self.hid = hidden_indices(model)
        self.m = self.hid.size
        self.params = None if params is None else np.atleast_2d(np.asarray(params, dtype=float))
        self.k = 1 if self.params is None else self.params.shape[0]
        x_ref, u_ref, w_ref, env_ref = reference
        self.h_ref, self.a = self._reference_jacobians(
            np.asarray(x_ref, dtype=float), np.asarray(u_ref, dtype=float),
            np.asarray(w_ref, dtype=float), env_ref)
        self.a_inv = np.linalg.inv(self.a)
        self._a_t = np.ascontiguousarray(np.swapaxes(self.a, 1, 2))
        self._mats: dict[float, tuple] = {}
        self.matrices(self.dt)

    # -- setup ------------------------------------------------------------------------
    def _rows_params(self, reps: int):
        """Parameter matrix for K sets x `reps` rows each, or None."""
        if self.params is None:
            return None
        return np.repeat(self.params, reps, axis=0)

    def _reference_jacobians(self, x_ref, u_ref, w_ref, env_ref):
        k, m, hid = self.k, self.m, self.hid
        n_pts = 1 + 2 * m
        params = self._rows_params(n_pts)
        env = {n: np.full(k * n_pts, float(v)) for n, v in env_ref.items()}
        h = np.tile(x_ref[hid], (k, 1))
        eps = 1e-7 * np.maximum(1.0, np.abs(h))  # (k, m)

        def jac(h):
            pts = np.repeat(h[:, None, :], n_pts, 1)  # (k, n_pts, m)
            idx = np.arange(m)
            pts[:, 1 + idx, idx] += eps
            pts[:, 1 + m + idx, idx] -= eps
            x = np.repeat(x_ref[None], k * n_pts, 0)
            x[:, hid] = pts.reshape(-1, m)
            xd, _ = evaluate_rates_and_measurement(
                self.model, x, u_ref[None], w_ref[None], env, params)
            f = xd[:, hid].reshape(k, n_pts, m)
            a = (f[:, 1 : 1 + m] - f[:, 1 + m :]) / (2 * eps[:, :, None])  # (k, j, i)
            return f[:, 0], np.swapaxes(a, 1, 2)

        valid = np.ones(k, dtype=bool)
        eye = np.eye(m)
        with np.errstate(all="ignore"):
            for _ in range(self.NEWTON_ITERATIONS + 1):
                f0, a = jac(h)
                bad = ~(np.all(np.isfinite(a), axis=(1, 2)) & np.all(np.isfinite(f0), axis=1))
                bad |= ~np.isfinite(np.linalg.cond(np.where(bad[:, None, None], -eye, a)))
                valid &= ~bad
                a[~valid] = -eye  # a harmless stand-in: the set is reported invalid
                f0[~valid] = 0.0
                if _ == self.NEWTON_ITERATIONS:
                    break
                h = h - np.linalg.solve(a, f0[..., None])[..., 0]
                h[~valid] = 0.0
        self.valid = valid
        return h, a

    def matrices(self, dt: float):
        """(E, Phi1, Phi2/dt), each (K, m, m), cached per step length."""
        key = round(float(dt), 12)
        if key not in self._mats:
            if len(self._mats) > 64:
                self._mats.clear()
            self._mats[key] = etd2_matrices(self.a, float(dt))
        return self._mats[key]

    def step_matrices(self, dt: float | None = None):
        """(E^T, (Phi1 + Phi2/dt)^T, (Phi2/dt)^T), each (K, m, m) C-contiguous, for
        right-multiplying row vectors (see predict/correct)."""
        key = ("rows", round(float(self.dt if dt is None else dt), 12))
        if key not in self._mats:
            e, phi1, phi2 = self.matrices(key[1])

            def t(a):
                return np.ascontiguousarray(np.swapaxes(a, 1, 2))

            self._mats[key] = (t(e), t(phi1 + phi2), t(phi2))
        return self._mats[key]

    # -- stepping -----------------------------------------------------------------------
    def evaluate(self, h: np.ndarray, rows: RowBatch, params_rows):
        """g = f_h - A h (K, R, m) and z (K, R, 6) at the rows with hidden states h."""
        k, r, m = h.shape
        x = rows.x
        x[:, self.hid] = h.reshape(k * r, m)
        xd, z = evaluate_rates_and_measurement(self.model, x, rows.u, rows.w, rows.env,
                                               params_rows)
        f = xd[:, self.hid].reshape(k, r, m)
        g = f - np.matmul(h, self._a_t)
        return g, f, z.reshape(k, r, 6)

    @property
    def a_t(self) -> np.ndarray:
        """A^T per set (K, m, m), C-contiguous."""
        return self._a_t

    @property
    def a_inv_t(self) -> np.ndarray:
        """(A^-1)^T per set (K, m, m): the quasi-steady Newton step's matrix."""
        return np.swapaxes(self.a_inv, 1, 2)

    def quasi_steady(self, h: np.ndarray, rows: RowBatch, params_rows,
                     iterations: int = QUASI_STEADY_ITERATIONS):
        """Newton steps towards f_h = 0 at the rows (start of a window / of a filter)."""
        a_inv_t = self.a_inv_t
        for _ in range(iterations):
            _, f, _ = self.evaluate(h, rows, params_rows)
            h = h - np.matmul(f, a_inv_t)
        return h

    def _mats_for(self, h, dt):
        mats = self.step_matrices(dt)
        return tuple(m[0] for m in mats) if h.ndim == 2 else mats

    def predict(self, h, g, g_prev, dt: float | None = None) -> np.ndarray:
        """Predictor h^p_{n+1} (K, R, m) from h_n, g_n, g_{n-1} (each (K, R, m); or
        (R, m) when K = 1)."""
        e_t, p1_t, p2_t = self._mats_for(h, dt)
        out = np.matmul(h, e_t)
        out += np.matmul(g, p1_t)
        out -= np.matmul(g_prev, p2_t)
        return out

    def correct(self, h_pred, g, g_prev, g_next, dt: float | None = None) -> np.ndarray:
        """Corrector h_{n+1} = h^p_{n+1} + (Phi2/dt)(g_{n+1} - 2 g_n + g_{n-1}) (the
        trapezoid E h_n + Phi1 g_n + (Phi2/dt)(g_{n+1} - g_n) written around h^p)."""
        _, _, p2_t = self._mats_for(h_pred, dt)
        d = g_next - 2.0 * g
        d += g_prev
        return h_pred + np.matmul(d, p2_t)
