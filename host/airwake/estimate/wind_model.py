"""The state-space model the wind particle filter runs on (model apart from algorithm).

State of one particle: the eq 5.3 wind w = [v_x v_y v_z w_x w_y w_z] (body axes, at the
hub) and its own hidden rotor states h (flapping, lead-lag, flybar, ...), see
docs/wind-estimation.md for why the rotor states are carried per particle.

    transition   w_n = w_{n-1} + q * sqrt(dt) * N(0, I)         (random walk, per component)
                 h_n: exponential predictor-corrector            (airwake.calibrate.hidden)
    observation  z_n = z_hat(body_n, u_n, w_n, h_n) + noise      (6 acceleration channels)
    likelihood   log p(z_n | particle) = -|| (z_n - z_hat) / s || / sigma     (eq 5.17)

with s (6,) the channel scales (measurement noise std per channel: m/s^2 and rad/s^2
made comparable) and sigma the reference's error sensitivity factor. The filter calls
`propagate` (random walk + rotor-state predictor) and `log_likelihood` (the one batched
model evaluation of the sample, which also completes the rotor-state step: the
corrector needs the derivative at the new sample). The wind stays in a box (`bounds`):
a random-walk step or a jitter that leaves it is clipped. The per-particle arithmetic
is compiled (`airwake.estimate.kernels`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from airwake.calibrate.hidden import (
    HiddenPropagator,
    RowBatch,
    evaluate_rates_and_measurement,
)
from airwake.estimate.kernels import observe_rows, transition_rows

# Default process noise (random-walk intensity, per sqrt(s)) and boxes. Vorticity
# components are scaled to their plausible range: |v| up to ~10 m/s, |w| up to ~1 1/s.
PROCESS_STD = (0.5, 0.5, 0.5, 0.1, 0.1, 0.1)  # m/s/sqrt(s), rad/s/sqrt(s)
INIT_HALF_WIDTH = (6.0, 6.0, 3.0, 1.0, 1.0, 1.0)  # uniform prior box around 0
BOUNDS = (15.0, 15.0, 8.0, 3.0, 3.0, 3.0)  # |component| never exceeds these


@dataclass
class Particles:
    """wind (N, 6); hidden (N, m) rotor states at the current sample; g, g_prev (N, m)
    the rotor-state remainder at the current and the previous sample (None right after
    a (re)start, when the rotor states are quasi-steady)."""

    wind: np.ndarray
    hidden: np.ndarray
    g: np.ndarray | None = None
    g_prev: np.ndarray | None = None

    @property
    def started(self) -> bool:
        return self.g is not None

    def __len__(self) -> int:
        return self.wind.shape[0]

    def take(self, idx: np.ndarray) -> Particles:
        def pick(a):
            return None if a is None else a[idx]

        return Particles(self.wind[idx], self.hidden[idx], pick(self.g), pick(self.g_prev))


class WindMeasurementModel:
    """Wind random walk + helicopter measurement model over one flight.

    model: HeliModel (calibrated); data: `airwake.calibrate.residuals.FlightData` (body
    states, inputs, env, measured z, channel scales); process_std (6,); init_half_width
    (6,); bounds (6,)."""

    def __init__(self, model, data, process_std=PROCESS_STD, init_half_width=INIT_HALF_WIDTH,
                 bounds=BOUNDS, channel_scale=None) -> None:
        self.model = model
        self.data = data
        self.process_std = np.asarray(process_std, dtype=float)
        self.init_half_width = np.asarray(init_half_width, dtype=float)
        self.bounds = np.asarray(bounds, dtype=float)
        for name, v in (("process_std", self.process_std),
                        ("init_half_width", self.init_half_width), ("bounds", self.bounds)):
            if v.shape != (6,) or not np.all(np.isfinite(v)) or np.any(v < 0):
                raise ValueError(f"{name} must be 6 non-negative numbers, got {v}")
        self.scale = np.asarray(data.scale if channel_scale is None else channel_scale, float)
        self.prop = HiddenPropagator(model, data.dt, None, data.reference_row())
        if not self.prop.valid[0]:
            raise ValueError("the model's rotor dynamics cannot be linearised at this "
                             "flight's median state (non-finite or singular Jacobian)")
        self.hid = self.prop.hid
        self.n_steps = data.t.size
        dt = np.diff(data.t)
        self.dt = np.append(dt, data.dt)
        # a step longer than 3 typical steps is a gap: rotor states restart quasi-steady
        self.restart = np.zeros(self.n_steps, dtype=bool)
        self.restart[0] = True
        self.restart[1:] = dt > 3.0 * data.dt
        self._buffers: dict[str, np.ndarray] = {}
        self._a_t = np.ascontiguousarray(self.prop.a[0].T)
        self._eye = np.eye(self.prop.m)
        self._zero6 = np.zeros(6)
        self._step = self._zero6
        self._prepared = -1

    # -- rows -------------------------------------------------------------------------
    def _rows(self, k: int, hidden: np.ndarray, wind: np.ndarray) -> RowBatch:
        n = hidden.shape[0]
        x = self._buffer("x", (n, self.model.n_states))
        x[:] = self.data.x[k]
        x[:, self.hid] = hidden
        return RowBatch(x, self.data.u[k : k + 1], wind, self._env(k))

    def _env(self, k: int) -> dict:
        return {name: v[k : k + 1] for name, v in self.data.env.items()}

    def _buffer(self, name: str, shape) -> np.ndarray:
        buf = self._buffers.get(name)
        if buf is None or buf.shape != shape:
            buf = self._buffers[name] = np.empty(shape)
        return buf

    def evaluate(self, x, u, w, env):
        """(dx/dt, z) of the helicopter model for the particles' rows (one call)."""
        return evaluate_rates_and_measurement(self.model, x, u, w, env, None)

    # -- the filter's calls ----------------------------------------------------------
    def initial(self, n: int, rng: np.random.Generator) -> Particles:
        """Wind uniform in +-init_half_width, rotor states quasi-steady at sample 0."""
        wind = rng.uniform(-1.0, 1.0, (n, 6)) * self.init_half_width
        wind = np.clip(wind, -self.bounds, self.bounds)
        p = Particles(wind, np.repeat(self.prop.h_ref[0][None], n, 0))
        self.restart_hidden(p, 0)
        return p

    def restart_hidden(self, p: Particles, k: int) -> None:
        rows = self._rows(k, p.hidden, p.wind)
        with np.errstate(all="ignore"):
            h = self.prop.quasi_steady(p.hidden[None], rows, None)[0]
        bad = ~np.all(np.isfinite(h), axis=1)
        h[bad] = self.prop.h_ref[0]
        p.hidden = h
        p.g = p.g_prev = None

    def propagate(self, p: Particles, k: int, rng: np.random.Generator) -> None:
        """Transition from sample k-1 to k (in place): the wind's random walk, and the
        rotor states' predictor (completed by `log_likelihood`)."""
        noise = rng.standard_normal(p.wind.shape)
        self._step = self.process_std * np.sqrt(self.dt[k - 1])
        if self.restart[k]:
            p.wind = np.clip(p.wind + noise * self._step, -self.bounds, self.bounds)
            self.restart_hidden(p, k)
            return
        self._prepare(p, k, noise)

    def _prepare(self, p: Particles, k: int, noise) -> None:
        n, m = p.hidden.shape
        x = self._buffer("x", (n, self.model.n_states))
        h_pred = self._buffer("h_pred", (n, m))
        started = p.started
        if started:
            e_t, p1_t, p2_t = (a[0] for a in self.prop.step_matrices(self.dt[k - 1]))
            g, g_prev = p.g, p.g_prev
        else:
            e_t = p1_t = p2_t = self._eye
            g = g_prev = p.hidden
        if noise is None:  # rows only (first sample, after a restart): the wind stays
            noise = self._buffer("zero_noise", p.wind.shape)
            noise[:] = 0.0
        transition_rows(p.wind, noise, self._step, self.bounds, p.hidden, g, g_prev, e_t, p1_t,
                        p2_t, started, self.data.x[k], self.hid, x, h_pred)
        self._prepared = k

    def log_likelihood(self, p: Particles, k: int, sigma: float) -> np.ndarray:
        """eq 5.17 for every particle at sample k, (N,): -||(z - z_hat)/s|| / sigma from
        one batched model evaluation (non-finite predictions -> -inf). The same
        evaluation completes the rotor-state step to sample k (the corrector)."""
        n, m = p.hidden.shape
        if self._prepared != k:  # first sample or after a restart: rows not built yet
            self._prepare(p, k, None)
        x = self._buffers["x"]
        h_pred = self._buffers["h_pred"]
        with np.errstate(all="ignore"):
            xd, z = self.evaluate(x, self.data.u[k : k + 1], p.wind, self._env(k))
        started = p.started
        if not started:
            p.g = np.empty((n, m))
            p.g_prev = np.empty((n, m))
        p2_t = self.prop.step_matrices(self.dt[k - 1])[2][0] if started else self._eye
        ll = np.empty(n)
        observe_rows(np.ascontiguousarray(xd), np.ascontiguousarray(z), h_pred, p.hidden,
                     p.g, p.g_prev, self._a_t, p2_t, started, self.hid, self.prop.h_ref[0],
                     self.data.z[k], 1.0 / self.scale, 1.0 / sigma, ll)
        self._prepared = -1
        return ll

    def clip(self, wind: np.ndarray) -> np.ndarray:
        return np.clip(wind, -self.bounds, self.bounds)

    def process_step_std(self, k: int) -> np.ndarray:
        return self.process_std * np.sqrt(self.dt[max(k - 1, 0)])
