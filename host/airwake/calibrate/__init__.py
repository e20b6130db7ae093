"""Calibration of the helicopter model's parameters against a still-air flight
(reference §5.3): the reference's particle swarm (eq 5.16) and a fast equation-error
least-squares fit, both on the same residuals (docs/calibration.md).

    from airwake.calibrate import calibrate
    from airwake.heli import save_spec
    result = calibrate("flight.parquet", model="table51", method="lsq")
    result.rms_before, result.rms_after          # (6,) per channel
    result.names, result.values, result.std      # free parameters, fit, 1-sigma
    result.notes                                 # identifiability report
    save_spec(result.model, "fitted.toml")       # atomic (temp file + rename)

Model-generated flights for tests and benches: `airwake.calibrate.synthetic`.
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

from airwake.calibrate.errors import CalibrationError
from airwake.lazy import lazy_exports

if TYPE_CHECKING:
    from airwake.calibrate.fit import FitResult

__all__ = ["CalibrationError", "FitResult", "calibrate", "load_flight", "model_error",
           "model_error_std"]
# numpy and the fit load on first use: `airwake --help` imports this package
__getattr__, __dir__ = lazy_exports(__name__, {"FitResult": "airwake.calibrate.fit"})


def load_flight(flight):
    """A FlightTable from a path; tables and DataFrames pass through."""
    if isinstance(flight, (str, os.PathLike)):
        from airwake.record.flight_table import load_flight_table

        return load_flight_table(flight)
    return flight


def _one_blas_thread(fn):
    """Run `fn` with BLAS on one thread: a fit is then the same to the bit on any machine
    and after whatever the process ran before. A multi-threaded BLAS sums in an order that
    depends on its thread count, and the least-squares path drifts with the last bits
    (its Jacobian is a finite difference): before this, the first calibration of a
    process ran scipy's BLAS (loaded on first use, after the residuals' one-thread limit
    was set up) on two threads and every later one on one, 0.6 % apart in a fitted
    inertia, and a campaign run twice in one process stored two different models for
    one content address. `single_blas_thread` lives in a module that imports
    scipy.linalg, so its BLAS is loaded before the limit applies."""
    import functools

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        from airwake.calibrate.hidden import single_blas_thread

        with single_blas_thread():
            return fn(*args, **kwargs)

    return wrapper


@_one_blas_thread
def calibrate(flight, model="table51", method: str = "lsq", params=None, *,
              window_s: float = 2.0, warmup_s: float = 1.0, max_windows: int | None = None,
              seed: int = 0, particles: int = 2000, iterations: int = 500,
              pso_windows: int | None = 16, spread: float = 0.5, max_nfev: int = 60,
              channel_scale=None, cutoff_hz: float | None = 6.0,
              progress: bool = False, yaw_gyro_effect: bool = False) -> FitResult:
    """Fit the model's free parameters to a flight (see docs/calibration.md).

    params: None (the non-fixed parameters this flight identifies, by subset selection:
    `params.identified_subset`) or names/globs (fitted as named). max_windows: use an
    evenly spaced subset of that many windows (None = the whole flight). cutoff_hz: the
    front end's zero-phase low-pass of every signal (the wind estimator's, so the model is
    fitted to what the estimator will compare it with; None or 0: the raw flight). The
    seed drives the PSO (initial swarm, r1/r2, the window subset) and nothing else.
    yaw_gyro_effect: where the flight shows a yaw gyro, add the catalogue's `yaw_gyro` to
    the fitted model with the gain its tail-servo capture measures (`_gyro_share`)."""
    import numpy as np

    from airwake.calibrate.envelope import flight_envelope, wind_trust
    from airwake.calibrate.params import identified_subset, select_parameters
    from airwake.calibrate.residuals import FlightData, WindowedPredictor, make_windows
    from airwake.heli import load_model
    from airwake.progress import Progress

    if method not in ("lsq", "pso"):
        raise CalibrationError(f"unknown method {method!r}; use 'lsq' or 'pso'")
    # the seconds before the first evaluation (the flight, the front end's filter, which
    # parameters it identifies) are a step of their own on a long flight
    prep = Progress("calibrate: preparing", 3, " steps", enabled=progress, min_interval_s=0)
    prep.update(0, "loading the flight")
    model = load_model(model)
    ft = load_flight(flight)
    free = select_parameters(model, params)
    if not free.any():
        raise CalibrationError("no free parameter to fit (every selected one is fixed)")
    data = FlightData.from_flight(model, ft, channel_scale=channel_scale)
    front = None
    if cutoff_hz:
        prep.update(1, f"{len(data)} samples; the front end's {cutoff_hz:g} Hz low-pass")
        data, front = _front_end(data, model, float(cutoff_hz), channel_scale)
    windows = make_windows(data, window_s, warmup_s)
    if max_windows is not None and max_windows < windows.n_windows:
        pick = np.unique(np.linspace(0, windows.n_windows - 1, max_windows).round().astype(int))
        windows = windows.subset(pick)
    pred = WindowedPredictor(model, data, windows)
    held = []
    if params is None:
        prep.update(2, "which parameters the flight identifies")
        # residuals low-passed at f_c and sampled at f_s are correlated over ~f_s/(2 f_c)
        corr = data_rate_over_band(data, front)
        free, held = identified_subset(model, pred, free, correlation_samples=corr)
    prep.finish(f"{int(free.sum())} parameters to fit")
    # the residual at the model the user started from, before any stage moves it (the
    # weighting stage below is a first fit: measured after it, "before" hid what it did)
    start_rms = pred.channel_rms(model.parameter_vector()[None])[0]
    start_values = model.parameter_vector()
    weighted_start = None
    if front is not None and channel_scale is None:
        model, scale = _reweight(model, pred, free, max_nfev, progress)
        data.scale = scale
        front["channel_scale"] = scale.tolist()
    if method == "lsq":
        from airwake.calibrate.lsq import fit_lsq

        bar = Progress("calibrate lsq", max_nfev, " evaluations", enabled=progress)
        result = fit_lsq(model, pred, free, max_nfev=max_nfev, progress=bar)
    else:
        from airwake.calibrate.pso import fit_pso

        bar = Progress("calibrate pso", iterations, " iterations", enabled=progress)
        result = fit_pso(model, pred, free, np.random.default_rng(seed), particles,
                         iterations, pso_windows, spread, progress=bar)
    bar.finish(f"rms {np.sqrt(np.mean(result.rms_after ** 2)):.4g}")
    if np.all(np.isfinite(start_rms)):
        weighted_start = result.rms_before
        result.rms_before = start_rms
        result.start = start_values[free]
    envelope = flight_envelope(data, model)
    result.notes[:0] = held
    # a yaw gyro between the rudder the model reads and the tail servo (calibrate.yaw_gyro)
    from airwake.calibrate.yaw_gyro import note as gyro_note
    from airwake.calibrate.yaw_gyro import yaw_gyro

    gyro = yaw_gyro(getattr(ft, "df", ft))
    line = gyro_note(gyro)
    if line:
        result.notes.append(line)
        _gyro_share(result, gyro, getattr(ft, "df", ft), cutoff_hz, yaw_gyro_effect)
    result.info.update(samples=int(len(data)), windows=int(windows.n_windows),
                       scored_samples=int(windows.n_scored), seed=int(seed),
                       held=list(held), front_end=front, envelope=envelope,
                       rms_after_weighting_fit=None if weighted_start is None else
                       [float(v) for v in weighted_start],
                       wind_trust=wind_trust(envelope), yaw_gyro=gyro)
    return result


def _gyro_share(result, gyro: dict, df, cutoff_hz, add: bool) -> None:
    """The gyro's share of the fitted yaw damping (`calibrate.yaw_gyro.effect_gain`) into
    `gyro` (the report's `yaw_gyro`), and the `yaw_gyro` effect with its gain into the
    fitted model when `add`."""
    from airwake.calibrate.yaw_gyro import aero_yaw_damping, effect_gain

    aero = aero_yaw_damping(df, gyro, cutoff_hz)
    share = None if aero is None else effect_gain(result.model, gyro, aero)
    if share is None:
        return
    gyro.update(aero_damping_1_s=aero["damping_1_s"], aero_explained=aero["explained"],
                **share)
    g = share["gain_rad_per_rad_s"]
    what = (f"the flight's tail-servo pulses put the airframe's aerodynamic yaw damping at "
            f"{aero['damping_1_s']:.2f} 1/s, the fitted model's at "
            f"{share['model_damping_1_s']:.2f}: the rest is the gyro's, on the inertial rate")
    if add and g < 0.0 and "yaw_gyro" not in result.model:
        from airwake.heli.effects.catalogue import YawGyro

        result.model = result.model + YawGyro(gain_rad_per_rad_s=g)
        result.notes.append(f"{what}; yaw_gyro added with gain {g:+.4f} rad per rad/s (the "
                            "model's answer to the air's rotation about z is the "
                            "airframe's)")
    elif g < 0.0:
        result.notes.append(f"{what}; --yaw-gyro adds the catalogue's yaw_gyro with gain "
                            f"{g:+.4f} rad per rad/s (docs/calibration.md)")


def model_error_std(model, flight, *, cutoff_hz: float = 6.0, window_s: float = 2.0,
                    warmup_s: float = 1.0):
    """(6,) the model's error per channel on a still-air flight, after the wind
    estimator's front end (`cutoff_hz` low-pass) and over the same windows a calibration
    scores: what `airwake calibrate` writes as `[calibration] model_error_std` for the
    model it fitted, here for any model (one `airwake model add` made, say), so the wind
    estimator's noise floor always belongs to the model it runs."""
    return model_error(model, flight, cutoff_hz=cutoff_hz, window_s=window_s,
                       warmup_s=warmup_s)[0]


def model_error(model, flight, *, cutoff_hz: float = 6.0, window_s: float = 2.0,
                warmup_s: float = 1.0):
    """((6,), (6,)): `model_error_std`, and its steady part — `[calibration]
    model_error_offset`, the RMS over blocks of the flight (`residuals.OFFSET_BLOCK_S`) of
    each block's mean residual: a body-fixed force or moment (the flight condition's model
    error, the accelerometers' turn-on bias) the wind estimator cannot tell from a steady
    wind."""
    from airwake.calibrate.residuals import FlightData, WindowedPredictor, make_windows
    from airwake.heli import load_model

    model = load_model(model)
    data = FlightData.from_flight(model, load_flight(flight))
    if cutoff_hz:
        data, _ = _front_end(data, model, float(cutoff_hz), None)
    pred = WindowedPredictor(model, data, make_windows(data, window_s, warmup_s))
    rms, offset = (v[0] for v in pred.channel_stats(model.parameter_vector()[None]))
    if not all(map(math.isfinite, [*rms, *offset])):
        raise CalibrationError(f"{getattr(flight, 'path', flight)}: the model's prediction "
                               "is not finite on this flight; no model error to report")
    return rms, offset


REWEIGHT_WINDOWS = 16


def data_rate_over_band(data, front) -> float:
    """Samples per independent residual: f_s / (2 f_c) after the front end, else 1."""
    if not front:
        return 1.0
    return max(1.0 / (data.dt * 2.0 * front["cutoff_hz"]), 1.0)


def _reweight(model, pred, free, max_nfev, progress):
    """Channel weights from the data: a first least-squares fit on an evenly spaced
    subset of the windows, then each channel's scale = its residual RMS there (the
    maximum-likelihood weights when each channel's misfit variance is unknown). Returns
    the first fit's model (the start of the full fit) and the scales."""
    import numpy as np

    from airwake.calibrate.lsq import fit_lsq
    from airwake.calibrate.residuals import WindowedPredictor
    from airwake.progress import Progress

    win = pred.windows
    pick = np.unique(np.linspace(0, win.n_windows - 1, min(REWEIGHT_WINDOWS, win.n_windows))
                     .round().astype(int))
    coarse = WindowedPredictor(model, pred.data, win.subset(pick))
    bar = Progress("calibrate lsq (weights)", max_nfev, " evaluations", enabled=progress)
    first = fit_lsq(model, coarse, free, max_nfev=max_nfev, coarse_fraction=0.0,
                    progress=bar)
    bar.finish()
    pred.evaluations += coarse.evaluations
    scale = np.maximum(first.rms_after, 1e-3 * np.max(first.rms_after))
    return first.model, scale


def _front_end(data, model, cutoff_hz: float, channel_scale):
    """The low-passed flight at its own rate (no decimation: the windowed predictor's
    fixed-Jacobian rotor step needs the full rate) and its channel scales: the raw
    white-noise scale times sqrt(2 f_c / f_s), the share of white noise the filter passes,
    unless given."""
    import numpy as np

    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.prefilter import prefilter

    fs = 1.0 / data.dt
    try:
        pre = prefilter(data, model, cutoff_hz, fs)
    except WindEstimationError as exc:
        raise CalibrationError(str(exc)) from None
    out = pre.data
    if channel_scale is None:
        out.scale = data.scale * np.sqrt(min(2.0 * cutoff_hz / fs, 1.0))
    return out, {"cutoff_hz": float(cutoff_hz), "rate_hz": float(fs)}
