"""Step 2 — where the model fails: residual breakdowns of an `Analysis`.

- **regimes**: residual mean and RMS per channel in bins of height above ground / rotor
  radius, horizontal airspeed (|(u, v)|, still air), collective, rotor speed, roll,
  pitch and the three body rates (quantile bins; height in fixed multiples of R), with
  sample counts;
- **worst windows**: the 2-s windows with the largest noise-weighted residual energy,
  their dominant channel and flight regime;
- **spectra**: residual PSD per channel (Welch, unfiltered: shows the analysis band's
  edge, the noise floor and rotor-vibration lines), and the magnitude-squared coherence
  of each channel's residual with each input;
- **correlation tests** (MATLAB `resid` style) on the in-band residual over the mask:
  autocorrelation against what band-limited white noise through the same filter gives,
  and cross-correlation with each input at lags -L..L, with 99 % bands from Bartlett's
  formula (the series are autocorrelated: the textbook 2.58/sqrt(N) would flag almost
  everything);
- **higher-order correlation tests** (Billings & Voon 1986, as in SysIdentPy) for
  unmodelled nonlinearity: phi_{u^2' e}(k) = E[(u^2 - mean u^2)(t) e(t-k)], phi_{u^2'
  e^2}(k) = E[(u^2 - mean)(t) (e^2 - mean)(t-k)] and phi_{e (e u)}(k) = E[e(t) e(t-1-k)
  u(t-1-k)], normalised, with the same kind of bands; u are the inputs.
"""

from __future__ import annotations

import numpy as np

from airwake.discrepancy import signal
from airwake.discrepancy.data import CHANNEL_LABELS
from airwake.heli.context import MEAS_CHANNELS
from airwake.heli.model import INPUT_NAMES

INPUT_LABELS = {"delta_col_rad": "col", "delta_lat_rad": "lat", "delta_lon_rad": "lon",
                "delta_ped_rad": "ped"}


def regime_variables(an) -> dict:
    """{name: (values (T,), unit)} of the regime variables the flight has."""
    fl = an.flight
    out = {}
    if fl.has("height_agl_m"):
        radius = float(an.model["main_rotor"].parameters()["radius_m"])
        out["height_over_R"] = (fl.column("height_agl_m") / radius, "z/R")
    out["airspeed_m_s"] = (np.hypot(fl.column("vel_u_m_s"), fl.column("vel_v_m_s")), "m/s")
    out["collective_rad"] = (fl.column("delta_col_rad"), "rad")
    if fl.has("rotor_speed_rad_s") and np.ptp(fl.column("rotor_speed_rad_s")) > 1e-6:
        out["rotor_speed_rad_s"] = (fl.column("rotor_speed_rad_s"), "rad/s")
    out["roll_rad"] = (fl.column("roll_rad"), "rad")
    out["pitch_rad"] = (fl.column("pitch_rad"), "rad")
    for c in ("p_rad_s", "q_rad_s", "r_rad_s"):
        out[c] = (fl.column(c), "rad/s")
    return out


def _edges(name, values, mask, n_bins):
    v = values[mask & np.isfinite(values)]
    if name == "height_over_R":
        e = np.array([0.0, 1.0, 1.5, 2.0, 3.0, 5.0, np.inf])
        return e
    if v.size == 0 or np.ptp(v) == 0:
        return None
    e = np.unique(np.quantile(v, np.linspace(0, 1, n_bins + 1)))
    if e.size < 3:
        return None
    e[0], e[-1] = -np.inf, np.inf
    return e


def regimes(an, n_bins: int = 6) -> dict:
    """{variable: {"unit", "bins": [{"lo", "hi", "count", "mean": {ch}, "rms": {ch}}]}}."""
    out = {}
    r = an.residual_band
    for name, (values, unit) in regime_variables(an).items():
        edges = _edges(name, values, an.mask, n_bins)
        if edges is None:
            continue
        bins = []
        for lo, hi in zip(edges[:-1], edges[1:], strict=True):
            sel = an.mask & (values >= lo) & (values < hi)
            n = int(sel.sum())
            if n == 0:
                continue
            bins.append({
                "lo": float(lo), "hi": float(hi), "count": n,
                "mean": {c: float(r[sel, j].mean()) for j, c in enumerate(MEAS_CHANNELS)},
                "rms": {c: float(np.sqrt(np.mean(r[sel, j] ** 2)))
                        for j, c in enumerate(MEAS_CHANNELS)},
            })
        out[name] = {"unit": unit, "bins": bins}
    return out


def worst_windows(an, window_s: float = 2.0, count: int = 5) -> list[dict]:
    """The `count` windows with the largest noise-weighted in-band residual energy."""
    fl = an.flight
    n = max(int(round(window_s * fl.rate_hz)), 2)
    e = (an.residual_band**2) * an.weights[None]
    e = np.where(an.mask[:, None], e, 0.0)
    wins = []
    variables = regime_variables(an)
    for run in fl.runs:
        for s in range(run.start, run.stop - n + 1, n):
            sel = slice(s, s + n)
            m = an.mask[sel]
            if m.sum() < n // 2:
                continue
            energy = e[sel].sum(0) / m.sum()
            wins.append((float(energy.sum()), s, energy))
    wins.sort(key=lambda w: -w[0])
    out = []
    for score, s, energy in wins[:count]:
        sel = slice(s, s + n)
        m = an.mask[sel]
        j = int(np.argmax(energy))
        out.append({
            "t_start_s": float(fl.t[s]), "t_end_s": float(fl.t[s + n - 1]),
            "score": score / 6.0,  # mean (residual/noise)^2 over channels
            "dominant_channel": MEAS_CHANNELS[j],
            "rms": {c: float(np.sqrt(np.mean(an.residual_band[sel, k][m] ** 2)))
                    for k, c in enumerate(MEAS_CHANNELS)},
            "regime": {k: float(np.nanmean(v[sel][m])) for k, (v, _) in variables.items()},
        })
    return out


def spectra(an, nperseg: int = 512) -> dict:
    fl = an.flight
    f, p_res = signal.welch(an.residual, fl.runs, fl.rate_hz, nperseg)
    _, p_meas = signal.welch(fl.z, fl.runs, fl.rate_hz, nperseg)
    u = np.column_stack([fl.column(c) for c in INPUT_NAMES])
    coh = np.zeros((f.size, 6, 4))
    for k in range(4):
        fc, c = signal.coherence(u[:, k], an.residual, fl.runs, fl.rate_hz, nperseg)
        if fc.size == f.size:
            coh[:, :, k] = c
    return {"f_hz": f, "residual_psd": p_res, "measured_psd": p_meas, "coherence": coh}


def _filter_autocorr(an, max_lag: int) -> np.ndarray:
    """Autocorrelation rho_h(0..L) of band-limited white noise (the analysis filter's)."""
    n = max(8 * max_lag, 4096)
    imp = np.zeros(n)
    imp[n // 2] = 1.0
    h = signal.band(imp, [slice(0, n)], an.settings, an.flight.rate_hz)
    full = np.correlate(h, h, mode="full")
    mid = full.size // 2
    rho = full[mid: mid + max_lag + 1]
    return rho / rho[0]


def correlation_tests(an, max_lag_s: float = 1.0) -> dict:
    """resid-style and Billings tests (module docstring); arrays + verdicts."""
    fl = an.flight
    mask = an.mask
    n = int(mask.sum())
    lag = max(int(round(max_lag_s * fl.rate_hz)), 5)
    rho_h = _filter_autocorr(an, 2 * lag)
    var_h = float(np.sum(rho_h**2) * 2 - 1)  # sum over all lags of rho_h^2
    u = an.band(np.column_stack([fl.column(c) for c in INPUT_NAMES]))
    out = {"max_lag": lag, "rate_hz": fl.rate_hz, "auto": {}, "cross": {}, "billings": {}}
    band_auto = 2.576 * np.sqrt(var_h / n)
    for j, c in enumerate(MEAS_CHANNELS):
        e = an.residual_band[:, j]
        rho = signal.autocorr_one_sided(e, mask, lag)
        dev = rho - rho_h[: lag + 1]
        out["auto"][c] = {"rho": rho, "white_band": rho_h[: lag + 1], "band": band_auto,
                          "outside": float(np.mean(np.abs(dev[1:]) > band_auto))}
        for k, inp in enumerate(INPUT_NAMES):
            lags, rxy = signal.correlation(e, u[:, k], mask, lag)
            rho_u = signal.autocorr_one_sided(u[:, k], mask, 2 * lag)
            band = signal.bartlett_band(rho_h[: 2 * lag + 1], rho_u, n)
            out["cross"][f"{c}|{inp}"] = {"lags": lags, "rho": rxy, "band": band,
                                          "outside": float(np.mean(np.abs(rxy) > band)),
                                          "peak": float(np.max(np.abs(rxy)))}
        out["billings"][c] = _billings(e, u, mask, lag, rho_h, n)
    return out


def _billings(e, u, mask, lag, rho_h, n) -> dict:
    """Higher-order correlation tests for one residual channel against every input."""
    res = {}
    e0 = np.where(mask, e - e[mask].mean(), 0.0)
    e2 = np.where(mask, e0**2 - np.mean(e0[mask] ** 2), 0.0)
    for k, inp in enumerate(INPUT_NAMES):
        uk = np.where(mask, u[:, k] - u[mask, k].mean(), 0.0)
        u2 = np.where(mask, uk**2 - np.mean(uk[mask] ** 2), 0.0)
        tests = {}
        for name, a, b in (("u2'e", u2, e0), ("u2'e2", u2, e2)):
            lags, rho = signal.correlation(a, b, mask, lag)
            ra = signal.autocorr_one_sided(a, mask, 2 * lag)
            rb = signal.autocorr_one_sided(b, mask, 2 * lag)
            band = signal.bartlett_band(ra, rb, n)
            sel = lags >= 0
            tests[name] = {"lags": lags[sel], "rho": rho[sel], "band": band,
                           "outside": float(np.mean(np.abs(rho[sel]) > band))}
        # phi_e(eu)(k) = E[e(t) e(t-1-k) u(t-1-k)]
        eu = e0 * uk
        lags, rho = signal.correlation(e0, eu, mask, lag + 1)
        ra = signal.autocorr_one_sided(e0, mask, 2 * lag)
        rb = signal.autocorr_one_sided(eu, mask, 2 * lag)
        band = signal.bartlett_band(ra, rb, n)
        sel = lags >= 1
        tests["e(eu)"] = {"lags": lags[sel] - 1, "rho": rho[sel], "band": band,
                          "outside": float(np.mean(np.abs(rho[sel]) > band))}
        res[inp] = tests
    return res


def breakdown(an, *, n_bins: int = 6, worst: int = 5, tests: bool = True) -> dict:
    """Everything above for one analysis (arrays kept for the report's figures)."""
    out = {"regimes": regimes(an, n_bins), "worst_windows": worst_windows(an, count=worst),
           "spectra": spectra(an)}
    if tests:
        out["tests"] = correlation_tests(an)
    return out


def summary(bd: dict) -> dict:
    """JSON-ready digest: regimes, worst windows, and the tests' flagged pairs."""
    out = {"regimes": bd["regimes"], "worst_windows": bd["worst_windows"]}
    tests = bd.get("tests")
    if tests:
        out["autocorrelation_outside_band"] = {
            CHANNEL_LABELS[c]: v["outside"] for c, v in tests["auto"].items()}
        flagged = []
        for key, v in tests["cross"].items():
            c, inp = key.split("|")
            if v["outside"] > 0.05:
                flagged.append({"channel": CHANNEL_LABELS[c], "input": INPUT_LABELS[inp],
                                "peak": v["peak"], "band": v["band"],
                                "outside": v["outside"]})
        out["cross_correlation_flags"] = flagged
        nonlin = []
        for c, per in tests["billings"].items():
            for inp, t in per.items():
                for name, d in t.items():
                    if d["outside"] > 0.05:
                        nonlin.append({"channel": CHANNEL_LABELS[c], "input": INPUT_LABELS[inp],
                                       "test": name, "outside": d["outside"]})
        out["higher_order_flags"] = nonlin
    return out
