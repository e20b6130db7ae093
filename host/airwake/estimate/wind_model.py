"""The state-space model the wind particle filter runs on (model apart from algorithm).

State of one particle: the eq 5.3 wind w = [v_x v_y v_z w_x w_y w_z] (body axes, at the
hub) and its own hidden rotor states h (flapping, lead-lag, flybar, ...), see
docs/wind-estimation.md for why the rotor states are carried per particle.

    transition   w_{n+1} = w_n + q * sqrt(dt) * N(0, I)        (random walk, per component)
                 h_{n+1}: exponential predictor-corrector        (airwake.calibrate.hidden)
    observation  z_n = z_hat(body_n, u_n, w_n, h_n) + noise     (6 acceleration channels)
    likelihood   log p(z_n | particle) = -|| (z_n - z_hat) / s || / sigma     (eq 5.17)

with s (6,) the channel scales (measurement noise std per channel: m/s^2 and rad/s^2
made comparable) and sigma the reference's error sensitivity factor. The wind stays in
a box (`bounds`): a random-walk step or a jitter that leaves it is clipped.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from airwake.calibrate.hidden import (
    HiddenPropagator,
    RowBatch,
    evaluate_rates_and_measurement,
)

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
        self._x = None
        self._a_t = np.ascontiguousarray(self.prop.a[0].T)
        self._h_pred = None
        hid = self.hid
        contiguous = hid.size > 0 and np.array_equal(hid, np.arange(hid[0], hid[0] + hid.size))
        self._hid_slice = slice(int(hid[0]), int(hid[-1]) + 1) if contiguous else None
        self._body_slice = slice(0, int(hid[0])) if contiguous else None
        if contiguous and hid[-1] + 1 != model.n_states:
            self._hid_slice = None

    # -- rows -------------------------------------------------------------------------
    def _rows(self, k: int, hidden: np.ndarray, wind: np.ndarray) -> RowBatch:
        n = hidden.shape[0]
        if self._x is None or self._x.shape[0] != n:
            self._x = np.empty((n, self.model.n_states))
            self._body = np.setdiff1d(np.arange(self.model.n_states), self.hid)
        x = self._x
        if self._hid_slice is not None:  # the usual layout: body first, rotor states after
            x[:, self._body_slice] = self.data.x[k, self._body_slice]
            x[:, self._hid_slice] = hidden
        else:
            x[:] = self.data.x[k]
            x[:, self.hid] = hidden
        env = {name: v[k : k + 1] for name, v in self.data.env.items()}
        return RowBatch(x, self.data.u[k : k + 1], wind, env)

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
        """Random-walk the wind from sample k-1 to k (in place)."""
        step = self.process_std * np.sqrt(self.dt[k - 1])
        noise = rng.standard_normal(p.wind.shape)
        noise *= step
        p.wind += noise
        np.clip(p.wind, -self.bounds, self.bounds, out=p.wind)
        if self.restart[k]:
            self.restart_hidden(p, k)

    def predict(self, p: Particles, k: int):
        """(z_hat (N, 6), g (N, m)): predicted measurement at sample k from one batched
        model evaluation at the particles' predicted rotor states, and the remainder g
        there (what `advance` corrects the rotor states with)."""
        if p.started:
            h = self.prop.predict(p.hidden, p.g, p.g_prev, self.dt[k - 1])
        else:
            h = p.hidden
        self._h_pred = h
        rows = self._rows(k, h, p.wind)
        with np.errstate(all="ignore"):
            xd, z = evaluate_rates_and_measurement(self.model, rows.x, rows.u, rows.w,
                                                   rows.env, None)
            g = xd[:, self._hid_slice] if self._hid_slice is not None else xd[:, self.hid]
            g = g - h @ self._a_t
        return z, g

    def log_likelihood(self, z_hat: np.ndarray, k: int, sigma: float) -> np.ndarray:
        """eq 5.17: -||(z - z_hat)/s|| / sigma, (N,); non-finite predictions -> -inf."""
        e = (self.data.z[k] - z_hat) / self.scale
        ll = -np.sqrt(np.einsum("nc,nc->n", e, e)) / sigma
        return np.where(np.isfinite(ll), ll, -np.inf)

    def advance(self, p: Particles, g: np.ndarray, k: int) -> None:
        """Correct the rotor states to sample k with g from `predict` (the corrector of
        airwake.calibrate.hidden). A particle whose rotor state is no longer finite
        restarts at the reference."""
        if p.started:
            with np.errstate(all="ignore"):
                h = self.prop.correct(self._h_pred, p.g, p.g_prev, g, self.dt[k - 1])
            p.g_prev = p.g
        else:
            h = p.hidden
            p.g_prev = g
        p.hidden, p.g = h, g
        bad = ~np.isfinite(h.sum(axis=1) + g.sum(axis=1))
        if bad.any():
            h[bad] = self.prop.h_ref[0]
            g[bad] = 0.0
            p.g_prev = p.g_prev.copy()
            p.g_prev[bad] = 0.0

    def clip(self, wind: np.ndarray) -> np.ndarray:
        return np.clip(wind, -self.bounds, self.bounds)

    def process_step_std(self, k: int) -> np.ndarray:
        return self.process_std * np.sqrt(self.dt[max(k - 1, 0)])
