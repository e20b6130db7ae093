"""Step 3 — which effect is missing: rank the catalogue's candidates on a flight.

For each candidate effect E of the catalogue (`candidates.py`) that the flight can test:

1. **Screen** (linear, cheap): regressors are the sensitivities of the predicted channels
   to E's amplitude parameters at "off", s_j = (z_hat(M + E(theta_j = step)) - z_hat(M)) /
   step, one batched prediction per candidate (and per alternative shape). The residual
   r = band(z - z_hat(M)) is regressed on band(s_j) over the analysis mask with channel
   weights 1/noise^2: in-sample explained share of the residual (ERR-style), per channel
   and overall; the same out of sample by time-block cross-validation; a partial-F test
   with the residual's effective sample size (autocorrelation-corrected, Geyer's initial
   positive sequence per channel) as denominator degrees of freedom.
2. **Refine** (nonlinear, the top few): `fit.fit_parameters` on E's fit parameters from
   the linear estimate; the refined explained share ranks the refined candidates, and
   refinement goes on down the list while an unrefined candidate's cross-validated
   screening share beats the best refined share (a screening the nonlinear fit does not
   bear out cannot put a candidate above a better one left unrefined).
3. **Decide**: significant when p < alpha / (number of candidates tested) *and* the
   cross-validated explained share >= min_explained *and* the explained RMS reaches
   min_noise_ratio x the noise floor in some channel (a practical effect size: with 10^4
   samples, statistically significant alone means little).
4. **Tell apart**: canonical correlations between the candidates' sensitivity subspaces
   on this flight; above 0.9 the flight cannot distinguish them ("indistinguishable
   here"), and the separating manoeuvres are suggested.
5. **Explain**: a one-line physical reason from the data (`reasons.py`) and a named,
   sparse regression of the residual on physical-variable terms (`sindy.py`) for effects
   outside the catalogue.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from airwake.discrepancy import signal
from airwake.discrepancy.candidates import CANDIDATES, Candidate, effect_with, flight_can_test
from airwake.discrepancy.compare import Analysis, analyse
from airwake.discrepancy.data import CHANNEL_LABELS
from airwake.discrepancy.fit import fit_parameters, predict_sets
from airwake.discrepancy.regress import LinearFit, canonical_correlations, linear_fit
from airwake.discrepancy.settings import AnalysisSettings
from airwake.discrepancy.wind import WIND_CANDIDATE
from airwake.heli.context import MEAS_CHANNELS

INDISTINGUISHABLE = 0.9
# "calibrate first": the baseline misses by more than BROAD_NOISE_RATIO x the noise floor
# in at least BROAD_CHANNELS channels, and refitting its own parameters leaves at most
# RECAL_UNEXPLAINED of what the best candidate leaves unexplained (both cross-validated)
BROAD_NOISE_RATIO = 3.0
BROAD_CHANNELS = 3
RECAL_UNEXPLAINED = 0.5


@dataclass
class CandidateResult:
    name: str
    title: str
    testable: bool = True
    why_not: str = ""
    shape: dict = field(default_factory=dict)
    linear: LinearFit | None = None
    linear_params: dict = field(default_factory=dict)
    refined: bool = False
    params: dict = field(default_factory=dict)  # fitted values (short names)
    explained: float = 0.0  # final (refined if refined, else linear in-sample)
    explained_channels: np.ndarray = field(default_factory=lambda: np.zeros(6))
    rms_after: np.ndarray = field(default_factory=lambda: np.zeros(6))
    significant: bool = False
    decision: str = ""
    reason: str = ""
    indistinguishable_from: list = field(default_factory=list)
    manoeuvre: str = ""
    contribution: np.ndarray | None = None  # (T, 6) predicted change of the channels
    sens: np.ndarray | None = None  # (n, 6, J) weighted screening regressors
    wind: dict | None = None  # unmodelled wind: the fitted earth-axis wind (wind.describe)

    @property
    def kind(self) -> str:
        """"effect" (a catalogue effect: add it) or "wind" (supply the wind instead)."""
        return "wind" if self.name == WIND_CANDIDATE else "effect"

    @property
    def cv_explained(self) -> float:
        return self.linear.cv_explained if self.linear is not None else 0.0

    def to_json(self) -> dict:
        out = {"effect": self.name, "title": self.title, "kind": self.kind,
               "testable": self.testable}
        if not self.testable:
            out["why_not"] = self.why_not
            return out
        lin = self.linear
        out.update({
            "explained": self.explained,
            "explained_channels": {c: float(v) for c, v in
                                   zip(MEAS_CHANNELS, self.explained_channels, strict=True)},
            "cv_explained": lin.cv_explained,
            "cv_explained_channels": {c: float(v) for c, v in
                                      zip(MEAS_CHANNELS, lin.cv_channels, strict=True)},
            "f_stat": lin.f_stat, "p_value": lin.p_value, "n_eff": lin.n_eff,
            "condition_number": lin.condition,
            "params": self.params, "refined": self.refined, "shape": self.shape,
            "rms_after": {c: float(v) for c, v in zip(MEAS_CHANNELS, self.rms_after,
                                                      strict=True)},
            "significant": self.significant, "decision": self.decision,
            "reason": self.reason, "indistinguishable_from": self.indistinguishable_from,
            "separating_manoeuvre": self.manoeuvre,
        })
        if self.wind is not None:
            out["wind"] = self.wind
        return out


@dataclass
class Diagnosis:
    analysis: Analysis
    ranked: list  # CandidateResult, best first (testable ones), then untestable
    n_eff: float
    sindy: dict | None = None
    notes: list = field(default_factory=list)
    recalibration: dict | None = None  # screen_recalibration's numbers (None: not screened)
    model_calibrated: bool | None = None  # the spec carries a [calibration] table

    def verdict(self) -> dict:
        """What the diagnosis says, in one of four kinds (module docstring, step 6):
        "calibrate" (the model is not this aircraft's: calibrate before naming an
        effect), "wind" (the residual is wind: estimate or supply it), "effect" (the
        top-ranked significant catalogue effect) or "none". JSON-ready."""
        from airwake.discrepancy import wind as wind_mod

        tested = [r for r in self.ranked if r.testable]
        sig = [r for r in tested if r.significant]
        rc = self.recalibration
        best_cv = max((r.cv_explained for r in tested), default=0.0)
        wind = next((r for r in sig if r.name == WIND_CANDIDATE), None)
        if rc is not None and rc["calibrate_first"]:
            top = tested[0].name if tested else "none"
            if_wind = "" if wind is None else (
                f" If the model was calibrated on this aircraft in still air, the residual "
                f"is more likely the wind (unmodelled wind explains "
                f"{100 * wind.explained:.0f} %): {wind_mod.ADVICE}.")
            return {"kind": "calibrate", "effect": None, "text": (
                f"Calibrate first: the model does not fit this aircraft. {rc['broad']} of 6 "
                f"channels miss by more than {BROAD_NOISE_RATIO:g}x the noise floor, and "
                f"refitting the model's own {rc['parameters']} parameters explains "
                f"{100 * rc['cv_explained']:.0f} % of the residual (cross-validated) where "
                f"the best candidate ({top}) explains {100 * best_cv:.0f} %: any effect "
                "named now would stand in for the calibration. Calibrate on a still-air "
                "flight (`airwake calibrate FLIGHT --model SPEC --out fitted.toml`, "
                "docs/calibration.md), then diagnose again with `--model fitted.toml`."
                + if_wind)}
        if not sig:
            return {"kind": "none", "effect": None, "text": (
                "No candidate is significant: the model agrees with this flight within the "
                "thresholds.")}
        lead = sig[0]
        if lead is wind:
            w = wind.wind or {}
            mean = w.get("mean_ned_m_s", [0.0, 0.0, 0.0])
            runner = next((r for r in sig[1:] if any(
                o["effect"] == r.name for o in wind.indistinguishable_from)), None)
            also = "" if runner is None else (
                f" ({runner.name} explains {100 * runner.explained:.0f} % but is "
                "indistinguishable from a wind on this flight)")
            field = (f"a wind field of about ({mean[0]:+.1f}, {mean[1]:+.1f}, "
                     f"{mean[2]:+.1f}) m/s (N, E, D) with its gradients explains "
                     f"{100 * wind.explained:.0f} % of it")
            if self.analysis.wind is not None:
                return {"kind": "wind", "effect": None, "text": (
                    f"The wind given as the model's input leaves a wind-like residual, not a "
                    f"missing model effect{also}: a correction {field}. The wind table is "
                    "too smooth or biased here (an estimate's posterior mean, an anemometer "
                    "map's interpolation, the eq 5.3 field's linearisation over the disk); "
                    "no model effect is named.")}
            return {"kind": "wind", "effect": None, "text": (
                f"The residual is unmodelled wind, not a missing model effect{also}: "
                f"{field}. Do not add an effect for it: {wind_mod.ADVICE}.")}
        caveat = ""
        if wind is not None and any(o["effect"] == WIND_CANDIDATE
                                    for o in lead.indistinguishable_from):
            caveat = (f" On this flight it is indistinguishable from a wind (unmodelled wind "
                      f"explains {100 * wind.explained:.0f} %): if the flight was in wind, "
                      f"{wind_mod.ADVICE}; otherwise separate them with: {lead.manoeuvre}.")
        return {"kind": "effect", "effect": lead.name, "text": (
            f"The residual is best explained by {lead.name} ({100 * lead.explained:.0f} % "
            f"explained): {lead.reason}.{caveat}")}

    def top(self, k: int = 1) -> list[str]:
        return [c.name for c in self.ranked if c.testable][:k]

    def significant(self) -> list[str]:
        return [c.name for c in self.ranked if c.significant]

    def result(self, name: str) -> CandidateResult:
        for c in self.ranked:
            if c.name == name:
                return c
        raise KeyError(name)


def effective_rows(an: Analysis) -> float:
    """Effective number of independent residual values: sum over channels of Geyer's N_eff
    of the in-band residual."""
    return float(sum(signal.effective_samples(an.residual_band[:, j], an.mask)
                     for j in range(6)))


def screen(an: Analysis, cand: Candidate, blocks, n_eff: float, y: np.ndarray
           ) -> CandidateResult:
    """Linear screening of one candidate over its alternative shapes (best by CV)."""
    res = CandidateResult(cand.name, cand.title, manoeuvre=cand.manoeuvre)
    base_model = an.model
    best = None
    for shape in cand.shapes:
        eff0 = effect_with(cand.name, {**cand.base, **shape})
        m = base_model + eff0
        names = m.parameter_names
        v0 = m.parameter_vector()
        vecs = []
        for pname, step in cand.screen.items():
            v = v0.copy()
            v[names.index(f"{cand.name}.{pname}")] = cand.base.get(pname, 0.0) + step
            vecs.append(v)
        z = predict_sets(m, an, np.array(vecs), cand.reuse_hidden)
        steps = np.array(list(cand.screen.values()))
        sens = (z - an.zhat[None]) / steps[:, None, None]
        x = an.regressors(sens)
        fit = linear_fit(y, x, an.weights, blocks, n_eff)
        if best is None or fit.cv_explained > best[0].cv_explained:
            best = (fit, shape, x)
    fit, shape, x = best
    res.linear, res.shape = fit, dict(shape)
    res.sens = x
    res.linear_params = {p: cand.base.get(p, 0.0) + float(a)
                         for p, a in zip(cand.screen, fit.coef, strict=True)}
    res.params = {**{k: v for k, v in {**cand.base, **shape}.items()}, **res.linear_params}
    res.explained = fit.explained
    res.explained_channels = fit.explained_channels
    return res


def refine(an: Analysis, cand: Candidate, res: CandidateResult, max_nfev: int = 20) -> None:
    """Nonlinear fit of the candidate's parameters from the linear estimate."""
    from airwake.heli.effects.base import effect_class

    specs = {p.name: p for p in effect_class(cand.name).PARAMETERS}
    start = {}
    for p, v in res.params.items():
        lo, hi = specs[p].bounds
        start[p] = float(np.clip(v, lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo)))
    model = an.model + effect_with(cand.name, start)
    free = [f"{cand.name}.{p}" for p in cand.fit]
    fr = fit_parameters(an, model, free, max_nfev=max_nfev, reuse_hidden=cand.reuse_hidden)
    res.refined = True
    res.params = {**start, **{k.split(".", 1)[1]: v for k, v in fr.values.items()}}
    res.contribution = fr.zhat - an.zhat
    _score_contribution(an, res)


def _screen_wind(an: Analysis, blocks, n_eff: float, y: np.ndarray) -> CandidateResult:
    """Unmodelled wind screened like a candidate (`wind.screen`)."""
    from airwake.discrepancy import wind as wind_mod

    res = CandidateResult(WIND_CANDIDATE, wind_mod.WIND_TITLE, manoeuvre=wind_mod.MANOEUVRE)
    res.linear, res.sens, res.linear_params = wind_mod.screen(an, blocks, n_eff, y)
    res.shape = {"field": f"earth-axis wind + drift (Legendre P1..P{wind_mod.ORDER} of "
                          "time) + linear in position (eq 3.15), rotation = curl / 2"}
    res.params = dict(res.linear_params)
    res.explained, res.explained_channels = res.linear.explained, res.linear.explained_channels
    res.wind = wind_mod.describe(res.params, an.flight)
    return res


def _score_contribution(an: Analysis, res: CandidateResult) -> None:
    after = an.band(an.flight.z - an.zhat - res.contribution)[an.mask]
    before = an.residual_band[an.mask]
    w = an.weights
    sse0_c = np.sum(before**2, 0)
    sse1_c = np.sum(after**2, 0)
    res.explained = float(1.0 - np.sum(sse1_c * w) / np.sum(sse0_c * w))
    res.explained_channels = 1.0 - sse1_c / np.maximum(sse0_c, 1e-300)
    res.rms_after = np.sqrt(np.mean(after**2, 0))


def diagnose(model, flight, settings: AnalysisSettings | None = None, *,
             candidates=None, refine_top: int = 4, sindy: bool = True, progress=None,
             analysis: Analysis | None = None, wind=None,
             model_calibrated: bool | None = None) -> Diagnosis:
    """Rank the catalogue's candidates and unmodelled wind on `flight` for `model`
    (module docstring). `wind`: the flight's known wind as the model's input, (T, 6),
    "truth" or a wind table's path (`airwake.discrepancy.wind`); `candidates` may name
    `unmodelled_wind` too.
    `model_calibrated`: the model's spec says it was calibrated (`airwake calibrate`'s
    [calibration] table); unless True, the diagnosis also checks whether the model's own
    parameters explain the residual better than any candidate ("calibrate first")."""
    from airwake.discrepancy import wind as wind_mod
    from airwake.discrepancy.reasons import reason_for

    settings = settings or AnalysisSettings()
    if analysis is None:
        flight, wind = wind_mod.on_flight(wind, flight, settings)
    an = analysis or analyse(model, flight, settings, wind=wind)
    cands = [c for c in CANDIDATES if candidates is None or c.name in candidates]
    with_wind = candidates is None or WIND_CANDIDATE in candidates
    y = an.residual_band[an.mask]
    n = y.shape[0]
    blocks = [b for b in np.array_split(np.arange(n), settings.n_blocks) if b.size]
    n_eff = effective_rows(an)
    results, untestable = [], []
    for i, cand in enumerate(cands):
        if cand.name in an.model:
            untestable.append(CandidateResult(cand.name, cand.title, testable=False,
                                              why_not="already in the model"))
            continue
        why = flight_can_test(cand, an.flight, an.model, an.wind)
        if why:
            untestable.append(CandidateResult(cand.name, cand.title, testable=False,
                                              why_not=why))
            continue
        results.append(screen(an, cand, blocks, n_eff, y))
        if progress is not None:
            progress.update(i + 1, cand.name)
    if progress is not None:
        progress.update(len(cands), f"unmodelled wind, then refining the best {refine_top}")
    if with_wind:
        results.append(_screen_wind(an, blocks, n_eff, y))
    results.sort(key=lambda r: -r.cv_explained)
    by_name = {c.name: c for c in cands}

    def refine_one(res):
        if res.name == WIND_CANDIDATE:
            res.params, res.contribution = wind_mod.refine(an, res.linear_params)
            res.wind = wind_mod.describe(res.params, an.flight)
            res.refined = True
            _score_contribution(an, res)
        else:
            refine(an, by_name[res.name], res)

    for res in results[:refine_top]:
        if res.cv_explained > 0:
            refine_one(res)
    # refined candidates rank above unrefined ones, so a screening estimate the nonlinear
    # fit did not bear out must not leave a better-screened candidate unrefined below it:
    # refine on down the list while the best unrefined screening beats the best refinement
    while True:
        best = max((r.explained for r in results if r.refined), default=None)
        rest = [r for r in results if not r.refined and r.cv_explained > 0]
        if best is None or not rest or rest[0].cv_explained <= best:
            break
        refine_one(rest[0])
    for res in results:
        if not res.refined:
            x = res.sens
            res.contribution = None
            fitted = np.einsum("ncj,j->nc", x, res.linear.coef) / np.sqrt(an.weights)
            after = y - fitted
            res.rms_after = np.sqrt(np.mean(after**2, 0))
    results.sort(key=lambda r: (not r.refined, -(r.explained if r.refined else
                                                 r.cv_explained)))
    _decide(an, results, settings)
    _distinguish(results)
    for res in results:
        res.reason = reason_for(an, res)
    diag = Diagnosis(an, results + untestable, n_eff, model_calibrated=model_calibrated)
    if progress is not None:
        progress.finish("decided" + ("; checking whether recalibrating explains more"
                                     if model_calibrated is not True else ""))
    if model_calibrated is not True:
        diag.recalibration = screen_recalibration(an, blocks, n_eff, y, results)
    if sindy:
        from airwake.discrepancy.sindy import sparse_regression

        diag.sindy = sparse_regression(an)
    return diag


def screen_recalibration(an: Analysis, blocks, n_eff: float, y: np.ndarray,
                         results: list) -> dict:
    """Is the model this aircraft's? The residual regressed (linear, cross-validated,
    like a candidate) on the sensitivities to the model's own free parameters (those not
    marked fixed: what `airwake calibrate` fits), each stepped by 1 % of its value (or of
    its range at zero). "calibrate_first" when the baseline misfits broadly and
    recalibration leaves at most RECAL_UNEXPLAINED of what the best candidate leaves."""
    from airwake.discrepancy.fit import predict_sets

    model = an.model
    idx = np.flatnonzero(~model.fixed_mask())
    v0 = model.parameter_vector()
    lo, hi = model.bounds()
    steps = np.where(v0[idx] != 0.0, 0.01 * np.abs(v0[idx]), 0.01 * (hi[idx] - lo[idx]))
    vecs = np.repeat(v0[None], idx.size, 0)
    vecs[np.arange(idx.size), idx] += steps
    sens = (predict_sets(model, an, vecs) - an.zhat[None]) / steps[:, None, None]
    fit = linear_fit(y, an.regressors(sens), an.weights, blocks, n_eff)
    ratio = np.array([m["rms_over_noise"] for m in an.metrics().values()])
    broad = int(np.sum(ratio > BROAD_NOISE_RATIO))
    best = max((r.cv_explained for r in results), default=0.0)
    first = bool(broad >= BROAD_CHANNELS and fit.p_value < an.settings.alpha
                 and 1.0 - fit.cv_explained <= RECAL_UNEXPLAINED * (1.0 - best))
    return {"parameters": int(idx.size), "explained": fit.explained,
            "cv_explained": fit.cv_explained, "best_candidate_cv_explained": best,
            "broad": broad, "calibrate_first": first}


def _decide(an: Analysis, results: list, settings: AnalysisSettings) -> None:
    k = max(len(results), 1)
    noise = np.asarray(an.noise["band_rms"], float)
    for res in results:
        lin = res.linear
        p_ok = lin.p_value < settings.alpha / k
        size_ok = lin.cv_explained >= settings.min_explained
        rms_ok = bool(np.any(lin.explained_rms >= settings.min_noise_ratio * noise))
        res.significant = bool(p_ok and size_ok and rms_ok)
        parts = [f"p = {lin.p_value:.2g} {'<' if p_ok else '>='} {settings.alpha / k:.2g}",
                 f"CV explained {100 * lin.cv_explained:.1f} % "
                 f"{'>=' if size_ok else '<'} {100 * settings.min_explained:.0f} %",
                 "explained RMS " + ("reaches" if rms_ok else "below")
                 + f" {settings.min_noise_ratio:g} x noise"]
        res.decision = ("significant: " if res.significant else "not significant: ") + \
            "; ".join(parts)


def _distinguish(results: list, top: int = 6) -> None:
    tested = [r for r in results if r.sens is not None][:top]
    for i, a in enumerate(tested):
        xa = a.sens.reshape(-1, a.sens.shape[2])
        for b in tested[i + 1:]:
            xb = b.sens.reshape(-1, b.sens.shape[2])
            cc = canonical_correlations(xa, xb)
            if cc.size and cc[0] > INDISTINGUISHABLE:
                a.indistinguishable_from.append({"effect": b.name, "canonical_corr":
                                                 float(cc[0])})
                b.indistinguishable_from.append({"effect": a.name, "canonical_corr":
                                                 float(cc[0])})


def summary(diag: Diagnosis) -> dict:
    an = diag.analysis
    out = {
        "flight": an.flight.name,
        "model_effects": list(an.model.effect_names),
        "n_eff": diag.n_eff,
        "settings": an.settings.as_dict(),
        "candidates": [r.to_json() for r in diag.ranked],
        "significant": diag.significant(),
        "verdict": diag.verdict(),
        "recalibration": diag.recalibration,
        "notes": diag.notes,
    }
    if diag.sindy is not None:
        out["sparse_regression"] = diag.sindy
    return out


def channel_list(values, threshold: float = 0.2) -> list[str]:
    return [CHANNEL_LABELS[c] for c, v in zip(MEAS_CHANNELS, values, strict=True)
            if v >= threshold]
