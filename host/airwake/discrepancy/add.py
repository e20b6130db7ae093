"""Step 4 — add an effect to the model, fit it, write the new spec (and watch the error).

    result = add_effect("table52", "ground_effect", "flight.parquet", out="model2.toml")

The effect is a catalogue effect (by name) or one a user plugin registers
(`plugin="my_effect.py"`). Its parameters are fitted by nonlinear least squares on the
equation error (`fit.fit_parameters`: the same band, mask and noise weights as every other
step; bounds from the effect's parameter specs). A catalogue effect starts from its linear
screening estimate (`diagnose.screen`); a plugin from its defaults, fitting its non-fixed
parameters. `retune` names other model parameters (full names or globs, e.g.
"main_rotor.lock_number", "fuselage.*") fitted together with the effect. The new spec is
written to a temporary file next to `out`, loaded back to check it, and renamed over
`out`: a failure anywhere leaves nothing (or the previous file) behind.
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from airwake.discrepancy.candidates import candidate, effect_with
from airwake.discrepancy.compare import Analysis, analyse, channel_metrics
from airwake.discrepancy.errors import DiscrepancyError
from airwake.discrepancy.fit import FitResult, fit_parameters
from airwake.discrepancy.settings import AnalysisSettings
from airwake.heli import load_model, save_spec
from airwake.heli.context import MEAS_CHANNELS


@dataclass
class AddResult:
    effect: str
    model: object
    fit: FitResult
    before: dict  # channel metrics
    after: dict
    out: Path | None
    plugin: str | None

    def to_json(self) -> dict:
        return {
            "effect": self.effect,
            "plugin": self.plugin,
            "fitted": self.fit.values,
            "start": self.fit.start,
            "at_bound": self.fit.at_bound,
            "converged": self.fit.success,
            "evaluations": self.fit.nfev,
            "before": {c: self.before[c]["rms"] for c in MEAS_CHANNELS},
            "after": {c: self.after[c]["rms"] for c in MEAS_CHANNELS},
            "noise_band": {c: self.before[c]["noise_band"] for c in MEAS_CHANNELS},
            "reduction": {c: 1.0 - self.after[c]["rms"] / self.before[c]["rms"]
                          for c in MEAS_CHANNELS},
            "out": None if self.out is None else str(self.out),
            "model_effects": list(self.model.effect_names),
            "worse_channels": self.worse_channels(),
        }

    def worse_channels(self, tolerance: float = 0.01) -> list[str]:
        """Channels whose error the fitted effect raised by more than `tolerance`
        (relative): the effect, as fitted, does not describe them on this flight."""
        return [c for c in MEAS_CHANNELS
                if self.after[c]["rms"] > (1.0 + tolerance) * self.before[c]["rms"]]


def resolve_retune(model, patterns) -> list[str]:
    names = list(model.parameter_names)
    fixed = dict(zip(names, model.fixed_mask(), strict=True))
    out = []
    for pat in patterns or ():
        hits = [n for n in names if fnmatch.fnmatchcase(n, pat)]
        if not hits:
            raise DiscrepancyError(f"--retune {pat!r} matches no model parameter; parameters: "
                                   f"{', '.join(names)}")
        hits = [n for n in hits if not fixed[n] or n == pat]
        out += [n for n in hits if n not in out]
    return out


def _register_plugin(plugin) -> list[str]:
    from airwake.heli.effects.base import EffectError
    from airwake.heli.plugins import load_plugin

    try:
        return load_plugin(plugin)
    except EffectError as exc:
        raise DiscrepancyError(str(exc)) from None


def _calibration_after(start_spec, new_model, effect: str, flight, wind,
                       flight_name: str, misfit_flight=None, misfit_name: str = "") -> dict:
    """The new spec's [calibration] table: the start spec's, with the effects added since
    and `model_error_std` / `model_error_offset` / `still_air_wind_error` re-measured for
    the new model on the still-air flight it was fitted on (what the wind estimator takes
    as its channel-noise floor, its steady-offset allowance and its intervals' still-air
    error: those of the model it runs, not of the model before the effect). With a windy
    flight and its wind as input nothing is re-measured: the start spec's floor is kept
    (it can only be larger), and so is its still-air wind error, which was measured for
    the model before the effect (the calibration flight is not at hand here; an effect
    that lowers the misfit lowers it, so it errs wide); or none is written.
    `flight_name`: the flight as the report names it. `misfit_flight`: a still-air flight
    (read) to re-measure them on instead, named `misfit_name` (an effect fitted on steady
    legs, a floor for flights that manoeuvre as the calibration flight does)."""
    from airwake.calibrate import CalibrationError, model_error
    from airwake.calibrate.commands import add_still_air_wind_error
    from airwake.estimate.wind import STILL_AIR_BIAS_KEY
    from airwake.heli import spec_calibration

    table = dict(spec_calibration(start_spec) or {})
    table["added_effects"] = [*table.get("added_effects", []), effect]
    # which channel made the old model's still-air wind error says nothing of the new one's
    table.pop(STILL_AIR_BIAS_KEY, None)
    if misfit_flight is not None:
        flight, flight_name = misfit_flight, misfit_name
    elif wind is not None or isinstance(flight, np.ndarray):
        return table
    try:
        rms, offset = model_error(new_model, flight)
        table["model_error_std"] = [float(v) for v in rms]
        table["model_error_offset"] = [float(v) for v in offset]
        table["model_error_flight"] = flight_name
    except CalibrationError as exc:
        raise DiscrepancyError(f"the model with {effect}: {exc}") from None
    add_still_air_wind_error(table, new_model, flight)
    return table


def _load_misfit_flight(path):
    """The `misfit_on` flight, read before the fit so that one that cannot be read fails
    first, named (its use: a still-air flight, which the caller vouches for: nothing here
    can tell the air); the table read is the one the misfit is measured on."""
    from airwake.calibrate import load_flight
    from airwake.errors import AirwakeError

    if not Path(str(path)).is_file():
        raise DiscrepancyError(f"misfit flight {path}: no such flight table")
    try:
        return load_flight(str(path))
    except (AirwakeError, OSError, ValueError) as exc:
        raise DiscrepancyError(f"misfit flight {path}: not a flight table ({exc})") from None


def add_effect(model, effect: str, flight, *, plugin=None, retune=(), out=None,
               settings: AnalysisSettings | None = None, analysis: Analysis | None = None,
               max_nfev: int = 30, name: str = "", progress=None, wind=None,
               misfit_on=None) -> AddResult:
    """Enable `effect`, fit it (and `retune`) on `flight`, write `out` (module docstring).
    `wind`: the flight's known wind as the model's input: (T, 6), "truth" or a wind table's
    path (`airwake.discrepancy.wind`). `misfit_on`: the still-air flight the written
    spec's misfit (`model_error_std` / `_offset`, the still-air wind error) is measured
    on, when not `flight` (`_calibration_after`)."""
    from airwake.discrepancy.wind import ADVICE, WIND_CANDIDATE
    from airwake.heli.effects.base import EffectError, effect_class

    if effect == WIND_CANDIDATE:
        raise DiscrepancyError(f"{WIND_CANDIDATE} is not a model effect: the wind is an input "
                               f"of the model, not part of it; {ADVICE}")
    misfit_flight = None if misfit_on is None else _load_misfit_flight(misfit_on)
    settings = settings or AnalysisSettings()
    start_spec = model
    model = load_model(model)
    plugin_names = _register_plugin(plugin) if plugin is not None else []
    if plugin is not None and effect not in plugin_names:
        raise DiscrepancyError(f"plugin {plugin} registers {plugin_names}, not {effect!r}")
    try:
        cls = effect_class(effect)
    except EffectError as exc:
        raise DiscrepancyError(str(exc)) from None
    if effect in model:
        raise DiscrepancyError(f"effect {effect!r} is already in the model; refit it with "
                               f"--retune '{effect}.*' on a model without it, or remove it")
    if analysis is None:
        from airwake.discrepancy.wind import on_flight

        flight, wind = on_flight(wind, flight, settings)
    an = analysis or analyse(model, flight, settings, wind=wind)
    free_retune = resolve_retune(model, retune)
    cand = candidate(effect)
    if cand is not None:
        from airwake.discrepancy.diagnose import effective_rows, screen

        y = an.residual_band[an.mask]
        blocks = [b for b in np.array_split(np.arange(y.shape[0]), settings.n_blocks) if b.size]
        res = screen(an, cand, blocks, effective_rows(an), y)
        specs = {p.name: p for p in cls.PARAMETERS}
        start = {}
        for p, v in res.params.items():
            lo, hi = specs[p].bounds
            start[p] = float(np.clip(v, lo + 1e-6 * (hi - lo), hi - 1e-6 * (hi - lo)))
        fit_names = list(cand.fit)
        reuse = cand.reuse_hidden and not free_retune
    else:
        start = {}
        fit_names = [p.name for p in cls.PARAMETERS if not p.fixed and p.choices is None]
        reuse = False
    try:
        eff = effect_with(effect, start)
    except (TypeError, ValueError) as exc:
        raise DiscrepancyError(f"effect {effect!r} cannot be built: {exc}") from None
    trial = model + eff
    free = [f"{effect}.{p}" for p in fit_names] + free_retune
    if not free:
        raise DiscrepancyError(f"effect {effect!r} has no free parameter to fit")
    fr = fit_parameters(an, trial, free, max_nfev=max_nfev, reuse_hidden=reuse,
                        progress=progress)
    before = an.metrics()
    after_res = fl_res = an.flight.z - fr.zhat
    after = channel_metrics(an.band(after_res), an.measured_band, fl_res, an.mask, an.noise)
    written = None
    if out is not None:
        written = save_spec(fr.model, out, name=name or Path(out).stem,
                            description=f"{', '.join(model.effect_names)} + "
                            f"{effect} fitted on {an.flight.name}",
                            calibration=_calibration_after(start_spec, fr.model, effect,
                                                           flight, wind, an.flight.name,
                                                           misfit_flight, str(misfit_on)))
    return AddResult(effect, fr.model, fr, before, after, written, None if plugin is None
                     else str(plugin))
