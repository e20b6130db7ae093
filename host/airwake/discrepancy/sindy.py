"""A named, sparse regression of the residual on physical-variable terms (SINDy style),
so an effect outside the catalogue still shows up as evidence like
"rdot residual ∝ +0.31·V² − 0.05·ped·V".

Library (every term named, built from measured columns only): the inputs and their rates,
body velocities and rates, horizontal airspeed V (still-air assumption: V = |(u, v)|),
the rotor-speed deviation dΩ = Ω_meas − median Ω, the ground-image term (R/4z)² (height
floored at R/2), gravity components, and all pairwise products of the physical variables
(squares included); the measured angular accelerations only for the accelerometer channels
(for an angular channel they would correlate with its own measurement noise). Terms are
filtered to the analysis band like the residual and standardised (zero mean, unit
variance), so coefficients compare.

Fit per channel (residual standardised): sequentially thresholded least squares (STLSQ,
as PySINDy: ridge solve, drop |coef| < threshold, refit, repeat) inside *stability
selection*: the fit is repeated on bootstrap resamples of contiguous time blocks (the
residual is autocorrelated, so single samples are not independent draws); terms chosen in
>= `stable_fraction` of the resamples are kept, refitted by least squares, and reported
with their physical-unit coefficient, selection frequency, share of the residual they
explain (drop-one) and the cross-validated R² of the sparse model. Known failure modes
(PySINDy): collinear terms trade coefficients — each kept term lists the library terms
it is nearly collinear with (|corr| > 0.95: "or equally"), and the variance inflation
factors of the kept set are reported; pure noise produces unstable, small terms — a
channel whose residual is already near its noise floor is reported as "no structure".
"""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.data import CHANNEL_LABELS
from airwake.heli.context import MEAS_CHANNELS

MAX_ROWS = 12000


def _rates(t, x):
    from airwake.record.differentiate import smooth_derivative

    return smooth_derivative(t, x)


def build_library(an) -> tuple[np.ndarray, list[dict]]:
    """(T, M) terms and their descriptions [{"name", "vars", "acc_only"}]."""
    fl = an.flight
    t = fl.t
    base: dict[str, np.ndarray] = {}
    for short, col in (("col", "delta_col_rad"), ("lat", "delta_lat_rad"),
                       ("lon", "delta_lon_rad"), ("ped", "delta_ped_rad")):
        base[short] = fl.column(col)
    phys = {
        "u": fl.column("vel_u_m_s"), "v": fl.column("vel_v_m_s"), "w": fl.column("vel_w_m_s"),
        "p": fl.column("p_rad_s"), "q": fl.column("q_rad_s"), "r": fl.column("r_rad_s"),
    }
    phys["V"] = np.hypot(phys["u"], phys["v"])
    if fl.has("rotor_speed_rad_s"):
        om = fl.column("rotor_speed_rad_s")
        if np.ptp(om) > 1e-6:
            phys["dΩ"] = om - np.median(om)
    if fl.has("height_agl_m"):
        radius = float(an.model["main_rotor"].parameters()["radius_m"])
        z = fl.column("height_agl_m")
        z = np.where(np.isfinite(z), z, 1e9)
        gz = (radius / (4.0 * np.maximum(z, 0.5 * radius))) ** 2
        if np.ptp(gz) > 1e-4:
            phys["(R/4z)²"] = gz
    terms: list[np.ndarray] = []
    info: list[dict] = []

    def add(name, values, vars_, acc_only=False):
        terms.append(np.asarray(values, float))
        info.append({"name": name, "vars": list(vars_), "acc_only": acc_only})

    add("1", np.ones(t.size), [])
    for k, v in base.items():
        add(k, v, [k])
    rates = _rates(t, np.column_stack(list(base.values())))
    for i, k in enumerate(base):
        add(f"d{k}/dt", rates[:, i], [f"d{k}/dt"])
    for k, v in phys.items():
        add(k, v, [k])
    add("sin φ", np.sin(fl.column("roll_rad")), ["roll"])
    add("sin θ", np.sin(fl.column("pitch_rad")), ["pitch"])
    for c, short in (("pdot_rad_s2", "ṗ"), ("qdot_rad_s2", "q̇"), ("rdot_rad_s2", "ṙ")):
        add(short, fl.column(c), [short], acc_only=True)
    prod_vars = {**base, **phys}
    keys = list(prod_vars)
    for i, a in enumerate(keys):
        for b in keys[i:]:
            name = f"{a}²" if a == b else f"{a}·{b}"
            add(name, prod_vars[a] * prod_vars[b], [a, b])
    return np.column_stack(terms), info


def stlsq(x: np.ndarray, y: np.ndarray, threshold: float, ridge: float = 1e-3,
          iterations: int = 10) -> np.ndarray:
    """Sequentially thresholded ridge least squares on standardised x (n, M), y (n,)."""
    m = x.shape[1]
    keep = np.ones(m, dtype=bool)
    coef = np.zeros(m)
    g_all = x.T @ x / x.shape[0]
    b_all = x.T @ y / x.shape[0]
    for _ in range(iterations):
        idx = np.flatnonzero(keep)
        if idx.size == 0:
            break
        g = g_all[np.ix_(idx, idx)] + ridge * np.eye(idx.size)
        c = np.linalg.solve(g, b_all[idx])
        coef[:] = 0.0
        coef[idx] = c
        new = keep & (np.abs(coef) >= threshold)
        if np.array_equal(new, keep):
            break
        keep = new
    coef[~keep] = 0.0
    return coef


def _blocks(n: int, block: int) -> list[np.ndarray]:
    return [np.arange(s, min(s + block, n)) for s in range(0, n, block)]


def sparse_regression(an, *, threshold: float = 0.1, stable_fraction: float = 0.7,
                      resamples: int = 30, seed: int = 0, channels=None) -> dict:
    """Per channel: the stable sparse terms (module docstring). JSON-ready dict."""
    rng = np.random.default_rng(seed)
    lib, info = build_library(an)
    libb = an.band(lib)
    idx = np.flatnonzero(an.mask)
    step = max(1, idx.size // MAX_ROWS)
    idx = idx[::step]
    xall = libb[idx]
    sd = xall.std(0)
    usable = sd > 1e-12 * np.maximum(np.abs(xall).max(0), 1e-300)
    usable[0] = False  # the constant: handled by centring (reported as an offset)
    block = max(int(round(2.0 * an.flight.rate_hz / step)), 20)
    blocks = _blocks(idx.size, block)
    out = {"threshold": threshold, "stable_fraction": stable_fraction,
           "resamples": resamples, "library_size": int(usable.sum()), "channels": {}}
    metrics = an.metrics()
    for j, ch in enumerate(MEAS_CHANNELS):
        if channels is not None and ch not in channels:
            continue
        cols = np.flatnonzero(usable & np.array([not (d["acc_only"] and j >= 3)
                                                 for d in info]))
        x = (xall[:, cols] - xall[:, cols].mean(0)) / sd[cols]
        y_raw = an.residual_band[idx, j]
        ratio = metrics[ch]["rms_over_noise"]
        entry = {"label": CHANNEL_LABELS[ch], "rms_over_noise": ratio, "terms": []}
        if not np.isfinite(ratio) or ratio < 1.3:
            entry["summary"] = (f"{CHANNEL_LABELS[ch]}: no structure beyond noise "
                                f"(RMS {ratio:.2f} x noise floor)")
            out["channels"][ch] = entry
            continue
        ym, ys = y_raw.mean(), y_raw.std()
        y = (y_raw - ym) / ys
        counts = np.zeros(cols.size)
        for _ in range(resamples):
            pick = rng.integers(0, len(blocks), len(blocks))
            rows = np.concatenate([blocks[k] for k in pick])
            coef = stlsq(x[rows], y[rows], threshold)
            counts += coef != 0
        freq = counts / resamples
        stable = np.flatnonzero(freq >= stable_fraction)
        if stable.size == 0:
            entry["summary"] = f"{CHANNEL_LABELS[ch]}: no stable term"
            out["channels"][ch] = entry
            continue
        xs = x[:, stable]
        coef = np.linalg.lstsq(xs, y, rcond=None)[0]
        fit = xs @ coef
        r2 = 1.0 - np.sum((y - fit) ** 2) / np.sum(y * y)
        # cross-validated R^2 over 5 contiguous folds
        folds = np.array_split(np.arange(y.size), 5)
        sse = sst = 0.0
        for f in folds:
            tr = np.setdiff1d(np.arange(y.size), f)
            c = np.linalg.lstsq(xs[tr], y[tr], rcond=None)[0]
            sse += np.sum((y[f] - xs[f] @ c) ** 2)
            sst += np.sum(y[f] ** 2)
        cv_r2 = 1.0 - sse / sst
        vif = _vif(xs)
        corr_all = (x.T @ xs) / y.size  # (M', K) correlations of standardised columns
        terms = []
        for k, s in enumerate(stable):
            others = np.delete(np.arange(stable.size), k)
            drop = 1.0 - np.sum((y - xs[:, others] @ np.linalg.lstsq(
                xs[:, others], y, rcond=None)[0]) ** 2) / np.sum(y * y) if others.size else 0.0
            name = info[cols[s]]["name"]
            alike = [info[cols[i]]["name"] for i in np.flatnonzero(np.abs(corr_all[:, k]) > 0.95)
                     if i != s][:4]
            terms.append({
                "term": name, "vars": info[cols[s]]["vars"],
                "coef_std": float(coef[k]),
                "coef": float(coef[k] * ys / sd[cols[s]]),
                "frequency": float(freq[s]),
                "share": float(max(r2 - drop, 0.0)),
                "vif": float(vif[k]),
                "collinear_with": alike,
            })
        terms.sort(key=lambda d: -d["share"])
        entry.update({"terms": terms, "r2": float(r2), "cv_r2": float(cv_r2),
                      "summary": _sentence(CHANNEL_LABELS[ch], terms, r2)})
        out["channels"][ch] = entry
    return out


def _vif(xs: np.ndarray) -> np.ndarray:
    if xs.shape[1] < 2:
        return np.ones(xs.shape[1])
    c = np.corrcoef(xs, rowvar=False)
    try:
        return np.diag(np.linalg.inv(c))
    except np.linalg.LinAlgError:
        return np.full(xs.shape[1], np.inf)


def _sentence(label: str, terms: list[dict], r2: float) -> str:
    parts = []
    for t in terms[:4]:
        alt = f" (or {', '.join(t['collinear_with'][:2])})" if t["collinear_with"] else ""
        parts.append(f"{t['coef_std']:+.2f}·{t['term']}{alt}")
    return f"{label} residual ∝ " + " ".join(parts) + f"  (standardised; R² {r2:.2f})"
