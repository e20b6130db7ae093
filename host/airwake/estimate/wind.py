"""Wind estimation over a flight: run the particle filter, write the estimate, score it.

    est = estimate_wind("flight.parquet", model="table52", n_particles=2000, seed=0)
    est.df            # t_s, wind_vx_m_s ... wind_wz_rad_s, *_std, ess, resampled, skipped
    score_wind(est.df, flight_df)   # error mean/std per component vs truth_wind_*
    write_wind(est, "wind.parquet")

Output columns (one row per flight sample): `t_s`; the posterior mean `wind_vx_m_s`,
`wind_vy_m_s`, `wind_vz_m_s`, `wind_wx_rad_s`, `wind_wy_rad_s`, `wind_wz_rad_s` (eq 5.3,
body axes, at the main-rotor hub; w is the rotation coefficient, curl = 2 w) and their
posterior std `<name>_std`; `ess` (effective sample size after the update),
`resampled` and `skipped` flags. Parquet metadata (key "airwake"): model spec, flight,
particles, sigma, resampler, seed, process noise, channel scales.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

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


@dataclass
class WindEstimate:
    df: object  # pandas DataFrame (see module docstring)
    metadata: dict = field(default_factory=dict)
    seconds: float = 0.0


def estimate_wind(flight, model="table52", n_particles: int = 2000, sigma: float = 0.5,
                  resampler: str = "systematic", ess_threshold: float | None = None,
                  jitter: float = 0.2, seed: int = 0, process_std=None, init_half_width=None,
                  channel_scale=None, steps: int | None = None,
                  progress: bool = False) -> WindEstimate:
    """Run the wind particle filter over a flight table (path, FlightTable or DataFrame).

    resampler: 'systematic' (default, on ESS < N/2), 'stratified', or 'roulette' /
    'multinomial' (the reference: every sample unless ess_threshold is given)."""
    import pandas as pd

    from airwake.calibrate import CalibrationError, load_flight, load_model
    from airwake.calibrate.residuals import FlightData
    from airwake.estimate.errors import WindEstimationError
    from airwake.estimate.particle_filter import ParticleFilter
    from airwake.estimate.resample import RESAMPLERS
    from airwake.estimate.wind_model import INIT_HALF_WIDTH, PROCESS_STD, WindMeasurementModel
    from airwake.progress import Progress

    if resampler not in RESAMPLERS:
        raise WindEstimationError(
            f"unknown resampler {resampler!r}; use one of {sorted(RESAMPLERS)}")
    if ess_threshold is None:
        ess_threshold = 1.0 if resampler in ("roulette", "multinomial") else 0.5
    heli = load_model(model)
    ft = load_flight(flight)
    try:
        data = FlightData.from_flight(heli, ft, channel_scale=channel_scale)
    except CalibrationError as exc:
        raise WindEstimationError(str(exc)) from None
    try:
        wm = WindMeasurementModel(heli, data,
                                  PROCESS_STD if process_std is None else process_std,
                                  INIT_HALF_WIDTH if init_half_width is None else init_half_width)
        pf = ParticleFilter(wm, n_particles, sigma, RESAMPLERS[resampler], ess_threshold,
                            jitter, np.random.default_rng(seed))
    except ValueError as exc:
        raise WindEstimationError(str(exc)) from None
    n = wm.n_steps if steps is None else min(steps, wm.n_steps)
    bar = Progress("wind estimate", n, " samples", enabled=progress)
    t0 = time.perf_counter()
    out = pf.run(n, bar)
    seconds = time.perf_counter() - t0
    bar.finish(f"{n / max(seconds, 1e-9) / 150.0:.2f} x real time at 150 Hz")
    cols = {"t_s": data.t[:n]}
    for i, name in enumerate(WIND_NAMES):
        cols[name] = out.mean[:, i]
    for i, name in enumerate(WIND_NAMES):
        cols[f"{name}_std"] = out.std[:, i]
    cols["ess"] = out.ess
    cols["resampled"] = out.resampled
    cols["skipped"] = out.skipped
    meta = {
        "source": "airwake wind estimate",
        "flight": str(getattr(ft, "path", "") or ""),
        "model_spec": str(model) if not hasattr(model, "effects") else "<model>",
        "particles": int(n_particles), "sigma": float(sigma), "resampler": resampler,
        "ess_threshold": float(ess_threshold), "jitter": float(jitter), "seed": int(seed),
        "process_std": [float(v) for v in wm.process_std],
        "channel_scale": [float(v) for v in wm.scale],
        "seconds": seconds, "realtime_factor": float((data.t[n - 1] - data.t[0]) / seconds)
        if n > 1 else 0.0,
        "frame": "body axes at the main-rotor hub (eq 5.3)",
    }
    return WindEstimate(pd.DataFrame(cols), meta, seconds)


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


def score_wind(wind_df, flight_df, burn_in_s: float = 2.0) -> dict:
    """Error (estimate - truth) mean and std per component after `burn_in_s` of the
    flight, next to Table 5.3. Raises WindEstimationError when the flight has no truth."""
    from airwake.estimate.errors import WindEstimationError

    missing = [c for c in TRUTH_WIND if c not in flight_df.columns]
    if missing:
        raise WindEstimationError(f"--score needs the flight's truth columns; missing {missing}")
    t = np.asarray(wind_df["t_s"], dtype=float)
    n = t.size
    keep = t >= t[0] + burn_in_s
    out = {"burn_in_s": burn_in_s, "samples": int(keep.sum()), "components": {}}
    for name, truth in zip(WIND_NAMES, TRUTH_WIND, strict=True):
        err = (np.asarray(wind_df[name], float) - np.asarray(flight_df[truth], float)[:n])[keep]
        std_post = np.asarray(wind_df[f"{name}_std"], float)[keep]
        ref_mean, ref_std = TABLE_5_3[name]
        out["components"][name] = {
            "error_mean": float(np.mean(err)) if err.size else float("nan"),
            "error_std": float(np.std(err)) if err.size else float("nan"),
            "error_rms": float(np.sqrt(np.mean(err * err))) if err.size else float("nan"),
            "posterior_std_mean": float(np.mean(std_post)) if err.size else float("nan"),
            "table_5_3_mean": ref_mean,
            "table_5_3_std": ref_std,
        }
    return out
