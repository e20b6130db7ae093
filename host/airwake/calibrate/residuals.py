"""Equation-error residuals of a flight for many parameter sets at once.

    data = FlightData.from_flight(model, flight)              # arrays + channel scales
    win = make_windows(data, window_s=2.0, warmup_s=1.0)     # (W, L) row indexes
    pred = WindowedPredictor(model, data, win)
    z = pred.predict(param_sets)                              # (K, W, L, 6)
    r = pred.residuals(param_sets)                            # (K, n_scored * 6), weighted

One-step-ahead (equation error): every predicted sample uses the *measured* body states,
inputs and rotor speed of that sample; only the hidden rotor states are simulated
(`airwake.calibrate.hidden`). The flight is cut into windows of `warmup + length`
samples; each window starts its hidden states quasi-steady, runs `warmup` samples that
are not scored (the rotor/flybar transients decay, slowest ~8 1/s), then scores
`length` samples. Scored parts tile every continuous run of the flight (split at time
gaps), so the first `warmup` samples of each run are the only ones never scored. An
all-kernel model runs every window of every parameter set in one compiled pass
(`airwake.heli.measurement.windowed_measurements`; `calibrate` on the demo's 20 s
calibration flight: 39 s stepped in Python, 28 s so); a model with numpy stages
advances all windows of all sets together in Python, one model evaluation of K x W rows
per time step.

Channel weighting: each channel is divided by its noise scale s_c, estimated from the
measured signal's second differences, s_c = 1.4826 MAD(z[n+1] - 2 z[n] + z[n-1]) / sqrt(6)
(white noise passes a second difference with variance 6 s^2; the helicopter's motion
below ~15 Hz hardly does at 150 Hz), floored at 1 % of the channel's std. With white
sensor noise this is the maximum-likelihood weighting and a converged fit has weighted
residual RMS ~ 1 per channel. Coloured noise (e.g. S-G differentiated rates) makes s_c an
underestimate; pass `channel_scale` explicitly then.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from airwake.calibrate.errors import CalibrationError
from airwake.calibrate.hidden import HiddenPropagator, RowBatch, single_blas_thread
from airwake.heli.context import MEAS_CHANNELS
from airwake.heli.measurement import windowed_measurements
from airwake.heli.model import INPUT_NAMES


def noise_scale(z: np.ndarray) -> np.ndarray:
    """Per-channel white-noise std estimate from second differences, (T, C) -> (C,)."""
    z = np.asarray(z, dtype=float)
    if z.shape[0] < 5:
        return np.maximum(np.std(z, axis=0), 1e-12)
    d2 = z[2:] - 2.0 * z[1:-1] + z[:-2]
    mad = np.median(np.abs(d2 - np.median(d2, axis=0)), axis=0)
    est = 1.4826 * mad / np.sqrt(6.0)
    return np.maximum(est, np.maximum(0.01 * np.std(z, axis=0), 1e-9))


def split_runs(t: np.ndarray, max_gap_factor: float = 3.0) -> list[slice]:
    """Continuous runs of samples (no spacing above max_gap_factor x the median)."""
    from airwake.record.differentiate import split_runs as _split

    return _split(t, max_gap_factor)


@dataclass
class FlightData:
    """Model arrays of one flight: t (T,), x (T,S) body states filled, u (T,4),
    env {name: (T,)}, z (T,6) measured channels, runs (continuous slices), dt (median
    step, s), scale (6,) channel weights' denominators, source (name for messages)."""

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    env: dict
    z: np.ndarray
    runs: list
    dt: float
    scale: np.ndarray
    source: str = "<flight>"

    @classmethod
    def from_flight(cls, model, flight, source: str | None = None,
                    channel_scale=None) -> FlightData:
        """From a FlightTable / DataFrame / mapping; CalibrationError on missing columns,
        non-finite values or non-increasing time (file, column and row named)."""
        from airwake.heli.measurement import flight_arrays

        df = getattr(flight, "df", flight)
        src = source or str(getattr(flight, "path", None) or "<flight>")
        cols = df if isinstance(df, dict) else {c: df[c].to_numpy() for c in df.columns}
        needed = ["t_s", *INPUT_NAMES, *MEAS_CHANNELS,
                  *[c for c in model.measured_states.values() if not c.startswith("pos_")]]
        missing = [c for c in needed if c not in cols]
        if missing:
            raise CalibrationError(f"{src}: missing column(s) {missing} needed for calibration")
        for c in [*needed, "rotor_speed_rad_s", "height_agl_m"]:
            if c not in cols:
                continue
            v = np.asarray(cols[c], dtype=float)
            bad = np.isnan(v) if c == "height_agl_m" else ~np.isfinite(v)
            if bad.any():
                i = int(np.argmax(bad))
                raise CalibrationError(
                    f"{src}: column '{c}' has {int(bad.sum())} NaN/non-finite value(s), "
                    f"first at row {i}")
        fa = flight_arrays(model, cols)
        dt_all = np.diff(fa.t)
        if fa.t.size < 3 or np.any(dt_all <= 0):
            i = int(np.argmax(dt_all <= 0)) + 1 if fa.t.size >= 2 else 0
            raise CalibrationError(
                f"{src}: column 't_s' must increase strictly with >= 3 rows (row {i})")
        z = np.column_stack([np.asarray(cols[c], dtype=float) for c in MEAS_CHANNELS])
        runs = split_runs(fa.t)
        dt = float(np.median(dt_all))
        scale = noise_scale(z) if channel_scale is None else np.asarray(channel_scale, float)
        if scale.shape != (6,) or np.any(~np.isfinite(scale)) or np.any(scale <= 0):
            raise CalibrationError(f"channel scale must be 6 positive numbers, got {scale}")
        return cls(fa.t, fa.x, fa.u, fa.env, z, runs, dt, scale, src)

    def __len__(self) -> int:
        return self.t.size

    def reference_row(self):
        """(x, u, w, env) medians: where each parameter set's rotor Jacobian is taken."""
        return (np.median(self.x, axis=0), np.median(self.u, axis=0), np.zeros(6),
                {k: float(np.median(v)) for k, v in self.env.items()})


@dataclass
class Windows:
    """idx (W, L) row indexes, score (W, L) which of them count, warmup (samples)."""

    idx: np.ndarray
    score: np.ndarray
    warmup: int

    @property
    def n_windows(self) -> int:
        return self.idx.shape[0]

    @property
    def n_scored(self) -> int:
        return int(self.score.sum())

    def subset(self, which) -> Windows:
        return Windows(self.idx[which], self.score[which], self.warmup)

    def residual_windows(self) -> np.ndarray:
        """(n_scored * 6,) the window of each element of `WindowedPredictor.residuals`'s
        vector (scored samples in window order, six channels each): the independent
        clusters of the calibration's sandwich covariance (`fit.uncertainty`)."""
        return np.repeat(np.nonzero(self.score)[0], 6)


def make_windows(data: FlightData, window_s: float = 2.0, warmup_s: float = 1.0) -> Windows:
    """Windows tiling every run's samples after its first `warmup_s` (see module doc).
    A run shorter than warmup + window is one shorter window (all windows are padded to
    the same length by repeating a window's last row, unscored)."""
    warm = max(int(round(warmup_s / data.dt)), 1)
    length = max(int(round(window_s / data.dt)), 1)
    total = warm + length
    idx, score = [], []
    for run in data.runs:
        a, b = run.start, run.stop
        if b - a <= warm:
            continue
        s = a + warm
        while s < b:
            start = s - warm
            rows = np.arange(start, start + total)
            sc = (rows >= s) & (rows < b)
            if rows[-1] >= b:  # last window: shift back inside the run where possible
                shift = min(rows[-1] - (b - 1), start - a)
                rows = rows - shift
                sc = (rows >= s) & (rows < b)
            rows = np.minimum(rows, b - 1)
            sc &= np.concatenate([[True], np.diff(rows) > 0])
            idx.append(rows)
            score.append(sc)
            s += length
    if not idx:
        raise CalibrationError(
            f"{data.source}: no run of the flight is longer than the {warmup_s} s warm-up")
    return Windows(np.array(idx), np.array(score), warm)


# the steady part of a misfit: blocks this long, longer than the wind's turbulence (its
# correlation time is < 1 s) and than a survey leg's manoeuvres, so what a block's mean
# holds is what the wind estimator would take for a steady wind (on the blade-element
# still-air flight the x offset reads 0.021-0.023 m/s^2 for blocks of 20 to 160 s)
OFFSET_BLOCK_S = 30.0


class WindowedPredictor:
    """Predicted measurement over windows of a flight for K parameter sets at once."""

    def __init__(self, model, data: FlightData, windows: Windows) -> None:
        self.model = model
        self.data = data
        self.windows = windows
        self.evaluations = 0  # parameter-set evaluations (for reports)

    def predict(self, param_sets: np.ndarray, wind=None):
        """param_sets (K, P) -> (z (K, W, L, 6), valid (K,) bool). Sets whose rotor
        dynamics cannot be linearised or whose prediction is not finite are invalid
        (their z is NaN)."""
        sets = np.atleast_2d(np.asarray(param_sets, dtype=float))
        z, valid = self._run(sets, wind)
        valid &= np.all(np.isfinite(z), axis=(1, 2, 3))
        z[~valid] = np.nan
        return z, valid

    # parameter sets per pass of `cost`: its memory stays this many sets' predictions
    # (the PSO swarm is hundreds of sets)
    COST_CHUNK = 16

    def cost(self, param_sets: np.ndarray, wind=None) -> np.ndarray:
        """(K,) RMS of the weighted residuals over the scored samples, inf for invalid
        sets; computed `COST_CHUNK` sets at a time, so memory does not grow with the
        swarm."""
        sets = np.atleast_2d(np.asarray(param_sets, dtype=float))
        win, data = self.windows, self.data
        zm = data.z[win.idx] / data.scale  # (W, L, 6)
        score = win.score[None, :, :, None]
        rms = np.empty(sets.shape[0])
        for lo in range(0, sets.shape[0], self.COST_CHUNK):
            z, valid = self._run(sets[lo:lo + self.COST_CHUNK], wind)
            with np.errstate(all="ignore"):
                e = (zm[None] - z / data.scale) * score
                ss = np.einsum("kwlc,kwlc->k", e, e)
                r = np.sqrt(ss / max(6 * win.n_scored, 1))
            rms[lo:lo + z.shape[0]] = np.where(valid & np.isfinite(r), r, np.inf)
        return rms

    def _run(self, sets: np.ndarray, wind) -> tuple[np.ndarray, np.ndarray]:
        """Propagate all windows of all sets: (z (K, W, L, 6), valid (K,) the mask of the
        linearisation). One compiled pass for an all-kernel model
        (`airwake.heli.measurement.windowed_measurements`), else stepped here."""
        with single_blas_thread():
            model, data, win = self.model, self.data, self.windows
            k = sets.shape[0]
            prop = HiddenPropagator(model, data.dt, sets, data.reference_row())
            z = None
            if wind is None or np.size(wind) == 6:
                e_t, p1_t, p2_t = prop.step_matrices()
                with np.errstate(all="ignore"):
                    z = windowed_measurements(
                        model, data.x, data.u, data.env, win.idx, sets, prop.h_ref,
                        prop.a_t, prop.a_inv_t, e_t, p1_t, p2_t,
                        wind=wind, newton=prop.QUASI_STEADY_ITERATIONS)
            if z is None:
                z = self._stepped(prop, sets, wind)
            self.evaluations += k
            return z, prop.valid.copy()

    def _stepped(self, prop, sets: np.ndarray, wind) -> np.ndarray:
        """The same propagation a step at a time in Python (a model with numpy stages)."""
        win = self.windows
        k = sets.shape[0]
        w_count, length = win.idx.shape
        z = np.empty((k, w_count, length, 6))
        rows_params = np.repeat(sets, w_count, axis=0)
        wind_row = np.zeros((1, 6)) if wind is None else np.atleast_2d(wind)
        h = np.repeat(prop.h_ref[:, None, :], w_count, 1)
        with np.errstate(all="ignore"):
            rows = self._rows(win.idx[:, 0], k, wind_row)
            h = prop.quasi_steady(h, rows, rows_params)
            g, _, z[:, :, 0] = prop.evaluate(h, rows, rows_params)
            g_prev = g
            for j in range(1, length):
                h_pred = prop.predict(h, g, g_prev)
                g_new, _, z[:, :, j] = prop.evaluate(
                    h_pred, self._rows(win.idx[:, j], k, wind_row), rows_params)
                h = prop.correct(h_pred, g, g_prev, g_new)
                g_prev, g = g, g_new
        return z

    def _rows(self, idx: np.ndarray, k: int, wind_row) -> RowBatch:
        d = self.data
        x = np.tile(d.x[idx], (k, 1))
        u = np.tile(d.u[idx], (k, 1))
        env = {n: np.tile(v[idx], k) for n, v in d.env.items()}
        return RowBatch(x, u, wind_row, env)

    def measured(self) -> np.ndarray:
        """(W, L, 6) measured channels at the windows' rows."""
        return self.data.z[self.windows.idx]

    def residuals(self, param_sets: np.ndarray, wind=None):
        """Weighted residuals (K, n_scored * 6) = (z - z_hat)/scale at scored samples,
        and the valid mask (K,)."""
        z, valid = self.predict(param_sets, wind)
        r = (self.measured()[None] - z) / self.data.scale
        return r[:, self.windows.score].reshape(z.shape[0], -1), valid

    def channel_rms(self, param_sets: np.ndarray) -> np.ndarray:
        """(K, 6) RMS of the unweighted residual per channel over scored samples."""
        return self.channel_stats(param_sets)[0]

    def channel_stats(self, param_sets: np.ndarray, block_s: float = OFFSET_BLOCK_S
                      ) -> tuple[np.ndarray, np.ndarray]:
        """(K, 6) RMS of the unweighted residual per channel over the scored samples, and
        (K, 6) the steady part of it: the flight cut into blocks of `block_s` seconds (by
        each window's start), the RMS over the blocks of each block's mean residual over
        its windows' scored samples — a body-fixed force or moment the model misses in
        a flight condition, a sensor's turn-on bias."""
        z, _ = self.predict(param_sets)
        e = self.measured()[None] - z  # (K, W, L, 6)
        score = self.windows.score
        rms = np.sqrt(np.mean(e[:, score] ** 2, axis=1))
        start = self.data.t[self.windows.idx[:, 0]]
        block = np.floor((start - start.min()) / block_s).astype(int)
        means = []
        for b in np.unique(block):
            sel = score & (block == b)[:, None]
            if sel.any():
                means.append(e[:, sel].mean(axis=1))  # (K, 6)
        offset = np.sqrt(np.mean(np.square(means), axis=0))
        return rms, offset
