"""Step 5 — the report: one self-contained HTML page with PNG figures.

    write_report("flight.parquet", "model.toml", "report_dir")   # -> {"index": path, ...}

Runs compare (with free simulation), where, diagnose and — when the top candidate is
significant, or `after` names an improved spec — the before/after comparison (adding the
top candidate with `add_effect` and saving it as DIR/model_after.toml). Writes
DIR/index.html (inline CSS, no scripts, relative links to DIR/*.png) and DIR/summary.json.
Figures use matplotlib's Agg backend.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np

from airwake.discrepancy.data import CHANNEL_LABELS, CHANNEL_UNITS
from airwake.discrepancy.errors import DiscrepancyError
from airwake.heli.context import MEAS_CHANNELS

CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;max-width:1100px;
margin:2em auto;padding:0 1em;color:#1d2327;line-height:1.45}
h1{font-size:1.6em;border-bottom:2px solid #2c6e9b;padding-bottom:.2em}
h2{font-size:1.25em;margin-top:2em;color:#2c6e9b}
table{border-collapse:collapse;margin:.6em 0;font-size:.92em}
th,td{border:1px solid #c9d1d9;padding:.25em .6em;text-align:right}
th{background:#eef3f7}td.l,th.l{text-align:left}
tr.sig td{background:#fff6dd}
img{max-width:100%;border:1px solid #dde3e8;margin:.5em 0}
.note{color:#555;font-size:.9em}.big{font-size:1.1em;font-weight:600}
code{background:#f2f4f6;padding:0 .25em}
"""


def jsonable(o):
    """numpy scalars and arrays inside dicts and lists -> plain JSON values."""
    import numpy as np

    if isinstance(o, dict):
        return {str(k): jsonable(v) for k, v in o.items()}
    if isinstance(o, list | tuple):
        return [jsonable(v) for v in o]
    if isinstance(o, np.ndarray):
        return jsonable(o.tolist())
    if isinstance(o, np.floating | float):
        return float(o)
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.bool_):
        return bool(o)
    return o


def _esc(x) -> str:
    return html.escape(str(x))


def _fig(path: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(plt, fig, path: Path) -> str:
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path.name


def _figures(out: Path, an, bd, diag, after_an) -> dict:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figs = {}
    fl = an.flight
    t = fl.t
    # 1. measured vs predicted around the worst window
    ww = bd["worst_windows"]
    t0 = ww[0]["t_start_s"] - 4.0 if ww else t[an.mask][0]
    sel = (t >= t0) & (t <= t0 + 10.0) & an.mask
    fig, axes = plt.subplots(3, 2, figsize=(11, 7.5), sharex=True)
    pred_b = an.band(an.zhat)
    for j, c in enumerate(MEAS_CHANNELS):
        ax = axes[j % 3, j // 3]
        ax.plot(t[sel], an.measured_band[sel, j], "k-", lw=1.0, label="measured")
        ax.plot(t[sel], pred_b[sel, j], "C3-", lw=1.0, label="model")
        if after_an is not None:
            ax.plot(t[sel], after_an.band(after_an.zhat)[sel, j], "C2--", lw=1.0,
                    label="model + added effect")
        ax.set_ylabel(f"{CHANNEL_LABELS[c]} [{CHANNEL_UNITS[c]}]")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8)
    axes[2, 0].set_xlabel("t [s]")
    axes[2, 1].set_xlabel("t [s]")
    fig.suptitle("Measured and predicted channels (analysis band), around the worst window")
    figs["measured_vs_predicted"] = _save(plt, fig, out / "measured_vs_predicted.png")
    # 2. residual time series over the flight
    fig, axes = plt.subplots(6, 1, figsize=(11, 9), sharex=True)
    for j, c in enumerate(MEAS_CHANNELS):
        ax = axes[j]
        r = np.where(an.mask, an.residual_band[:, j], np.nan)
        ax.plot(t, r, "C0-", lw=0.6, label="model")
        if after_an is not None:
            ax.plot(t, np.where(an.mask, after_an.residual_band[:, j], np.nan), "C2-", lw=0.6,
                    label="with added effect")
        nb = an.noise["band_rms"][j]
        ax.axhspan(-nb, nb, color="0.85", zorder=0)
        ax.set_ylabel(CHANNEL_LABELS[c], rotation=0, labelpad=18)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("t [s]")
    fig.suptitle("Residual (measured − predicted, analysis band); grey: ±1 noise floor")
    figs["residuals"] = _save(plt, fig, out / "residuals.png")
    # 3. residual by regime
    metrics = an.metrics()
    worst = sorted(MEAS_CHANNELS, key=lambda c: -metrics[c]["rms_over_noise"])[:3]
    reg = bd["regimes"]
    names = [n for n in ("height_over_R", "airspeed_m_s", "collective_rad",
                         "rotor_speed_rad_s", "roll_rad", "q_rad_s") if n in reg][:6]
    if names:
        fig, axes = plt.subplots(1, len(names), figsize=(3.0 * len(names) + 1, 3.4))
        axes = np.atleast_1d(axes)
        for ax, n in zip(axes, names, strict=True):
            bins = reg[n]["bins"]
            x = np.arange(len(bins))
            for k, c in enumerate(worst):
                ax.bar(x + (k - 1) * 0.27, [b["mean"][c] for b in bins], 0.27,
                       label=CHANNEL_LABELS[c])
            ax.set_xticks(x)
            ax.set_xticklabels([_bin_label(b) for b in bins], rotation=60, fontsize=7)
            ax.set_title(f"{n} [{reg[n]['unit']}]", fontsize=9)
            ax.axhline(0, color="k", lw=0.5)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7)
        axes[0].set_ylabel("mean residual")
        fig.suptitle("Mean residual by flight regime (3 worst channels)")
        figs["regimes"] = _save(plt, fig, out / "regimes.png")
    # 4. spectra and coherence
    sp = bd["spectra"]
    fig, axes = plt.subplots(2, 6, figsize=(14, 5.5), sharex=True)
    for j, c in enumerate(MEAS_CHANNELS):
        ax = axes[0, j]
        ax.semilogy(sp["f_hz"], sp["residual_psd"][:, j], "C0-", lw=0.8, label="residual")
        ax.semilogy(sp["f_hz"], sp["measured_psd"][:, j], "0.6", lw=0.6, label="measured")
        ax.axhline(an.noise["density"][j], color="C3", lw=0.8, ls="--", label="noise")
        if an.settings.lowpass_hz:
            ax.axvline(an.settings.lowpass_hz, color="k", lw=0.6, ls=":")
        ax.set_title(CHANNEL_LABELS[c], fontsize=9)
        ax2 = axes[1, j]
        for k, lab in enumerate(("col", "lat", "lon", "ped")):
            ax2.plot(sp["f_hz"], sp["coherence"][:, j, k], lw=0.8, label=lab)
        ax2.set_ylim(0, 1)
        ax2.set_xlabel("f [Hz]")
        ax.grid(alpha=0.3)
        ax2.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    axes[1, 0].legend(fontsize=7)
    axes[0, 0].set_ylabel("PSD")
    axes[1, 0].set_ylabel("coherence with input")
    fig.suptitle("Residual spectrum (dotted: analysis band edge) and coherence with inputs")
    figs["spectra"] = _save(plt, fig, out / "spectra.png")
    # 5. correlation tests for the worst channel
    tests = bd.get("tests")
    if tests:
        c = worst[0]
        lag_t = 1.0 / tests["rate_hz"]
        fig, axes = plt.subplots(1, 5, figsize=(15, 3.3))
        a = tests["auto"][c]
        k = np.arange(a["rho"].size) * lag_t
        axes[0].plot(k, a["rho"], "C0-", label="residual")
        axes[0].plot(k, a["white_band"], "k--", lw=0.8, label="band-limited white")
        axes[0].fill_between(k, a["white_band"] - a["band"], a["white_band"] + a["band"],
                             color="0.85")
        axes[0].set_title(f"{CHANNEL_LABELS[c]}: autocorrelation", fontsize=9)
        axes[0].legend(fontsize=7)
        for ax, inp in zip(axes[1:], ("delta_col_rad", "delta_lat_rad", "delta_lon_rad",
                                      "delta_ped_rad"), strict=True):
            x = tests["cross"][f"{c}|{inp}"]
            ax.plot(x["lags"] * lag_t, x["rho"], "C1-")
            ax.axhspan(-x["band"], x["band"], color="0.85")
            ax.set_title(f"{CHANNEL_LABELS[c]} × {inp.split('_')[1]}", fontsize=9)
            ax.set_xlabel("lag [s]")
        for ax in axes:
            ax.grid(alpha=0.3)
        fig.suptitle("Correlation tests (grey: 99 % band, Bartlett)")
        figs["correlations"] = _save(plt, fig, out / "correlations.png")
    # 6. candidates
    tested = [r for r in diag.ranked if r.testable]
    if tested:
        fig, ax = plt.subplots(figsize=(10, 0.45 * len(tested) + 1.2))
        y = np.arange(len(tested))[::-1]
        ax.barh(y + 0.2, [100 * max(r.explained, 0) for r in tested], 0.4, color="C0",
                label="explained (fitted)")
        ax.barh(y - 0.2, [100 * max(r.cv_explained, 0) for r in tested], 0.4, color="C1",
                label="explained (cross-validated, linear)")
        ax.set_yticks(y)
        ax.set_yticklabels([("★ " if r.significant else "") + r.name for r in tested])
        ax.axvline(100 * an.settings.min_explained, color="k", ls=":", lw=0.8)
        ax.set_xlabel("share of the residual variance (noise-weighted) [%]")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3, axis="x")
        fig.suptitle("Candidate effects (★ significant)")
        figs["candidates"] = _save(plt, fig, out / "candidates.png")
    # 7. before/after
    if after_an is not None:
        m0, m1 = an.metrics(), after_an.metrics()
        fig, ax = plt.subplots(figsize=(9, 3.6))
        x = np.arange(6)
        ax.bar(x - 0.25, [m0[c]["rms_over_noise"] for c in MEAS_CHANNELS], 0.5, label="before")
        ax.bar(x + 0.25, [m1[c]["rms_over_noise"] for c in MEAS_CHANNELS], 0.5, label="after")
        ax.axhline(1.0, color="k", lw=0.8, ls="--", label="noise floor")
        ax.set_xticks(x)
        ax.set_xticklabels([CHANNEL_LABELS[c] for c in MEAS_CHANNELS])
        ax.set_ylabel("RMS / noise floor")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3, axis="y")
        fig.suptitle("Error before and after adding the effect")
        figs["before_after"] = _save(plt, fig, out / "before_after.png")
    return figs


def _remaining_html(rem) -> str:
    if not rem["channels_above"]:
        return (f"<p id=remaining>What remains: every channel is within {rem['ratio']:g} x its "
                "noise floor.</p>")
    chans = ", ".join(f"{_esc(c)} {v:.1f} x" for c, v in rem["channels_above"].items())
    rows = "".join(
        f"<tr><td>{w['t_start_s']:.1f}–{w['t_end_s']:.1f}</td>"
        f"<td class=l>{_esc(CHANNEL_LABELS[w['dominant_channel']])}</td>"
        f"<td>{w['score']:.1f}</td><td class=l>"
        + ", ".join(f"{_esc(k)} {v:.2f}" for k, v in w["regime"].items()) + "</td></tr>"
        for w in rem["worst_windows"])
    terms = "".join(f"<li>{_esc(v)}</li>" for v in rem["terms"].values())
    return (f"<h3 id=remaining>What remains, and where</h3><p>Still above {rem['ratio']:g} x "
            f"the noise floor: {chans}. Worst windows of the improved model:</p><table><tr>"
            "<th>t [s]</th><th class=l>dominant</th><th>score</th><th class=l>regime "
            f"(means)</th></tr>{rows}</table>"
            + (f"<p>Named terms that explain what remains:</p><ul>{terms}</ul>" if terms
               else "") + "<p class=note>A structure here is physics the model still lacks: "
            "write it as a plugin effect (docs/model-discrepancy.md) and add it with "
            "<code>airwake model add NAME --plugin FILE.py</code>.</p>")


def _bin_label(b) -> str:
    lo, hi = b["lo"], b["hi"]
    if not np.isfinite(lo):
        return f"<{hi:.3g}"
    if not np.isfinite(hi):
        return f">{lo:.3g}"
    return f"{lo:.3g}–{hi:.3g}"


def _metrics_table(m0: dict, m1: dict | None = None) -> str:
    head = ("<tr><th class=l>channel</th><th>RMS</th><th>NRMSE</th><th>R²</th>"
            "<th>noise floor</th><th>RMS / noise</th>")
    if m1:
        head += "<th>RMS after</th><th>after / noise</th><th>change</th>"
    rows = [head + "</tr>"]
    for c in MEAS_CHANNELS:
        a = m0[c]
        row = (f"<tr><td class=l>{CHANNEL_LABELS[c]} [{_esc(CHANNEL_UNITS[c])}]</td>"
               f"<td>{a['rms']:.4f}</td><td>{a['nrmse']:.3f}</td><td>{a['r2']:.3f}</td>"
               f"<td>{a['noise_band']:.4f}</td><td>{a['rms_over_noise']:.2f}</td>")
        if m1:
            b = m1[c]
            row += (f"<td>{b['rms']:.4f}</td><td>{b['rms_over_noise']:.2f}</td>"
                    f"<td>{100 * (b['rms'] / a['rms'] - 1):+.0f} %</td>")
        rows.append(row + "</tr>")
    return "<table>" + "".join(rows) + "</table>"


def _img(figs, key, alt) -> str:
    if key not in figs:
        return ""
    return f'<img src="{_esc(figs[key])}" alt="{_esc(alt)}">'


def write_report(flight, model, out_dir, *, settings=None, after=None, quiet=True,
                 wind=None, sindy: bool = True) -> dict:
    """Run the workflow and write DIR/index.html + figures (module docstring). `sindy`:
    the diagnosis's sparse regression for effects outside the catalogue (the slowest
    part; off in bulk runs that only want the ranked catalogue)."""
    from airwake.discrepancy import where
    from airwake.discrepancy.add import add_effect
    from airwake.discrepancy.compare import analyse, summary
    from airwake.discrepancy.diagnose import diagnose
    from airwake.discrepancy.diagnose import summary as diag_summary
    from airwake.discrepancy.settings import AnalysisSettings
    from airwake.discrepancy.wind import on_flight
    from airwake.heli import load_model, save_spec, spec_calibration

    settings = settings or AnalysisSettings()
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise DiscrepancyError(f"--out {out}: exists and is not a directory")
    base = load_model(model)
    fl, wind_in = on_flight(wind, flight, settings)
    an = analyse(base, fl, settings, free_sim=settings.free_sim_windows > 0, wind=wind_in)
    bd = where.breakdown(an)
    diag = diagnose(base, an.flight, settings, analysis=an, sindy=sindy,
                    model_calibrated=spec_calibration(model) is not None)
    verdict = diag.verdict()
    after_model, added, after_note = None, None, ""
    if after is not None:
        after_model = load_model(after)
        after_note = f"the model given with --after ({_esc(after)})"
    elif verdict["kind"] == "effect":
        added = add_effect(base, verdict["effect"], an.flight, settings=settings, analysis=an)
        after_model = added.model
        after_note = (f"the model with the top candidate <b>{_esc(verdict['effect'])}</b> "
                      "added")
    out.mkdir(parents=True, exist_ok=True)
    after_an = remaining = None
    if after_model is not None:
        after_an = analyse(after_model, an.flight, settings, free_sim=False, wind=an.wind)
        remaining = remaining_residual(after_an)
        if added is not None:
            save_spec(after_model, out / "model_after.toml",
                      description=f"report: {added.effect} added")
    figs = _figures(out, an, bd, diag, after_an)
    s_compare = summary(an)
    s_diag = diag_summary(diag)
    s_where = where.summary(bd)
    wind_note = (f"the wind from {_esc(wind)} as the model's input" if wind is not None
                 else "still air (no wind given)")
    page = _html(an, s_compare, s_where, s_diag, diag, figs, after_an, after_note, added,
                 model, flight, verdict, remaining, wind_note)
    (out / "index.html").write_text(page, encoding="utf-8")
    result = {"index": str(out / "index.html"), "figures": sorted(figs.values()),
              "compare": s_compare, "diagnose": s_diag, "where": s_where,
              "verdict": verdict, "wind": None if wind is None else str(wind),
              "after": None if after_an is None else {
                  c: m["rms"] for c, m in after_an.metrics().items()},
              "remaining": remaining,
              "added": None if added is None else added.to_json()}
    (out / "summary.json").write_text(json.dumps(jsonable(result), indent=1))
    return result


def remaining_residual(after_an, ratio: float = 2.0) -> dict:
    """What the improved model still misses, and where: the channels above `ratio` x the
    noise floor, the worst windows with their flight regime, and the named terms of a
    sparse regression of what remains (JSON-ready)."""
    from airwake.discrepancy import where
    from airwake.discrepancy.sindy import sparse_regression

    m = after_an.metrics()
    bd = where.summary(where.breakdown(after_an))
    above = {CHANNEL_LABELS[c]: float(v["rms_over_noise"]) for c, v in m.items()
             if v["rms_over_noise"] > ratio}
    sindy = sparse_regression(after_an)
    terms = {CHANNEL_LABELS[c]: e["summary"] for c, e in sindy["channels"].items()
             if CHANNEL_LABELS[c] in above}
    return {"ratio": ratio, "channels_above": above,
            "worst_windows": bd["worst_windows"][:3], "terms": terms}


def _html(an, sc, sw, sd, diag, figs, after_an, after_note, added, model, flight,
          verdict, remaining, wind_note) -> str:
    st = an.settings
    parts = [f"<!DOCTYPE html><html lang=en><head><meta charset=utf-8>"
             f"<title>Model vs measurement — {_esc(Path(str(flight)).name)}</title>"
             f"<style>{CSS}</style></head><body>"]
    parts.append(f"<h1>Model versus measurement: {_esc(Path(str(flight)).name)}</h1>")
    parts.append(f"<p class=big id=verdict>{_esc(verdict['text'])}</p>")
    parts.append(
        f"<p class=note>Flight {_esc(flight)} ({sc['duration_s']:.1f} s, {sc['samples']} "
        f"samples, {sc['samples_analysed']} analysed); model {_esc(model)} with effects "
        f"{_esc(', '.join(sc['model_effects']))}, in {wind_note}. Residual = measured − predicted "
        f"(one-step-ahead). Every number uses the same analysis band: a zero-phase "
        f"Butterworth low-pass at {st.lowpass_hz:g} Hz (order {st.filter_order}, run forward "
        f"and back), and leaves out the first {st.skip_start_s:g} s of every run (start-up "
        f"transient). The noise floor is estimated from the data alone ("
        f"{_esc(sc['noise_method'])}).</p>")
    # 1 compare
    parts.append("<h2 id=compare>1. Compare: error per channel</h2>")
    parts.append(_metrics_table(sc["channels"]))
    parts.append("<p class=note>NRMSE = RMS / standard deviation of the measured channel; "
                 "R² = 1 − SSE/SST; RMS / noise near 1 means the model is as good as the "
                 "sensors allow.</p>")
    fs = sc.get("free_simulation")
    if fs:
        rows = "".join(f"<tr><td class=l>{_esc(v)}</td><td>{r:.4f}</td>"
                       f"<td>{fs['end_rms'][v]:.4f}</td></tr>" for v, r in fs["rms"].items())
        parts.append(f"<p>Free simulation: the model integrated open-loop from the measured "
                     f"state with the measured inputs over {fs['windows']} windows of "
                     f"{fs['window_s']:.2f} s (the hover is open-loop unstable: compare models "
                     f"on the same windows).</p><table><tr><th class=l>variable</th>"
                     f"<th>RMS error</th><th>RMS at window end</th></tr>{rows}</table>")
    parts.append(_img(figs, "measured_vs_predicted", "measured vs predicted"))
    # 2 where
    parts.append("<h2 id=where>2. Where it fails</h2>")
    parts.append(_img(figs, "residuals", "residual time series"))
    parts.append(_img(figs, "regimes", "residual by regime"))
    ww = sw["worst_windows"]
    if ww:
        rows = "".join(
            f"<tr><td>{w['t_start_s']:.1f}–{w['t_end_s']:.1f}</td>"
            f"<td class=l>{_esc(CHANNEL_LABELS[w['dominant_channel']])}</td>"
            f"<td>{w['score']:.1f}</td><td class=l>"
            + ", ".join(f"{_esc(k)} {v:.2f}" for k, v in w["regime"].items()) + "</td></tr>"
            for w in ww)
        parts.append("<p>Worst 2-s windows (mean over channels of (residual / noise)²):</p>"
                     "<table><tr><th>t [s]</th><th class=l>dominant</th><th>score</th>"
                     f"<th class=l>regime (means)</th></tr>{rows}</table>")
    parts.append(_img(figs, "spectra", "residual spectra and coherence"))
    parts.append(_img(figs, "correlations", "correlation tests"))
    flags = sw.get("cross_correlation_flags", [])
    nonlin = sw.get("higher_order_flags", [])
    parts.append("<p>Cross-correlation of residual and inputs beyond the 99 % band: "
                 + (", ".join(f"{_esc(f['channel'])}×{_esc(f['input'])} "
                              f"({100 * f['outside']:.0f} % of lags)" for f in flags[:12])
                    or "none") + ". Higher-order (Billings) tests flagging unmodelled "
                 "nonlinearity: "
                 + (", ".join(f"{_esc(f['channel'])}/{_esc(f['input'])}/{_esc(f['test'])}"
                              for f in nonlin[:12]) or "none") + ".</p>")
    # 3 candidates
    parts.append("<h2 id=candidates>3. Which effect is missing: ranked candidates</h2>")
    parts.append(_img(figs, "candidates", "candidate effects"))
    rows = []
    for i, r in enumerate(x for x in diag.ranked if x.testable):
        params = ", ".join(f"{_esc(k)} = {v:.4g}" for k, v in r.params.items())
        indist = ("; indistinguishable here from "
                  + ", ".join(_esc(o["effect"]) for o in r.indistinguishable_from)
                  + f" — separate with: {_esc(r.manoeuvre)}") if r.indistinguishable_from else ""
        rows.append(
            f"<tr class={'sig' if r.significant else 'n'}><td>{i + 1}</td>"
            f"<td class=l>{_esc(r.name)}</td><td>{100 * r.explained:.1f} %</td>"
            f"<td>{100 * r.cv_explained:.1f} %</td><td>{r.linear.p_value:.2g}</td>"
            f"<td>{'yes' if r.significant else 'no'}</td><td class=l>{params}</td>"
            f"<td class=l>{_esc(r.reason)}{indist}</td></tr>")
    untestable = "".join(f"<li>{_esc(r.name)}: {_esc(r.why_not)}</li>" for r in diag.ranked
                         if not r.testable)
    parts.append("<table><tr><th>#</th><th class=l>effect</th><th>explained</th>"
                 "<th>CV explained</th><th>p</th><th>significant</th><th class=l>fitted</th>"
                 "<th class=l>why</th></tr>" + "".join(rows) + "</table>")
    if untestable:
        parts.append(f"<p>Not testable on this flight:</p><ul>{untestable}</ul>")
    parts.append(f"<p class=note>Explained = share of the noise-weighted residual variance "
                 f"removed by fitting the effect; CV = the same out of sample (linear "
                 f"screening, {st.n_blocks} time blocks). Significant = partial-F p below "
                 f"{st.alpha:g}/(number of candidates) with the residual's effective sample "
                 f"size ({diag.n_eff:.0f} of {int(an.mask.sum()) * 6} values), CV explained ≥ "
                 f"{100 * st.min_explained:.0f} % and an explained RMS ≥ "
                 f"{st.min_noise_ratio:g} × the noise floor in some channel.</p>")
    # SINDy
    parts.append("<h2 id=sparse-regression>Named sparse regression of the residual</h2>")
    if diag.sindy:
        items = "".join(f"<li>{_esc(e['summary'])}</li>" for e in diag.sindy["channels"]
                        .values())
        parts.append("<p>Terms of physical variables that stably explain each channel's "
                     "residual (STLSQ with stability selection over time blocks; coefficients "
                     "on standardised terms; 'or' lists nearly collinear alternatives). An "
                     f"effect outside the catalogue shows up here.</p><ul>{items}</ul>")
    # 5 error falls
    parts.append("<h2 id=error-falls>4–5. Add the effect and watch the error fall</h2>")
    if after_an is not None:
        parts.append(f"<p>After: {after_note}.</p>")
        if added is not None:
            vals = ", ".join(f"{_esc(k)} = {v:.4g}" for k, v in added.fit.values.items())
            parts.append(f"<p>Fitted: {vals} (written to <a href=model_after.toml>"
                         f"model_after.toml</a>).</p>")
        parts.append(_metrics_table(sc["channels"], after_an.metrics()))
        parts.append(_img(figs, "before_after", "before and after"))
        parts.append(_remaining_html(remaining))
    elif verdict["kind"] in ("wind", "calibrate"):
        parts.append(f"<p>Nothing added: {_esc(verdict['text'])}</p>")
    else:
        parts.append("<p>Nothing added: no candidate is significant (run <code>airwake model "
                     "add EFFECT</code> to try one anyway, or give <code>--after</code>).</p>")
    parts.append("<p class=note>Generated by <code>airwake model report</code>; "
                 "docs/model-discrepancy.md explains every number.</p></body></html>")
    return "\n".join(parts)
