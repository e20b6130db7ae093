"""Step 1 — compare the model with a flight.

One-step-ahead (equation error): the model's six measurement channels predicted from the
flight's measured states and inputs (`airwake.heli.measurement.predict_measurements`; the
rotor's hidden states are reconstructed along the flight). Per channel, in the analysis
band and over the analysis mask (`settings.py`): RMS, NRMSE = RMS / std(measured), R^2,
the data-only noise floor (`signal.noise_floor`) and RMS / noise.

Free simulation: the model integrated open-loop (RK4) from the measured state (hidden
states from the reconstruction) with the measured inputs over short windows; RMS error
of the rates p, q, r, attitude and body velocity over the windows. The hover is open-loop
unstable (doubling in ~1.5 s), so windows are short and the numbers grow with window
length: compare them between models on the same flight and window, not with the
equation error.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from airwake.discrepancy import signal
from airwake.discrepancy.data import CHANNEL_LABELS, Flight, load_flight
from airwake.discrepancy.errors import DiscrepancyError
from airwake.discrepancy.settings import AnalysisSettings
from airwake.heli.context import MEAS_CHANNELS

FREE_SIM_VARIABLES = ("p_rad_s", "q_rad_s", "r_rad_s", "roll_rad", "pitch_rad",
                      "vel_u_m_s", "vel_v_m_s", "vel_w_m_s")


def predict(model, flight: Flight, params=None, hidden=None, return_hidden=False, wind=None):
    """Predicted channels (T, 6) of `model` on `flight` (or (K, T, 6) for (K, P) params),
    in still air or with `wind` (T, 6) the eq 5.3 wind per sample as an input.
    Model failures become DiscrepancyError (a plugin that raises, non-finite output)."""
    from airwake.heli.measurement import predict_measurements

    try:
        out = predict_measurements(model, flight.df, wind=wind, params=params, hidden=hidden,
                                   return_hidden=return_hidden)
    except DiscrepancyError:
        raise
    except Exception as exc:  # noqa: BLE001 — user effects/plugins: one clear line
        raise DiscrepancyError(
            f"model {model.effect_names} failed on {flight.name}: "
            f"{type(exc).__name__}: {exc}") from None
    z = out[0] if return_hidden else out
    if not np.all(np.isfinite(z)):
        bad = np.argwhere(~np.isfinite(z))[0]
        raise DiscrepancyError(
            f"model {model.effect_names} predicts a non-finite {MEAS_CHANNELS[bad[-1]]} on "
            f"{flight.name} (sample {bad[-2] if z.ndim > 1 else bad[0]}): check the model "
            "parameters and the flight's units")
    return out


@dataclass
class Analysis:
    """A model evaluated on a flight, with everything the later steps reuse."""

    flight: Flight
    model: object
    settings: AnalysisSettings
    zhat: np.ndarray  # (T, 6) predicted
    residual: np.ndarray  # (T, 6) measured - predicted
    residual_band: np.ndarray  # (T, 6) in the analysis band
    measured_band: np.ndarray  # (T, 6)
    mask: np.ndarray  # (T,) bool
    noise: dict  # signal.noise_floor
    hidden: object = None
    free_sim: dict = field(default_factory=dict)
    wind: np.ndarray | None = None  # (T, 6) known wind given as the model's input

    def band(self, x: np.ndarray) -> np.ndarray:
        return signal.band(x, self.flight.runs, self.settings, self.flight.rate_hz)

    def regressors(self, sens: np.ndarray) -> np.ndarray:
        """(K, T, 6) sensitivities -> (n, 6, K) in the analysis band over the mask."""
        k = sens.shape[0]
        flat = np.moveaxis(sens, 0, -1).reshape(sens.shape[1], -1)  # (T, 6K)
        return self.band(flat).reshape(sens.shape[1], 6, k)[self.mask]

    @property
    def weights(self) -> np.ndarray:
        """(6,) channel weights 1/noise_band^2 (whitening: every channel in units of its
        own noise), with a floor so a near-noise-free channel does not dominate."""
        nb = np.asarray(self.noise["band_rms"], float)
        floor = np.nanmedian(nb[:3]) * 0.05, np.nanmedian(nb[3:]) * 0.05
        nb = np.where(np.isfinite(nb), nb, 1.0)
        nb = np.maximum(nb, np.r_[[floor[0]] * 3, [floor[1]] * 3])
        return 1.0 / nb**2

    def metrics(self) -> dict:
        return channel_metrics(self.residual_band, self.measured_band, self.residual,
                               self.mask, self.noise)


def channel_metrics(res_band, meas_band, res_raw, mask, noise) -> dict:
    """{channel: {rms, rms_raw, nrmse, r2, noise_band, noise_full, rms_over_noise}}."""
    out = {}
    for j, c in enumerate(MEAS_CHANNELS):
        e = res_band[mask, j]
        y = meas_band[mask, j]
        sse = float(np.sum(e * e))
        sst = float(np.sum((y - y.mean()) ** 2))
        rms = float(np.sqrt(np.mean(e * e)))
        nb = float(noise["band_rms"][j])
        out[c] = {
            "label": CHANNEL_LABELS[c],
            "rms": rms,
            "rms_raw": float(np.sqrt(np.mean(res_raw[mask, j] ** 2))),
            "mean": float(e.mean()),
            "nrmse": rms / float(y.std()) if y.std() > 0 else float("inf"),
            "r2": 1.0 - sse / sst if sst > 0 else float("nan"),
            "noise_band": nb,
            "noise_full": float(noise["full_rms"][j]),
            "rms_over_noise": rms / nb if nb > 0 else float("inf"),
        }
    return out


def analyse(model, flight, settings: AnalysisSettings | None = None, *,
            free_sim: bool = False, progress=None, wind=None) -> Analysis:
    """Evaluate `model` on `flight` (path / table / Flight): residuals, band, mask, noise.
    `wind`: None (still air) or (T, 6) the eq 5.3 wind per sample (e.g. a wind estimate,
    `airwake.discrepancy.wind.wind_input`) given to the model as a known input."""
    settings = settings or AnalysisSettings()
    flight = load_flight(flight, settings)
    check_model(model)
    if wind is not None:
        wind = np.asarray(wind, dtype=float)
        if wind.shape != (len(flight), 6) or not np.all(np.isfinite(wind)):
            raise DiscrepancyError(f"wind for {flight.name}: expected {len(flight)} finite "
                                   f"rows of 6 components, got shape {wind.shape}")
    zhat, hidden = predict(model, flight, return_hidden=True, wind=wind)
    res = flight.z - zhat
    runs, fs = flight.runs, flight.rate_hz
    mask = signal.analysis_mask(flight.t, runs, settings)
    if mask.sum() < 50:
        raise DiscrepancyError(f"{flight.name}: fewer than 50 samples remain after leaving "
                               f"out start-up transients and gaps")
    noise = signal.noise_floor(res, runs, settings, fs)
    an = Analysis(flight, model, settings, zhat, res, signal.band(res, runs, settings, fs),
                  signal.band(flight.z, runs, settings, fs), mask, noise, hidden, wind=wind)
    if free_sim and settings.free_sim_windows > 0:
        an.free_sim = free_simulation(an, progress=progress)
    return an


def check_model(model) -> None:
    from airwake.heli.model import HeliModel

    if not isinstance(model, HeliModel):
        raise DiscrepancyError(f"expected a HeliModel, got {type(model).__name__}")
    if "rigid_body" not in model:
        raise DiscrepancyError("the model has no rigid_body effect: it predicts nothing")


# -- free simulation ----------------------------------------------------------------------
def window_starts(an: Analysis, window_n: int, count: int) -> np.ndarray:
    """Start indexes of up to `count` windows of window_n samples, evenly spread, each
    entirely inside the analysis mask and one run."""
    ok = np.zeros(an.flight.t.size, dtype=bool)
    for run in an.flight.runs:
        m = an.mask[run]
        # a start is valid if the next window_n samples are all masked
        c = np.concatenate([[0], np.cumsum(m)])
        n = m.size
        if n < window_n:
            continue
        full = (c[window_n:] - c[:-window_n]) == window_n
        ok[run.start:run.start + full.size] = full
    cand = np.flatnonzero(ok)
    if cand.size == 0:
        return cand
    # greedy evenly spaced non-overlapping picks
    picks = []
    targets = np.linspace(cand[0], cand[-1], max(count, 1))
    last_end = -1
    for tgt in targets:
        i = cand[np.searchsorted(cand, tgt).clip(0, cand.size - 1)]
        if i <= last_end:
            later = cand[cand > last_end]
            if later.size == 0:
                break
            i = later[0]
        picks.append(int(i))
        last_end = i + window_n - 1
    return np.array(picks[:count], dtype=int)


def free_simulation(an: Analysis, model=None, progress=None) -> dict:
    """Open-loop RK4 from the measured state over windows (see the module docstring).
    Returns {"window_s", "windows": starts (W,), "t": (W, n), variables: {name: {"sim":
    (W, n), "meas": (W, n), "rms": float}}}."""
    from airwake.heli.integrate import rk4_step

    model = model or an.model
    fl, st = an.flight, an.settings
    n_win = max(int(round(st.free_sim_window_s * fl.rate_hz)), 2)
    starts = window_starts(an, n_win, st.free_sim_windows)
    if starts.size == 0:
        return {}
    # initial states: measured body states + reconstructed hidden states
    s_dim = model.n_states
    x_all = np.zeros((fl.t.size, s_dim))
    for state, column in model.measured_states.items():
        if column in fl.df.columns:
            x_all[:, model.state_names.index(state)] = fl.column(column)
    hid = [model.state_names.index(s) for s in model.hidden_state_names]
    if hid and an.hidden is not None and model is an.model:
        x_all[:, hid] = an.hidden.h
    elif hid:
        _, h = predict(model, fl, return_hidden=True, wind=an.wind)
        x_all[:, hid] = h.h
    from airwake.heli.model import INPUT_NAMES

    u_all = np.column_stack([fl.column(c) for c in INPUT_NAMES])
    env_all = {c: fl.column(c) for c in ("height_agl_m", "rotor_speed_rad_s") if fl.has(c)}
    idx = starts[:, None] + np.arange(n_win)[None]  # (W, n)
    x = x_all[starts].copy()
    sims = np.empty((starts.size, n_win, s_dim))
    sims[:, 0] = x
    sub = st.free_sim_substeps
    for k in range(n_win - 1):
        i0, i1 = idx[:, k], idx[:, k + 1]
        dt = (fl.t[i1] - fl.t[i0]) / sub
        env = {c: v[i0] for c, v in env_all.items()}
        for j in range(sub):
            a = (j + 0.5) / sub  # inputs at the sub-step's midpoint (linear between samples)
            u = (1 - a) * u_all[i0] + a * u_all[i1]
            w = None if an.wind is None else an.wind[i0]
            x = rk4_step(model, x, u, float(dt[0]), w, env)
        sims[:, k + 1] = x
        if not np.all(np.isfinite(x)):
            x = np.nan_to_num(x)
        if progress is not None:
            progress.update(k + 1)
    out = {"window_s": n_win / fl.rate_hz, "windows": starts, "t": fl.t[idx] - fl.t[starts][:,
                                                                                    None],
           "variables": {}}
    for var in FREE_SIM_VARIABLES:
        if var not in fl.df.columns:
            continue
        si = model.state_index(var)
        sim = sims[:, :, si]
        meas = fl.column(var)[idx]
        err = sim - meas
        out["variables"][var] = {"sim": sim, "meas": meas,
                                 "rms": float(np.sqrt(np.nanmean(err**2))),
                                 "end_rms": float(np.sqrt(np.nanmean(err[:, -1] ** 2)))}
    return out


def summary(an: Analysis) -> dict:
    """JSON-ready numbers of a comparison."""
    m = an.metrics()
    fl = an.flight
    out = {
        "flight": fl.name,
        "model_effects": list(an.model.effect_names),
        "samples": int(fl.t.size),
        "samples_analysed": int(an.mask.sum()),
        "duration_s": float(fl.t[-1] - fl.t[0]),
        "rate_hz": fl.rate_hz,
        "settings": an.settings.as_dict(),
        "noise_method": "median Welch PSD of the residual in "
                        f"[{an.noise['f_lo_hz']:.1f}, {an.noise['f_hi_hz']:.1f}] Hz, white",
        "channels": m,
        "overall": overall_score(an),
    }
    if an.free_sim:
        out["free_simulation"] = {
            "window_s": an.free_sim["window_s"],
            "windows": len(an.free_sim["windows"]),
            "rms": {v: d["rms"] for v, d in an.free_sim["variables"].items()},
            "end_rms": {v: d["end_rms"] for v, d in an.free_sim["variables"].items()},
        }
    return out


def overall_score(an: Analysis) -> dict:
    """Noise-weighted overall numbers: mean over channels of (RMS / noise)^2 and its root."""
    m = an.metrics()
    ratios = np.array([m[c]["rms_over_noise"] for c in MEAS_CHANNELS])
    return {"rms_over_noise": float(np.sqrt(np.mean(ratios**2)))}
