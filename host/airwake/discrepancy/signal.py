"""Signal processing shared by every step: the analysis band, the analysis mask, the
data-only noise floor, spectra, coherence and correlations with honest confidence bands.

Arrays are (T,) or (T, C) over the flight's samples; `runs` are the contiguous sample
ranges (no time gaps, `Flight.runs`); filters run inside each run only.
"""

from __future__ import annotations

import numpy as np
from scipy import signal as sps

from airwake.discrepancy.settings import AnalysisSettings

MIN_RUN = 30  # runs shorter than this are left out of the analysis


def lowpass_sos(settings: AnalysisSettings, rate_hz: float):
    """Butterworth low-pass (second-order sections), or None when off / above Nyquist."""
    fc = settings.lowpass_hz
    if not fc or fc >= 0.45 * rate_hz:
        return None
    return sps.butter(settings.filter_order, fc, btype="low", fs=rate_hz, output="sos")


def band(x: np.ndarray, runs, settings: AnalysisSettings, rate_hz: float) -> np.ndarray:
    """The analysis band of x: zero-phase low-pass within each run (settings docstring)."""
    x = np.asarray(x, dtype=float)
    sos = lowpass_sos(settings, rate_hz)
    if sos is None:
        return x.copy()
    out = x.copy()
    for run in runs:
        n = run.stop - run.start
        if n < MIN_RUN:
            continue
        pad = min(3 * (2 * len(sos) + 1), n - 1)
        out[run] = sps.sosfiltfilt(sos, x[run], axis=0, padlen=pad)
    return out


def analysis_mask(t: np.ndarray, runs, settings: AnalysisSettings) -> np.ndarray:
    """True for samples every statistic uses: not in the first skip_start_s of a run, not
    within edge_s of a run's end, not in runs shorter than MIN_RUN."""
    mask = np.zeros(t.size, dtype=bool)
    for run in runs:
        if run.stop - run.start < MIN_RUN:
            continue
        tr = t[run]
        ok = (tr >= tr[0] + settings.skip_start_s + settings.edge_s) & (
            tr <= tr[-1] - settings.edge_s)
        mask[run] = ok
    return mask


def filter_gain_integral(settings: AnalysisSettings, rate_hz: float) -> float:
    """Equivalent noise bandwidth (Hz) of the analysis band: integral of |H(f)|^2 over
    0..Nyquist for the forward-backward filter (|H_ff|^2 = |H_butter|^4)."""
    sos = lowpass_sos(settings, rate_hz)
    nyq = rate_hz / 2.0
    if sos is None:
        return nyq
    f, h = sps.sosfreqz(sos, worN=8192, fs=rate_hz)
    return float(np.trapezoid(np.abs(h) ** 4, f))


def noise_floor(residual: np.ndarray, runs, settings: AnalysisSettings, rate_hz: float
                ) -> dict:
    """Data-only noise estimate per channel (residual (T, C), unfiltered).

    Method: Welch power spectral density of the residual within each run; the noise
    density is the *median* of the PSD over the band just above the analysis band,
    [f_c, min(2.5 f_c, 0.9 Nyquist)] (the median ignores narrow rotor-vibration lines);
    the noise is taken white at that density, so its variance in the analysis band is
    density x the band's equivalent noise bandwidth and over the full band density x
    Nyquist. Assumes the model error above f_c is negligible and the noise spectrum flat
    across f_c; filtered sensor outputs (e.g. the Savitzky-Golay angular accelerations)
    violate the second in part: the estimate is then an over- or under-estimate by the
    filter's shape — compare with `rms_highband` ratios over flights.
    Returns {"density": (C,), "band_rms": (C,), "full_rms": (C,), "f_lo_hz", "f_hi_hz"}.
    """
    r = np.atleast_2d(np.asarray(residual, dtype=float).T).T
    nyq = rate_hz / 2.0
    fc = settings.lowpass_hz if settings.lowpass_hz and settings.lowpass_hz < 0.45 * rate_hz \
        else 0.3 * nyq
    f_lo, f_hi = fc, min(2.5 * fc, 0.9 * nyq)
    if f_hi - f_lo < 2.0:
        f_lo, f_hi = 0.5 * nyq, 0.9 * nyq
    psds, weights = [], []
    for run in runs:
        n = run.stop - run.start
        if n < 64:
            continue
        nper = int(min(256, 2 ** np.floor(np.log2(n / 2))))
        f, p = sps.welch(r[run], fs=rate_hz, nperseg=nper, axis=0, detrend="linear")
        psds.append((f, p))
        weights.append(n)
    if not psds:
        c = r.shape[1]
        return {"density": np.full(c, np.nan), "band_rms": np.full(c, np.nan),
                "full_rms": np.full(c, np.nan), "f_lo_hz": f_lo, "f_hi_hz": f_hi}
    dens = []
    for f, p in psds:
        sel = (f >= f_lo) & (f <= f_hi)
        if sel.sum() < 3:
            sel = f >= 0.5 * nyq
        dens.append(np.median(p[sel], axis=0))
    w = np.asarray(weights, float)
    density = np.sum(np.asarray(dens) * w[:, None], 0) / w.sum()
    enbw = filter_gain_integral(settings, rate_hz)
    return {"density": density, "band_rms": np.sqrt(density * enbw),
            "full_rms": np.sqrt(density * nyq), "f_lo_hz": f_lo, "f_hi_hz": f_hi}


def welch(x: np.ndarray, runs, rate_hz: float, nperseg: int = 512):
    """Welch PSD averaged over runs (weighted by length): f (F,), psd (F, C)."""
    x = np.atleast_2d(np.asarray(x, dtype=float).T).T
    acc, total, f_out = None, 0, None
    for run in runs:
        n = run.stop - run.start
        if n < 64:
            continue
        nper = int(min(nperseg, 2 ** np.floor(np.log2(n / 2))))
        if f_out is not None and nper != (f_out.size - 1) * 2:
            continue
        f, p = sps.welch(x[run], fs=rate_hz, nperseg=nper, axis=0)
        f_out = f if f_out is None else f_out
        acc = p * n if acc is None else acc + p * n
        total += n
    if acc is None:
        return np.zeros(1), np.zeros((1, x.shape[1]))
    return f_out, acc / total


def coherence(x: np.ndarray, y: np.ndarray, runs, rate_hz: float, nperseg: int = 512):
    """Magnitude-squared coherence between x (T,) and each column of y (T, C)."""
    y = np.atleast_2d(np.asarray(y, dtype=float).T).T
    pxy_acc = pxx_acc = pyy_acc = None
    f_out = None
    for run in runs:
        n = run.stop - run.start
        if n < 64:
            continue
        nper = int(min(nperseg, 2 ** np.floor(np.log2(n / 2))))
        if f_out is not None and nper != (f_out.size - 1) * 2:
            continue
        f, pxx = sps.welch(x[run], fs=rate_hz, nperseg=nper)
        _, pyy = sps.welch(y[run], fs=rate_hz, nperseg=nper, axis=0)
        _, pxy = sps.csd(x[run][:, None], y[run], fs=rate_hz, nperseg=nper, axis=0)
        f_out = f if f_out is None else f_out
        pxx_acc = pxx * n if pxx_acc is None else pxx_acc + pxx * n
        pyy_acc = pyy * n if pyy_acc is None else pyy_acc + pyy * n
        pxy_acc = pxy * n if pxy_acc is None else pxy_acc + pxy * n
    if f_out is None:
        return np.zeros(1), np.zeros((1, y.shape[1]))
    coh = np.abs(pxy_acc) ** 2 / np.maximum(pxx_acc[:, None] * pyy_acc, 1e-300)
    return f_out, np.clip(coh, 0.0, 1.0)


def _centered(x, mask):
    v = np.where(mask, x - x[mask].mean(), 0.0)
    return v


def correlation(a: np.ndarray, b: np.ndarray, mask: np.ndarray, max_lag: int):
    """Normalised cross-correlation rho_ab(k) = E[a(t) b(t - k)] / (sd_a sd_b) for
    k = -max_lag..max_lag over masked samples (pairs where both ends are in the mask).
    Returns lags (2L+1,), rho (2L+1,)."""
    a0 = _centered(np.asarray(a, float), mask)
    b0 = _centered(np.asarray(b, float), mask)
    n = int(mask.sum())
    sa = np.sqrt(np.sum(a0 * a0) / n)
    sb = np.sqrt(np.sum(b0 * b0) / n)
    lags = np.arange(-max_lag, max_lag + 1)
    if sa == 0 or sb == 0:
        return lags, np.zeros(lags.size)
    full = sps.correlate(a0, b0, mode="full", method="fft")  # index T-1 is lag 0
    mid = a0.size - 1
    rho = full[mid + lags] / (n * sa * sb)
    return lags, rho


def bartlett_band(rho_a: np.ndarray, rho_b: np.ndarray, n_eff_samples: int,
                  z: float = 2.576) -> float:
    """99 % band (z = 2.576) of a cross-correlation estimate between two series with
    autocorrelations rho_a, rho_b (lags 0..L, one-sided) under the null of no
    cross-correlation (Bartlett 1946): var = (1/N) sum_k rho_a(k) rho_b(k) over all k.
    With white series this is the familiar z/sqrt(N) of MATLAB's `resid`; with low-pass
    filtered residuals it is wider — the honest band."""
    s = 1.0 + 2.0 * float(np.sum(rho_a[1:] * rho_b[1:]))
    return z * np.sqrt(max(s, 1.0 / max(n_eff_samples, 1)) / max(n_eff_samples, 1))


def autocorr_one_sided(x: np.ndarray, mask: np.ndarray, max_lag: int) -> np.ndarray:
    lags, rho = correlation(x, x, mask, max_lag)
    return rho[max_lag:]


def effective_samples(x: np.ndarray, mask: np.ndarray, max_lag: int = 300) -> float:
    """N_eff = N / (1 + 2 sum_k rho(k)) with the sum truncated at the first negative
    autocorrelation (initial positive sequence, Geyer)."""
    n = int(mask.sum())
    rho = autocorr_one_sided(x, mask, min(max_lag, max(n // 4, 1)))
    s = 0.0
    for r in rho[1:]:
        if r <= 0:
            break
        s += r
    return n / (1.0 + 2.0 * s)


def time_blocks(mask: np.ndarray, n_blocks: int) -> list[np.ndarray]:
    """Indexes of the masked samples split into n_blocks contiguous blocks (equal counts)."""
    idx = np.flatnonzero(mask)
    return [b for b in np.array_split(idx, n_blocks) if b.size]
