"""Wind estimation over a flight: run an estimator, write the estimate, score it.

    est = estimate_wind("flight.parquet", model="fitted.toml")          # the smoother
    est = estimate_wind("flight.parquet", model="fitted.toml", method="apf", seed=0)
    est = estimate_wind("flight.parquet", method="net", net="wind.pt")  # a §4.6 wind net
    est.df            # t_s, wind_vx_m_s ... wind_wz_rad_s, *_std (+ ess, resampled, skipped)
    score_wind(est.df, flight_df)   # error, correlation, 90 % coverage vs truth_wind_*
    write_wind(est, "wind.parquet")

Output columns (one row per estimator sample: the front end's decimated samples, 15 Hz
for the smoother by default; match other tables by `t_s`): `t_s`; the posterior mean
`wind_vx_m_s`, `wind_vy_m_s`, `wind_vz_m_s`, `wind_wx_rad_s`, `wind_wy_rad_s`,
`wind_wz_rad_s` (eq 5.3, body axes, at the main-rotor hub; w is the rotation
coefficient, curl = 2 w) and their posterior std `<name>_std` (the mean-flow ones
include the INS velocity error); the APF adds `ess`, `resampled` and `skipped`. A wind
net (`airwake.nets.wind_net`, method "net") estimates per flight sample (150 Hz) and has
no posterior: its `<name>_std` is the net's RMS on its own validation blocks (the model
card), a typical error rather than a per-sample one. Parquet metadata (key "airwake"):
method, model spec (or net file), flight, front end, the learned prior and channel noise
(smoother) or particles, sigma, resampler, seed (APF) or the net's card (net).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from airwake.estimate.prefilter import CUTOFF_HZ, RATE_HZ
from airwake.heli.model import WIND_NAMES
from airwake.record.flight_table import TRUTH_WIND

# Reference Table 5.3: error statistics of the APF wind estimate (indoor fan flow).
TABLE_5_3 = {
    "wind_vx_m_s": (0.0372, 0.4761),
    "wind_vy_m_s": (-0.1091, 0.9299),
    "wind_vz_m_s": (0.1188, 0.5503),
    "wind_wx_rad_s": (0.1498, 0.1448),
    "wind_wy_rad_s": (0.0282, 0.0816),
    "wind_wz_rad_s": (-0.0072, 0.0645),
}
SCORE_BURN_IN_S = 2.0  # the estimate's first seconds (the smoother's start) not scored


@dataclass
class WindEstimate:
    df: object  # pandas DataFrame (see module docstring)
    metadata: dict = field(default_factory=dict)
    seconds: float = 0.0
    smoother: object = None  # the WindSmoother (method "smoother"): for the bound
    result: object = None  # its SmootherResult


METHODS = ("smoother", "apf", "net")
# how the smoother holds the model's steady misfit per channel (`model_error_offset`):
# "consider", a steady offset it does not estimate, whose effect widens the intervals
# (forces only); "states", Gauss-Markov bias states it estimates beside the wind
MODEL_ERROR_MODES = ("consider", "states")
# The wind is the air velocity over the ground, so the INS velocity error goes one to one
# into v (not into w): measured on each flight against its GNSS velocity
# (`airwake.estimate.ins_error`), or given by the user; the VN-200 datasheet's 0.05 m/s
# only when the flight has no GNSS velocity, and the metadata says so.
APF_RATE_HZ = 30.0
# what a model that does not fly a flight raises (a plugin's own error, a singular rotor)
MODEL_FAILURES = (ArithmeticError, ValueError, RuntimeError, TypeError, KeyError,
                  IndexError, np.linalg.LinAlgError)


def estimate_wind(flight, model="table52", method: str = "smoother", *,
                  cutoff_hz: float | None = None, rate_hz: float | None = None,
                  em_passes: int | None = None, airspeed_m_s: float | None = None,
                  ins_velocity_std: float | None = None,
                  accel_bias_std: float | None = None,
                  n_particles: int = 2000, sigma: float = 0.5,
                  resampler: str = "systematic", ess_threshold: float | None = None,
                  jitter: float = 0.2, seed: int = 0, process_std=None, init_half_width=None,
                  channel_scale=None, steps: int | None = None,
                  progress: bool = False, net=None, interval_model=None,
                  anchor=None, calibration: dict | None = None,
                  rotation_from_mean_flow: bool = True,
                  model_error: str = "consider") -> WindEstimate:
    """Estimate the eq 5.3 wind over a flight table (path, FlightTable or DataFrame).

    method "smoother" (default): the iterated EKF/RTS smoother with the Gauss-Markov wind
    prior learned from the flight (`airwake.estimate.smoother`); "apf": the reference's
    active particle filter (eq 5.17; resampler 'systematic' on ESS < N/2, 'stratified',
    or 'roulette' / 'multinomial' = the reference, every sample unless ess_threshold is
    given). Both read the front end's low-passed, decimated samples
    (`airwake.estimate.prefilter`: cutoff_hz 6, rate_hz 15 for the smoother and 30 for the
    APF; cutoff_hz=0 feeds the APF the raw flight as the reference did); "net": a direct
    wind network (`net`: its .pt file or the loaded net; `model` unused) per flight sample.
    ins_velocity_std: the INS velocity error (1 sigma, m/s) added to the mean-flow std;
    None (default) measures it on the flight against its GNSS velocity
    (`airwake.estimate.ins_error`). accel_bias_std (smoother): the INS's residual
    accelerometer bias on this flight (1 sigma per axis, m/s^2, from its data sheet), a
    steady force joined to the model's `model_error_offset` in the intervals.
    interval_model (net): a calibrated model whose smoother's estimate on the same flight
    widens the net's mean-flow interval by the wind's fast part the net cannot see
    (`airwake.estimate.net_interval`); the smoother's options above apply to it, its EM
    passes `net_interval.INTERVAL_EM_PASSES` unless em_passes is given.
    anchor (smoother): a wind table made without the model (`--method net` with a
    still-air net; path or DataFrame) whose mean flow and its std are taken as a
    measurement of v at every sample, so the model reads the rotation given that mean
    flow (`WindSmoother`'s `anchor`).
    calibration (smoother): the [calibration] table to read instead of the spec's (the
    one `airwake calibrate` is about to write); the spec's `still_air_wind_error` joins
    the std (`still_air_wind_error` below).
    rotation_from_mean_flow (smoother): the EM sets the turbulence std of w_x and w_y from
    the mean flow's (`airwake.estimate.smoother`); False learns it as the others.
    model_error (smoother): how the model's steady misfit (the spec's
    `model_error_offset`, with accel_bias_std on the accelerometers) enters: "consider"
    (default) keeps it out of the estimate and widens the intervals by what it does to it
    (forces only); "states" estimates it per channel as Gauss-Markov bias states beside
    the wind (correlation time: the block it was measured over,
    `calibrate.residuals.OFFSET_BLOCK_S`) — right for a steady force with the mean flow
    pinned by an anchor (an INS's accelerometer bias on a model that fits); on the
    blade-element airframe not better than "consider" (docs/wind-estimation.md "The
    model's slow misfit as states")."""
    from airwake.calibrate import CalibrationError, load_flight
    from airwake.calibrate.residuals import FlightData
    from airwake.estimate.errors import WindEstimationError
    from airwake.heli import load_model, spec_calibration
    from airwake.record.flight_table import flight_fingerprint

    if method not in METHODS:
        raise WindEstimationError(f"unknown method {method!r}; use one of {list(METHODS)}")
    from airwake.estimate.ins_error import ins_velocity_error

    if ins_velocity_std is not None and not (np.isfinite(ins_velocity_std)
                                             and ins_velocity_std >= 0):
        raise WindEstimationError(
            f"--ins-velocity-std {ins_velocity_std!r}: must be a number >= 0")
    if accel_bias_std is not None and not (np.isfinite(accel_bias_std)
                                           and accel_bias_std >= 0):
        raise WindEstimationError(
            f"--accel-bias-std {accel_bias_std!r}: must be a number >= 0 (m/s^2)")
    if accel_bias_std is not None and method != "smoother":
        raise WindEstimationError("--accel-bias-std widens the smoother's intervals: it is "
                                  f"for --method smoother, not {method}")
    if (method == "net") != (net is not None):
        raise WindEstimationError("--method net needs --net WIND.pt (and --net needs "
                                  "--method net)")
    if not rotation_from_mean_flow and method != "smoother":
        raise WindEstimationError("--rotation-sigma learned sets the smoother's prior: it is "
                                  f"for --method smoother, not {method}")
    if anchor is not None and method != "smoother":
        raise WindEstimationError(f"--anchor is for --method smoother, not {method}")
    if model_error not in MODEL_ERROR_MODES:
        raise WindEstimationError(f"--model-error {model_error!r}: use one of "
                                  f"{list(MODEL_ERROR_MODES)}")
    if interval_model is not None and method != "net":
        raise WindEstimationError("--interval-model widens a wind net's interval: it is for "
                                  f"--method net, not {method}")
    ft = load_flight(flight)
    ins = ins_velocity_error(getattr(ft, "df", ft), getattr(ft, "metadata", None) or {},
                             ins_velocity_std)
    ins_velocity_std = ins.std_m_s
    if method == "net":
        est = _run_net(ft, net, ins_velocity_std)
        est.metadata.update(ins.to_dict())
        if interval_model is not None:
            from airwake.estimate.net_interval import INTERVAL_EM_PASSES

            ref = estimate_wind(ft, model=interval_model, cutoff_hz=cutoff_hz,
                                rate_hz=rate_hz, em_passes=(INTERVAL_EM_PASSES
                                                            if em_passes is None else em_passes),
                                airspeed_m_s=airspeed_m_s, ins_velocity_std=ins_velocity_std,
                                channel_scale=channel_scale, progress=progress)
            _widen_by_model(est, ref, interval_model)
        return est
    heli = load_model(model)
    try:
        data = FlightData.from_flight(heli, ft, channel_scale=channel_scale)
    except CalibrationError as exc:
        raise WindEstimationError(str(exc)) from None
    meta = {
        "source": "airwake wind estimate",
        "method": method,
        "flight": str(getattr(ft, "path", "") or ""),
        "model_spec": str(model) if not hasattr(model, "effects") else "<model>",
        "frame": "body axes at the main-rotor hub (eq 5.3)",
        **ins.to_dict(),
        "flight_fingerprint": flight_fingerprint(getattr(ft, "df", ft)),
    }
    smoother = result = None
    cutoff = CUTOFF_HZ if cutoff_hz is None else cutoff_hz
    if method == "smoother":
        cal = spec_calibration(model) if calibration is None else calibration
        floor = model_error_floor(model, table=cal)
        offset = model_error_floor(model, "model_error_offset", table=cal)
        meta["model_error_std"] = None if floor is None else floor.tolist()
        meta["model_error_offset"] = None if offset is None else offset.tolist()
        meta["accel_bias_std_m_s2"] = accel_bias_std
        if accel_bias_std:
            # the flight's own sensor bias and the model's steady misfit, independent
            offset = np.zeros(6) if offset is None else offset.copy()
            offset[:3] = np.hypot(offset[:3], accel_bias_std)
        # (read before the run: a bad table costs no run)
        plain_g = _still_air_excess(model, cal, anchored=False)
        anchored_g = _still_air_excess(model, cal, anchored=True)
        meta["model_error"] = model_error
        df, extra, seconds, smoother, result = _run_smoother(
            heli, data, cutoff, RATE_HZ if rate_hz is None else rate_hz, em_passes,
            airspeed_m_s, ins_velocity_std, progress, floor, offset, anchor,
            rotation_from_mean_flow, model_error)
        if anchor is not None:
            meta["anchor"] = str(anchor) if not hasattr(anchor, "columns") else "<table>"
        excess = anchored_g if anchor is not None else plain_g
        meta[STILL_AIR_KEY] = None if excess is None else excess.tolist()
        if excess is not None:
            g = np.broadcast_to(excess, (len(df), 6))
            if anchor is not None:
                # where the anchor has a gap the estimate there is the plain smoother's
                gap = ~smoother.anchor[2]
                g = np.where(gap[:, None], plain_g, excess)
                meta["still_air_wind_error_plain_rows"] = int(gap.sum())
            for j, name in enumerate(WIND_NAMES):
                df[f"{name}_std"] = np.hypot(df[f"{name}_std"].to_numpy(), g[:, j])
    else:
        df, extra, seconds = _run_apf(
            heli, data, cutoff,
            APF_RATE_HZ if rate_hz is None else rate_hz, ins_velocity_std, n_particles,
            sigma, resampler, ess_threshold, jitter, seed, process_std, init_half_width,
            channel_scale, steps, progress)
    meta.update(extra)
    meta["calibration_envelope"] = envelope_check(model, data, heli, df)
    span = float(df["t_s"].iloc[-1] - df["t_s"].iloc[0]) if len(df) > 1 else 0.0
    meta["seconds"] = seconds
    meta["realtime_factor"] = span / seconds if seconds > 0 else 0.0
    return WindEstimate(df, meta, seconds, smoother, result)


def model_error_floor(spec, key: str = "model_error_std",
                      table: dict | None = None) -> np.ndarray | None:
    """(6,) the model's error on its still-air calibration flight after the front end
    (the spec's `[calibration] model_error_std`, written by `airwake calibrate`; with
    key="model_error_offset" the part of it that holds for a window), or None for a spec
    without it (a shipped table, a model object, an older calibration). `table`: that
    [calibration] table instead of the spec's."""
    from airwake.heli import spec_calibration

    cal = (spec_calibration(spec) if table is None else table) or {}
    values = cal.get(key)
    if values is None:
        return None
    return _six_at_least_zero(values, f"{spec}: [calibration] {key}", "channel")


def _six_at_least_zero(values, where: str, per: str) -> np.ndarray:
    """(6,) `values` as floats, or WindEstimationError naming `where` and the values."""
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        a = np.zeros(0)
    if a.shape != (6,) or np.any(~np.isfinite(a)) or np.any(a < 0):
        from airwake.estimate.errors import WindEstimationError

        raise WindEstimationError(f"{where} = {values!r}: expected 6 numbers >= 0 (one per "
                                  f"{per})")
    return a


STILL_AIR_KEY = "still_air_wind_error"
STILL_AIR_MODES = ("smoother", "anchored")
# [calibration] key of the plain smoother's steady still-air error, channel by channel
STILL_AIR_BIAS_KEY = "still_air_wind_bias"


def still_air_wind_error(model, flight, calibration: dict | None = None) -> dict:
    """What the smoother's intervals miss on a still-air flight, where the whole 6-D wind
    is known to be zero: `[calibration.still_air_wind_error]`, written by `airwake
    calibrate` and `airwake model add` on the flight the model was fitted on.

    Model error is not only a channel-noise floor and a steady offset (both in the
    posterior already): a misfit coloured at the wind's time scales reads as turbulence
    through the model's sensitivities, and where the model's sensitivity to a component
    is not the airframe's (the rotation's, on a teetering head it does not hold), the
    posterior claims information the flight does not carry. On still air that misfit is
    the whole estimate. Per component, the RMS of the estimate beyond the posterior's
    own std, sqrt(max(0, mean(e^2) - mean(std^2))) after `SCORE_BURN_IN_S`, joins the std
    of every later estimate in quadrature (`estimate_wind`; the estimate itself does not
    change). Measured twice, as the estimate is made: "smoother" (the plain smoother)
    and "anchored" (the mean flow anchored on the still air's zero, known to the INS's
    velocity error). `calibration`: the model's [calibration] table (None: the spec's own);
    its `model_error_std` / `model_error_offset` apply, its old `still_air_wind_error` not.
    The estimator runs with its default settings (front end, EM passes) but one: the
    rotation's turbulence std is learned on its own, not from the mean flow's
    (`rotation_from_mean_flow=False`), which in still air would be near zero and hide the
    misfit the model reads as rotation (on the bench model, anchored: w_x / w_y 0.12 /
    0.35 1/s free, 0 / 0 tied, while at sea its w_y bias is -0.2 ... -0.5).
    Returns {"smoother": [6], "anchored": [6]}; WindEstimationError where the smoother
    cannot run on the flight."""
    plain, anchored = _still_air_runs(model, flight, calibration)
    return {"smoother": excess_error(plain.df), "anchored": excess_error(anchored.df)}


def still_air_report(model, flight, calibration: dict | None = None) -> tuple[dict, dict]:
    """(`still_air_wind_error`'s table, `wind_bias_by_channel` of its plain run, or None
    where that cannot be measured): what `airwake calibrate` and `airwake model add`
    write, from one pair of smoother runs (the rotation's prior learned on its own, as
    `still_air_wind_error` runs them)."""
    from airwake.estimate.errors import WindEstimationError

    plain, anchored = _still_air_runs(model, flight, calibration)
    excess = {"smoother": excess_error(plain.df), "anchored": excess_error(anchored.df)}
    try:
        bias = wind_bias_by_channel(plain)
    except (WindEstimationError, *MODEL_FAILURES):
        bias = None  # a diagnostic: the excess, which the intervals need, is kept
    return excess, bias


def _still_air_runs(model, flight, calibration):
    """The plain and the anchored estimate on a still-air flight (still_air_wind_error)."""
    import pandas as pd

    from airwake.calibrate import load_flight
    from airwake.heli import spec_calibration

    if calibration is None:
        calibration = spec_calibration(model) or {}
    table = {k: v for k, v in calibration.items() if k != STILL_AIR_KEY}
    ft = load_flight(flight)
    plain = estimate_wind(ft, model=model, calibration=table, rotation_from_mean_flow=False)
    t = np.asarray(plain.df["t_s"], float)
    # still air: the mean flow is zero, as well as the INS knows the helicopter's
    # velocity (the smoother adds that error itself; a std must be > 0)
    ins = max(float(plain.metadata["ins_velocity_std_m_s"]), 1e-3)
    zero = pd.DataFrame({"t_s": t, **{n: np.zeros_like(t) for n in WIND_NAMES[:3]},
                         **{f"{n}_std": np.full_like(t, ins) for n in WIND_NAMES[:3]}})
    anchored = estimate_wind(ft, model=model, calibration=table, anchor=zero,
                             rotation_from_mean_flow=False)
    return plain, anchored


def largest_shares(bias: dict, top: int = 2) -> list[tuple[str, float, float, list]]:
    """Per component of a `wind_bias_by_channel` table: (component, steady error, the
    shares' sum, [(channel, share)] for the `top` largest shares by magnitude)."""
    chans = bias["channels"]
    out = []
    for j, (name, shares) in enumerate(bias["by_channel"].items()):
        order = sorted(range(len(chans)), key=lambda k: -abs(shares[k]))[:top]
        out.append((name, bias["error_mean"][j], bias["explained"][j],
                    [(chans[k], shares[k]) for k in order]))
    return out


def wind_bias_by_channel(est, wind=None, burn_in_s: float | None = None) -> dict:
    """Where a smoother estimate's steady error comes from, channel by channel, on a
    flight whose wind is known: zero (still air, `wind` None) or `wind` (n, 6) at the
    estimate's rows.

    The smoother reads six wind components from six channels, so a steady misfit of the
    model on any channel lands in the wind, through the inverse of the model's
    sensitivities. m_j, the model's mean misfit on channel j at the known wind (measured
    minus `WindSmoother.open_loop`), moves the smoothed estimate by S_kcj m_j at sample k
    (`WindSmoother.offset_sensitivity`, exact for the last pass's linearisation); the mean
    over the samples after `burn_in_s` (default `SCORE_BURN_IN_S`) is channel j's share
    of component c's steady error. What the shares do not explain is the misfit that
    changes along the flight (its regimes). Returns {"channels": the six channel names,
    "misfit_mean": (6,), "error_mean": (6,) the estimate's mean error, "explained": (6,)
    the shares' sum, "by_channel": {component: (6,) shares}} (lists of floats).
    WindEstimationError for an estimate with no smoother (the APF's, the net's)."""
    from airwake.estimate.errors import WindEstimationError
    from airwake.heli.context import MEAS_CHANNELS

    sm = getattr(est, "smoother", None)
    if sm is None:
        raise WindEstimationError("wind_bias_by_channel: needs the smoother's estimate "
                                  "(its sensitivities); this one has none")
    t = np.asarray(est.df["t_s"], float)
    known = np.zeros((t.size, 6)) if wind is None else np.asarray(wind, float)
    if known.shape != (t.size, 6):
        raise WindEstimationError(f"wind_bias_by_channel: the known wind is {known.shape}, "
                                  f"the estimate has {t.size} rows of 6 components")
    if not np.all(np.isfinite(known)):
        raise WindEstimationError("wind_bias_by_channel: the known wind has non-finite "
                                  f"values in {int(np.sum(~np.isfinite(known).all(1)))} rows")
    misfit = sm.pre.data.z - sm.open_loop(known)
    burn = SCORE_BURN_IN_S if burn_in_s is None else float(burn_in_s)
    est_w = np.column_stack([np.asarray(est.df[n], float) for n in WIND_NAMES])
    keep = (t >= t[0] + burn) & np.all(np.isfinite(misfit), 1) & np.all(np.isfinite(est_w), 1)
    if not keep.any():
        raise WindEstimationError("wind_bias_by_channel: no sample with a finite misfit "
                                  "after the burn-in")
    m = misfit[keep].mean(0)
    sens = sm.offset_sensitivity()[keep]
    if not np.isfinite(sens).all(2).all(1).any():
        raise WindEstimationError("wind_bias_by_channel: the smoother made no channel "
                                  "update after the burn-in (no sensitivity)")
    shares = np.nanmean(sens * m[None, None, :], axis=0)
    return {"channels": list(MEAS_CHANNELS), "misfit_mean": m.tolist(),
            "error_mean": (est_w - known)[keep].mean(0).tolist(),
            "explained": shares.sum(1).tolist(),
            "by_channel": {n: shares[c].tolist() for c, n in enumerate(WIND_NAMES)}}


def excess_error(wind_df, truth=None, burn_in_s: float | None = None) -> list[float]:
    """(6,) per component, the estimate's error RMS beyond its posterior std:
    sqrt(max(0, mean(e^2) - mean(std^2))) over the samples after `burn_in_s` (default
    `SCORE_BURN_IN_S`) where both are finite; e = estimate - truth (zero: still air)."""
    burn = SCORE_BURN_IN_S if burn_in_s is None else float(burn_in_s)
    t = np.asarray(wind_df["t_s"], float)
    keep = t >= t[0] + burn if t.size else np.zeros(0, bool)
    out = []
    for j, name in enumerate(WIND_NAMES):
        e = np.asarray(wind_df[name], float)[keep]
        if truth is not None:
            e = e - np.asarray(truth, float)[keep, j]
        s = np.asarray(wind_df[f"{name}_std"], float)[keep]
        ok = np.isfinite(e) & np.isfinite(s)
        if not ok.any():
            out.append(0.0)
            continue
        out.append(float(np.sqrt(max(np.mean(e[ok] ** 2) - np.mean(s[ok] ** 2), 0.0))))
    return out


def _still_air_excess(spec, cal: dict | None, anchored: bool) -> np.ndarray | None:
    """(6,) the spec's `still_air_wind_error` for the estimate being made (anchored or
    not), or None for a spec without it."""
    from airwake.estimate.errors import WindEstimationError

    entry = (cal or {}).get(STILL_AIR_KEY)
    if entry is None:
        return None
    where = str(spec) if isinstance(spec, (str, Path)) else "the model's [calibration]"
    if not isinstance(entry, dict):
        raise WindEstimationError(f"{where}: [calibration] {STILL_AIR_KEY} = {entry!r}: "
                                  f"expected a table with {' and '.join(STILL_AIR_MODES)}")
    mode = STILL_AIR_MODES[1] if anchored else STILL_AIR_MODES[0]
    return _six_at_least_zero(entry.get(mode), f"{where}: [calibration.{STILL_AIR_KEY}] "
                              f"{mode}", "component")


def envelope_check(spec, data, heli, df) -> dict | None:
    """How much of the flight's air velocity (estimated wind - body velocity, body axes)
    lies inside the envelope the model was calibrated over (the spec's [calibration]
    table, `airwake.calibrate.envelope`); None when the spec has none."""
    from airwake.calibrate.envelope import envelope_fraction
    from airwake.heli import spec_calibration

    cal = spec_calibration(spec)
    if not cal or "envelope" not in cal:
        return None
    t = np.asarray(df["t_s"], float)
    vel = np.column_stack([np.interp(t, data.t, data.x[:, heli.state_index(s)])
                           for s in ("vel_u_m_s", "vel_v_m_s", "vel_w_m_s")])
    air = np.column_stack([np.asarray(df[n], float) for n in WIND_NAMES[:3]]) - vel
    inside = envelope_fraction(cal["envelope"], air)
    return {"inside_fraction": {a: float(v) for a, v in zip("xyz", inside, strict=True)},
            "trusted": cal.get("trusted", {}),
            "calibration_flight": cal.get("flight")}


def _frame(t, mean, std, ins_velocity_std, extra_cols=None):
    """The output table: posterior mean and std per component; the INS velocity error
    (not observable from the dynamics: it shifts the air velocity one to one) is added
    in quadrature to the mean-flow components' std."""
    import pandas as pd

    std = np.array(std, dtype=float)
    std[:, :3] = np.sqrt(std[:, :3] ** 2 + ins_velocity_std**2)
    cols = {"t_s": t}
    for i, name in enumerate(WIND_NAMES):
        cols[name] = mean[:, i]
    for i, name in enumerate(WIND_NAMES):
        cols[f"{name}_std"] = std[:, i]
    cols.update(extra_cols or {})
    return pd.DataFrame(cols)


def _anchor_at(anchor, t: np.ndarray, ins_velocity_std: float):
    """(mean, std) (n, 3) of a wind table's mean flow at times t (NaN outside it and
    where it has none: a dropout); the INS velocity error its std carries (its metadata's
    `ins_velocity_std_m_s`, else this flight's) taken out again — the smoother reads the
    same INS and adds it to its own output — and where its std is not above that error,
    the std kept as it is (never a narrower measurement than the table says)."""
    from airwake.estimate.errors import WindEstimationError
    from airwake.record.flight_table import FlightTableError, read_flight_table

    cols = [c for n in WIND_NAMES[:3] for c in (n, f"{n}_std")]
    if hasattr(anchor, "columns"):
        df, meta = anchor, {}
    else:
        try:
            df, meta = read_flight_table(anchor)
        except FlightTableError as exc:
            raise WindEstimationError(f"--anchor: {exc}") from None
    missing = [c for c in ("t_s", *cols) if c not in df.columns]
    if missing:
        raise WindEstimationError(f"--anchor {anchor}: not a wind table (missing {missing})")
    ta = np.asarray(df["t_s"], dtype=float)
    if ta.size < 2 or not np.all(np.isfinite(ta)) or not np.all(np.diff(ta) > 0):
        raise WindEstimationError(f"--anchor {anchor}: t_s must be finite and increase "
                                  "over 2+ samples")
    mean = np.column_stack([np.interp(t, ta, np.asarray(df[n], float), np.nan, np.nan)
                            for n in WIND_NAMES[:3]])
    std = np.column_stack([np.interp(t, ta, np.asarray(df[f"{n}_std"], float), np.nan,
                                     np.nan) for n in WIND_NAMES[:3]])
    ins = meta.get("ins_velocity_std_m_s", ins_velocity_std)
    ins = float(ins) if isinstance(ins, int | float) and np.isfinite(ins) else ins_velocity_std
    var = std**2 - ins**2
    with np.errstate(invalid="ignore"):
        std = np.where(var > 0, np.sqrt(np.maximum(var, 0.0)), std)
    return mean, std


def _run_smoother(heli, data, cutoff_hz, rate_hz, em_passes, airspeed_m_s, ins_velocity_std,
                  progress, noise_floor=None, offset_std=None, anchor=None,
                  rotation_from_mean_flow=True, model_error="states"):
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.prefilter import prefilter
    from airwake.estimate.smoother import ITERATIONS, LEARN, WindSmoother
    from airwake.estimate.wind_prior import AIRSPEED_M_S, WindPrior
    from airwake.progress import Progress

    if cutoff_hz <= 0:
        raise WindEstimationError("--cutoff-hz 0 (no front end) is for --method apf only: "
                                  "the smoother needs the low-passed, decimated samples")
    pre = prefilter(data, heli, cutoff_hz, rate_hz)
    radius = _rotor_radius(heli)
    prior = WindPrior.from_physics(radius, AIRSPEED_M_S if airspeed_m_s is None
                                   else airspeed_m_s)
    passes = ITERATIONS if em_passes is None else int(em_passes)
    if anchor is not None:
        anchor = _anchor_at(anchor, pre.data.t, ins_velocity_std)
    channel_bias = None
    if model_error == "states" and offset_std is not None and np.any(
            np.asarray(offset_std, dtype=float) > 0):
        from airwake.calibrate.residuals import OFFSET_BLOCK_S

        # the steady misfit is estimated, not considered: no consider term for it below
        channel_bias = (np.asarray(offset_std, dtype=float), OFFSET_BLOCK_S)
        offset_std = None
    try:
        learn = LEARN if rotation_from_mean_flow else tuple(
            x for x in LEARN if x != "rotation_from_mean_flow")
        sm = WindSmoother(heli, pre, prior, iterations=passes, noise_floor=noise_floor,
                          anchor=anchor, learn=learn, channel_bias=channel_bias)
    except MODEL_FAILURES as exc:
        raise WindEstimationError(f"{data.source}: {exc}") from None
    bar = Progress("wind estimate (smoother)", passes, " passes", enabled=progress)
    try:
        res = sm.run(bar)
    except MODEL_FAILURES as exc:
        # a model that does not fly this flight (a plugin that raises, a singular rotor)
        raise WindEstimationError(f"{data.source}: the model failed on this flight: "
                                  f"{type(exc).__name__}: {exc}") from None
    bad = ~np.all(np.isfinite(res.mean) & np.isfinite(res.std), axis=1)
    if bad.any():
        raise WindEstimationError(
            f"{data.source}: the model's prediction is not finite from t = "
            f"{res.t[np.argmax(bad)]:.2f} s on ({int(bad.sum())} samples): check the model "
            "spec's parameters and the flight's units")
    span = float(res.t[-1] - res.t[0]) if res.t.size > 1 else 0.0
    bar.finish(f"{span / max(res.seconds, 1e-9):.1f} x real time")
    std = res.std
    offset_part = None
    if offset_std is not None:
        # the model's steady force misfit (a body-fixed force in a flight condition, the
        # accelerometers' turn-on bias) moves the estimate as a steady wind would: the
        # posterior does not know of it, so its effect on the estimate joins the std. The
        # angular channels' steady misfits are left out: they widen rotation intervals
        # that already hold the truth (0.84-1.00 measured on the blade-element ship
        # flights) and change the mean flow's little (b15 v_x coverage 0.77 -> 0.80)
        forces = np.asarray(offset_std, dtype=float).copy()
        forces[3:] = 0.0
        offset_part = sm.offset_std(forces)
        std = np.sqrt(std**2 + offset_part**2)
    anchor_sigma = None
    if anchor is not None:
        # the posterior fuses the anchor with the model's own reading of the mean flow,
        # which is what the anchor is there to replace (biased on an airframe the model
        # does not fit): the model does not narrow the anchor's interval
        std = std.copy()
        std[:, :3] = np.fmax(std[:, :3], anchor[1])
        # and the rotation read given it carries its error, which the per-sample update
        # takes as white: its typical std as a steady offset ("consider")
        anchor_sigma = np.nanmedian(anchor[1], axis=0)
        part = sm.anchor_offset_std(anchor_sigma)
        std[:, 3:] = np.sqrt(std[:, 3:] ** 2 + part[:, 3:] ** 2)
    df = _frame(res.t, res.mean, std, ins_velocity_std)
    extra = {
        "front_end": {"cutoff_hz": pre.cutoff_hz, "rate_hz": pre.rate_hz,
                      "factor": pre.factor},
        "prior_start": prior.to_dict(),
        "prior": res.prior.to_dict(),
        "noise_std": res.noise_std.tolist(),
        "passes": passes,
        "learn": list(learn),
        "history": res.history,
        "model_rows_evaluated": int(res.evaluations),
        "offset_std": None if offset_part is None else forces.tolist(),
        "offset_std_rms": None if offset_part is None else
        np.sqrt(np.nanmean(offset_part**2, axis=0)).tolist(),
        "anchor_offset_std": None if anchor_sigma is None else anchor_sigma.tolist(),
        "channel_bias": None if channel_bias is None else
        {"sigma": channel_bias[0].tolist(), "tau_s": float(channel_bias[1]),
         # the flight's mean of each channel's estimated slow misfit (0: none there)
         "mean": _bias_mean(res.bias, sm.bias_channels)},
    }
    return df, extra, res.seconds, sm, res


def _bias_mean(bias: np.ndarray, channels: np.ndarray) -> list:
    """(6,) the flight's mean of the channel-bias states (0 on a channel without one)."""
    out = np.zeros(6)
    if channels.size:
        out[channels] = np.nanmean(bias[:, channels], axis=0)
    return out.tolist()


def _run_apf(heli, data, cutoff_hz, rate_hz, ins_velocity_std, n_particles, sigma, resampler,
             ess_threshold, jitter, seed, process_std, init_half_width, channel_scale, steps,
             progress):
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.particle_filter import ParticleFilter
    from airwake.estimate.prefilter import prefilter
    from airwake.estimate.resample import RESAMPLERS
    from airwake.estimate.wind_model import INIT_HALF_WIDTH, PROCESS_STD, WindMeasurementModel
    from airwake.progress import Progress

    if resampler not in RESAMPLERS:
        raise WindEstimationError(
            f"unknown resampler {resampler!r}; use one of {sorted(RESAMPLERS)}")
    if ess_threshold is None:
        ess_threshold = 1.0 if resampler in ("roulette", "multinomial") else 0.5
    front = None
    if cutoff_hz > 0:
        pre = prefilter(data, heli, cutoff_hz, rate_hz)
        data = pre.data  # keeps the raw flight's channel scales: conservative after the filter
        front = {"cutoff_hz": pre.cutoff_hz, "rate_hz": pre.rate_hz, "factor": pre.factor}
    try:
        wm = WindMeasurementModel(heli, data,
                                  PROCESS_STD if process_std is None else process_std,
                                  INIT_HALF_WIDTH if init_half_width is None else init_half_width)
        pf = ParticleFilter(wm, n_particles, sigma, RESAMPLERS[resampler], ess_threshold,
                            jitter, np.random.default_rng(seed))
    except MODEL_FAILURES as exc:
        raise WindEstimationError(str(exc)) from None
    n = wm.n_steps if steps is None else min(steps, wm.n_steps)
    bar = Progress("wind estimate (apf)", n, " samples", enabled=progress)
    t0 = time.perf_counter()
    try:
        out = pf.run(n, bar)
    except MODEL_FAILURES as exc:
        raise WindEstimationError(f"{data.source}: the model failed on this flight: "
                                  f"{type(exc).__name__}: {exc}") from None
    seconds = time.perf_counter() - t0
    span = float(data.t[n - 1] - data.t[0]) if n > 1 else 0.0
    bar.finish(f"{span / max(seconds, 1e-9):.2f} x real time")
    df = _frame(data.t[:n], out.mean, out.std, ins_velocity_std,
                {"ess": out.ess, "resampled": out.resampled, "skipped": out.skipped})
    extra = {
        "front_end": front,
        "particles": int(n_particles), "sigma": float(sigma), "resampler": resampler,
        "ess_threshold": float(ess_threshold), "jitter": float(jitter), "seed": int(seed),
        "process_std": [float(v) for v in wm.process_std],
        "channel_scale": [float(v) for v in wm.scale],
    }
    return df, extra, seconds


def _run_net(ft, net, ins_velocity_std) -> WindEstimate:
    """A direct wind net (§4.6) over the flight: its estimate per sample; std = the net's
    validation RMS per output (its card), the INS velocity error added like the others."""
    from pathlib import Path

    from airwake.estimate.errors import WindEstimationError
    from airwake.nets.model import NetFileError, load_net
    from airwake.nets.wind_net import envelope_share, predict_wind
    from airwake.record.flight_table import FlightTableError, flight_fingerprint

    path = str(net) if isinstance(net, str | Path) else "<net>"
    t0 = time.perf_counter()
    try:
        loaded = load_net(net) if isinstance(net, str | Path) else net
        est = predict_wind(loaded, ft)
        inside = envelope_share(loaded, ft, est)
    except (NetFileError, FlightTableError) as exc:
        raise WindEstimationError(f"{path}: {exc}") from None
    seconds = time.perf_counter() - t0
    card = loaded.card
    rms = card["validation_rms"]
    mean = est[list(WIND_NAMES)].to_numpy(float)
    std = np.tile([rms[n]["net"] for n in WIND_NAMES], (len(est), 1))
    # what the net does not estimate (a still-air net's rotation: NaN throughout)
    none = ~np.isfinite(mean).any(axis=0)
    std[:, none] = np.nan
    df = _frame(est["t_s"].to_numpy(float), mean, std, ins_velocity_std)
    t = df["t_s"].to_numpy(float)
    span = float(t[-1] - t[0]) if t.size > 1 else 0.0
    meta = {
        "source": "airwake wind estimate",
        "method": "net",
        "flight": str(getattr(ft, "path", "") or ""),
        "net": path,
        "net_training_flights": [f["path"] for f in card.get("training_flights", [])],
        "net_validation_rms": rms,
        "std_is": ("the net's validation RMS per output (model card), INS error added"
                   + ("; measured in still air, it leaves out the wind's fast part at sea "
                      "(0.3 Hz and above): the interval is too narrow there "
                      "(docs/networks.md)"
                      if (card.get("wind_net_config") or {}).get("labels") == "still_air"
                      else "")),
        "not_estimated": [n for n, no in zip(WIND_NAMES, none, strict=True) if no],
        # the share of samples whose air velocity the training flights held (nets.
        # air_envelope); None for a net trained before the card kept its envelope
        "training_envelope_inside": inside,
        "training_envelope": None if inside is None else {
            k: v for k, v in card["air_velocity_envelope"].items() if k != "cells"},
        "frame": "body axes at the main-rotor hub (eq 5.3)",
        "ins_velocity_std_m_s": float(ins_velocity_std),
        "flight_fingerprint": flight_fingerprint(getattr(ft, "df", ft)),
        "calibration_envelope": None,
        "seconds": seconds,
        "realtime_factor": span / seconds if seconds > 0 else 0.0,
    }
    return WindEstimate(df, meta, seconds)


def _widen_by_model(est: WindEstimate, ref: WindEstimate, spec) -> None:
    """The net's mean-flow std joined in quadrature to the local RMS of the model
    smoother's disagreement with it above the net's band and to the fast wind the
    smoother did not see either (`airwake.estimate.net_interval`); the smoother's time is
    counted in the estimate's."""
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.net_interval import (
        HIGHPASS_HZ,
        MEAN_FLOW,
        WINDOW_S,
        disagreement_std,
        unseen_std,
    )

    try:
        fast = disagreement_std(est.df, ref.df)
        unseen = unseen_std(est.df["t_s"].to_numpy(float), ref.result)
    except ValueError as exc:
        raise WindEstimationError(f"--interval-model: {exc}") from None
    for j, name in enumerate(MEAN_FLOW):
        col = f"{name}_std"
        est.df[col] = np.sqrt(est.df[col].to_numpy(float) ** 2 + fast[:, j] ** 2
                              + unseen[:, j] ** 2)
    meta = est.metadata
    est.seconds += ref.seconds
    t = est.df["t_s"].to_numpy(float)
    span = float(t[-1] - t[0]) if t.size > 1 else 0.0
    meta["seconds"] = est.seconds
    meta["realtime_factor"] = span / est.seconds if est.seconds > 0 else 0.0
    meta["interval_model"] = str(spec) if not hasattr(spec, "effects") else "<model>"
    meta["interval_fast_std_median_m_s"] = {
        n: float(np.median(fast[:, j])) for j, n in enumerate(MEAN_FLOW)}
    meta["interval_unseen_std_median_m_s"] = {
        n: float(np.median(unseen[:, j])) for j, n in enumerate(MEAN_FLOW)}
    meta["interval_turbulence_sigma_m_s"] = [float(x) for x in ref.result.prior.sigma[:3]]
    meta["std_is"] = (
        "the net's validation RMS per output (model card), INS error added, joined in "
        f"quadrature to the local RMS (Gaussian window, sigma {WINDOW_S:g} s) of the "
        f"difference between the smoother of {meta['interval_model']} and the net above "
        f"{HIGHPASS_HZ:g} Hz (the wind's fast part the net does not follow, plus the "
        "smoother's own fast error) and to the smoother's turbulence posterior std's share "
        f"above {HIGHPASS_HZ:g} Hz (the fast part neither saw; docs/networks.md)")


def _rotor_radius(heli) -> float:
    from airwake.estimate.errors import WindEstimationError

    if "main_rotor" not in heli:
        raise WindEstimationError(f"model {heli.effect_names} has no main_rotor: the wind "
                                  "estimate reads the wind through the rotor")
    return float(heli["main_rotor"].parameters()["radius_m"])


def check_output(path):
    """The output path is usable (suffix, directory): checked before a long run."""
    from pathlib import Path

    from airwake.estimate.errors import WindEstimationError

    p = Path(path)
    if p.suffix.lower() not in (".parquet", ".pq", ".csv"):
        raise WindEstimationError(f"{p}: output must be .parquet or .csv")
    if not p.parent.is_dir():
        raise WindEstimationError(f"cannot write {p}: directory {p.parent} does not exist")
    return p


def write_wind(est: WindEstimate, path) -> None:
    """Parquet with the metadata (schema key "airwake"), written via a temp file."""
    import os
    import tempfile
    from pathlib import Path

    from airwake.record.flight_table import write_flight_table

    p = check_output(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.stem}-", suffix=p.suffix, dir=p.parent)
    os.close(fd)
    try:
        write_flight_table(est.df, tmp, est.metadata)
        os.replace(tmp, p)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def truth_at(wind_df, flight_df) -> np.ndarray:
    """(n, 6) the flight's truth_wind_* columns at the wind table's times (the estimate
    may be decimated: matched by time, not row)."""
    t = np.asarray(wind_df["t_s"], dtype=float)
    tf = np.asarray(flight_df["t_s"], dtype=float)
    return np.column_stack([np.interp(t, tf, np.asarray(flight_df[c], float))
                            for c in TRUTH_WIND])


COVERAGE_Z90 = 1.6448536269514722  # two-sided 90 % interval of a normal: +-1.645 std


def score_wind(wind_df, flight_df, burn_in_s: float = SCORE_BURN_IN_S) -> dict:
    """Error (estimate - truth) per component after `burn_in_s`: mean, std, RMS, the
    correlation of estimate and truth, the mean posterior std and how often the 90 %
    interval (mean +- 1.645 std) holds the truth, next to Table 5.3. Raises
    WindEstimationError when the flight has no truth."""
    from airwake.estimate.errors import WindEstimationError

    missing = [c for c in TRUTH_WIND if c not in flight_df.columns]
    if missing:
        raise WindEstimationError(f"--score needs the flight's truth columns; missing {missing}")
    t = np.asarray(wind_df["t_s"], dtype=float)
    truth = truth_at(wind_df, flight_df)
    keep = (t >= t[0] + burn_in_s) if t.size else np.zeros(0, bool)
    out = {"burn_in_s": burn_in_s, "samples": int(keep.sum()), "components": {}}
    for j, name in enumerate(WIND_NAMES):
        est = np.asarray(wind_df[name], float)[keep]
        tru = truth[keep, j]
        err = est - tru
        std_post = np.asarray(wind_df[f"{name}_std"], float)[keep]
        ref_mean, ref_std = TABLE_5_3[name]
        # NaN throughout: a component the estimator does not estimate
        ok = err.size > 1 and bool(np.isfinite(est).any())
        corr = float(np.corrcoef(est, tru)[0, 1]) if ok and np.std(est) > 0 and np.std(
            tru) > 0 else float("nan")
        out["components"][name] = {
            "error_mean": float(np.mean(err)) if ok else float("nan"),
            "error_std": float(np.std(err)) if ok else float("nan"),
            "error_rms": float(np.sqrt(np.mean(err * err))) if ok else float("nan"),
            "truth_std": float(np.std(tru)) if ok else float("nan"),
            "correlation": corr,
            "posterior_std_mean": float(np.mean(std_post)) if ok else float("nan"),
            "coverage_90": float(np.mean(np.abs(err) <= COVERAGE_Z90 * std_post))
            if ok else float("nan"),
            "table_5_3_mean": ref_mean,
            "table_5_3_std": ref_std,
        }
    return out


def wind_bound(est: WindEstimate, flight_df, use_truth: bool = True) -> dict:
    """The posterior Cramer-Rao bound (`WindSmoother.bound`) of the smoother's flight, for
    the problem the estimator faces: the model's channels carry this model's error on
    this flight, not white sensor noise. At the truth wind when the flight has it and
    `use_truth` (else at the estimate), the channel error is what the model leaves at that
    wind — measured minus the model's prediction through the front end
    (`WindSmoother.open_loop`): sensor noise and model misfit together, as they are —
    fitted as one coloured Gaussian process of the six channels (`VectorNoise.fit`, a
    vector AR by AIC: the channels' misfits share causes and are correlated): a
    misfit whose power sits at the wind's low frequencies informs the wind less than white
    noise of the same RMS, one at the rotor's frequencies more. The steady offsets the
    posterior considers (the model's `model_error_offset`, `--accel-bias-std`) enter as
    nuisance parameters; at the truth the prior's turbulence std is the truth's own
    (`WindPrior.fitted_to`), at the estimate the learned one. The INS velocity error is
    added to the mean-flow components, as in the posterior. Returns {"std": (n, 6),
    "noise_std": (6,) the channel error's RMS, "at": "truth"|"estimate", "noise_model"}."""
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.smoother import SIGMA_FLOOR, VectorNoise

    sm, res = est.smoother, est.result
    if sm is None:
        raise WindEstimationError("the Cramer-Rao bound is computed for --method smoother")
    have = use_truth and all(c in flight_df.columns for c in TRUTH_WIND)
    wind = truth_at(est.df, flight_df) if have else np.asarray(res.mean, float)
    error = sm.pre.data.z - sm.open_loop(wind)
    try:
        noise = VectorNoise.fit(error, sm.pre.data.runs)
        # the Bayesian bound averages over winds drawn from its prior: at the truth, the
        # prior of the air actually flown through (the learned one holds the model's
        # misfit as turbulence too: 0.45-0.5 against the airwake's 0.07-0.12 measured on
        # the blade-element ship flights, and a bound for such winds is no bound here)
        prior = res.prior.fitted_to(wind, sm.pre.data.t, SIGMA_FLOOR) if have else res.prior
    except ValueError as exc:
        raise WindEstimationError(f"the bound's channel-error model: {exc}") from None
    offset = est.metadata.get("offset_std")
    std = sm.bound(wind, prior, noise, offset)
    ins = float(est.metadata.get("ins_velocity_std_m_s", 0.0))
    std[:, :3] = np.sqrt(std[:, :3] ** 2 + ins**2)
    return {"std": std, "noise_std": noise.std(), "at": "truth" if have else "estimate",
            "noise_model": f"VAR({noise.order}) of the six channels (AIC) + steady offsets"}


def score_bound(score: dict, bound: dict, wind_df) -> dict:
    """Adds to each component of a score: crlb_std (RMS of the bound over the scored
    samples) and error_over_crlb (error RMS / crlb_std)."""
    t = np.asarray(wind_df["t_s"], float)
    keep = t >= t[0] + score["burn_in_s"]
    for j, name in enumerate(WIND_NAMES):
        b = bound["std"][keep, j]
        c = score["components"][name]
        c["crlb_std"] = float(np.sqrt(np.mean(b * b)))
        c["error_over_crlb"] = c["error_rms"] / c["crlb_std"] if c["crlb_std"] > 0 else None
    score["crlb"] = {"at": bound["at"], "noise_std": [float(v) for v in bound["noise_std"]],
                     "noise_model": bound.get("noise_model", "white")}
    return score
