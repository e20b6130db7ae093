"""Wind in the diagnosis: a known wind as the model's input, and unmodelled wind as a
candidate explanation of the residual.

The model predicts the six channels from the measured states, inputs *and the wind*
(eq 5.3: three mean-flow and three rotation components at the hub, body axes). A flight
in wind analysed as if in still air leaves the wind's whole effect in the residual, and
a catalogue effect fitted to it explains some of it for the wrong reason (a steady wind
over a deck looks like a CG offset: a trim shift proportional to the rotor force). So:

- **Known wind** (`wind_input`, the `--wind SOURCE` option of `airwake model ...`): a wind
  table given as the model's input. SOURCE is an `airwake wind estimate` output, an
  anemometer-derived table (body axes `wind_v{x,y,z}_m_s`, or earth axes
  `wind_{n,e,d}_m_s`, rotated here by the flight's attitude), or for a simulated flight
  the word `truth` (its `truth_wind_*` columns).
- **Unmodelled wind** (`WIND_CANDIDATE`): screened like a catalogue effect, with the
  wind as the "parameters": a wind field in earth axes (`basis`: a constant, a slow drift
  in time as Legendre polynomials up to `ORDER`, and eq 3.15's linear variation with
  position, whose half curl is the eq 5.3 rotation), rotated into body axes by the
  measured attitude. Its regressors are the model's sensitivities to each coefficient
  (one prediction per basis function), its refinement Gauss-Newton steps with the
  sensitivities retaken at the fitted wind (the model's response to a 10 m/s wind is not
  linear). A steady or slowly drifting wind generalises across time blocks, so
  the candidate competes with the catalogue on the same cross-validated share; the
  turbulence around it does not (it is what `airwake wind estimate` is for). When the
  wind is known, the candidate screens what the supplied wind still misses.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.polynomial import legendre

from airwake.discrepancy.errors import DiscrepancyError

WIND_CANDIDATE = "unmodelled_wind"
WIND_TITLE = "unmodelled wind"
ORDER = 2  # Legendre polynomials of time P0..P_ORDER per earth-axis component
SCREEN_STEP_M_S = 1.0
SCREEN_STEP_GRADIENT = 0.2  # 1/s: an airwake's shear is ~0.1-1 1/s
NED_COLUMNS = ("wind_n_m_s", "wind_e_m_s", "wind_d_m_s")
ADVICE = ("estimate the wind (`airwake wind estimate FLIGHT --model SPEC --out WIND.parquet`) "
          "or supply a measured one, and analyse again with `--wind WIND.parquet` (simulated "
          "flights: `--wind truth`)")
MANOEUVRE = ("fly in still air (indoors, or a calm day) to look for missing physics, or give "
             "the flight's wind with --wind")


def body_from_ned(df, vectors: np.ndarray) -> np.ndarray:
    """(T, 3) earth-axis (NED) vectors -> body axes by the flight's roll, pitch, yaw."""
    from scipy.spatial.transform import Rotation

    euler = np.column_stack([df[c].to_numpy(float) for c in ("yaw_rad", "pitch_rad",
                                                              "roll_rad")])
    return Rotation.from_euler("ZYX", euler).inv().apply(vectors)


def _positions(flight) -> np.ndarray | None:
    """(T, 3) NED position from its mean over the flight (relative to the ship's reference
    point where the flight has it: an airwake moves with its ship); None without positions."""
    cols = ("pos_n_m", "pos_e_m", "pos_d_m")
    if not all(c in flight.df.columns for c in cols):
        return None
    p = np.column_stack([flight.column(c) for c in cols])
    ship = ("ship_pos_n_m", "ship_pos_e_m", "ship_pos_d_m")
    if all(c in flight.df.columns for c in ship):
        s = np.column_stack([flight.column(c) for c in ship])
        if np.all(np.isfinite(s)):
            p = p - s
    if not np.all(np.isfinite(p)):
        return None
    return p - p.mean(0)


def basis(flight, order: int = ORDER) -> tuple[np.ndarray, list[str], np.ndarray]:
    """Body-axis winds (K, T, 6) of the K basis functions, their names and the screening
    step of each coefficient. The wind field, in earth axes (NED) about the flight's mean
    position x0 (eq 3.15's linear field, with a slow drift in time):

        u(x, t) = u0 + sum_k u_k P_k(s(t)) + G (x - x0),   rotation = curl(u) / 2

    u0, u_k in m/s (k = 1..order, P_k Legendre, s = time scaled to [-1, 1]), G (3 x 3) in
    1/s; the eq 5.3 rotation coefficient is half the curl (a field v + w x r)."""
    t = flight.t
    n = t.size
    span = max(float(t[-1] - t[0]), 1e-9)
    s = 2.0 * (t - t[0]) / span - 1.0
    funcs = []  # (name, NED translation (T, 3), NED rotation (3,), step)
    for k in range(order + 1):
        pk = legendre.legval(s, np.eye(order + 1)[k])
        for j, axis in enumerate("NED"):
            tr = np.zeros((n, 3))
            tr[:, j] = pk
            funcs.append((f"{axis}{k}", tr, np.zeros(3), SCREEN_STEP_M_S))
    rel = _positions(flight)
    if rel is not None:
        for i, ai in enumerate("NED"):
            for j, aj in enumerate("NED"):
                tr = np.zeros((n, 3))
                tr[:, i] = rel[:, j]
                g = np.zeros((3, 3))
                g[i, j] = 1.0
                curl = np.array([g[2, 1] - g[1, 2], g[0, 2] - g[2, 0], g[1, 0] - g[0, 1]])
                funcs.append((f"d{ai}/d{aj}", tr, 0.5 * curl, SCREEN_STEP_GRADIENT))
    out = np.zeros((len(funcs), n, 6))
    for k, (_, tr, rot, _) in enumerate(funcs):
        out[k, :, :3] = body_from_ned(flight.df, tr)
        if np.any(rot):
            out[k, :, 3:] = body_from_ned(flight.df, np.repeat(rot[None], n, 0))
    return out, [f[0] for f in funcs], np.array([f[3] for f in funcs])


def describe(params: dict, flight, order: int = ORDER) -> dict:
    """The fitted field in words and numbers (JSON-ready): the mean earth-axis wind, its
    drift over the flight, and the rotation (eq 5.3) of the gradient part."""
    t = flight.t
    s = 2.0 * (t - t[0]) / max(float(t[-1] - t[0]), 1e-9) - 1.0
    ned = np.zeros((t.size, 3))
    for k in range(order + 1):
        pk = legendre.legval(s, np.eye(order + 1)[k])
        for j, axis in enumerate("NED"):
            ned[:, j] += params.get(f"{axis}{k}", 0.0) * pk
    mean = ned.mean(0)
    g = np.array([[params.get(f"d{a}/d{b}", 0.0) for b in "NED"] for a in "NED"])
    rot = 0.5 * np.array([g[2, 1] - g[1, 2], g[0, 2] - g[2, 0], g[1, 0] - g[0, 1]])
    return {"mean_ned_m_s": [float(v) for v in mean],
            "speed_m_s": float(np.linalg.norm(mean[:2])),
            "drift_m_s": float(np.sqrt(np.mean(np.sum((ned - mean) ** 2, 1)))),
            "gradient_per_s": g.tolist(),
            "rotation_ned_rad_s": [float(v) for v in rot]}


# -- the candidate --------------------------------------------------------------------------
def screen(an, blocks, n_eff: float, y: np.ndarray):
    """Linear screening of unmodelled wind (module docstring): (LinearFit, the weighted
    in-band regressors (n, 6, K), {basis name: coefficient})."""
    from airwake.discrepancy.regress import linear_fit

    b, names, steps = basis(an.flight)
    x = an.regressors(_sensitivities(an, _known(an), an.zhat, b, steps))
    fit = linear_fit(y, x, an.weights, blocks, n_eff)
    return fit, x, {n: float(a) for n, a in zip(names, fit.coef, strict=True)}


def _known(an) -> np.ndarray:
    return np.zeros((len(an.flight), 6)) if an.wind is None else an.wind


def _sensitivities(an, w, z, b, steps) -> np.ndarray:
    """(K, T, 6) d z_hat / d coefficient at the wind w (forward differences; the rotor's
    hidden states depend on the wind, so each is reconstructed)."""
    from airwake.discrepancy.compare import predict

    return np.stack([(predict(an.model, an.flight, wind=w + st * bk) - z) / st
                     for bk, st in zip(b, steps, strict=True)])


def refine(an, linear_params: dict, iterations: int = 2) -> tuple[dict, np.ndarray]:
    """Gauss-Newton from the linear estimate (the model's response to a wind of several
    m/s is not linear, so the sensitivities are taken again at the fitted wind): the
    fitted coefficients and the predicted change of the channels (T, 6)."""
    from airwake.discrepancy.compare import predict
    from airwake.discrepancy.fit import weighted_residual

    b, names, steps = basis(an.flight)
    w0 = _known(an)
    coef = np.array([linear_params[n] for n in names])
    sw = np.sqrt(an.weights)

    def cost(c):
        z = predict(an.model, an.flight, wind=w0 + np.einsum("k,ktc->tc", c, b))
        r = weighted_residual(an, z)
        return float(r @ r), z

    best, z = cost(coef)
    for _ in range(iterations):
        sens = _sensitivities(an, w0 + np.einsum("k,ktc->tc", coef, b), z, b, steps)
        x = an.regressors(sens) * sw[None, :, None]
        r = an.band(an.flight.z - z)[an.mask] * sw[None]
        step, *_ = np.linalg.lstsq(x.reshape(-1, x.shape[2]), r.reshape(-1), rcond=1e-8)
        trial = coef + step
        c, zt = cost(trial)
        if not c < best:
            break
        coef, best, z = trial, c, zt
    return {n: float(v) for n, v in zip(names, coef, strict=True)}, z - an.zhat


# -- a known wind ----------------------------------------------------------------------------
def on_flight(wind, flight_source, settings=None):
    """(Flight, wind (T, 6) or None) for the analysis: `wind` is None, a (T, 6) array, or a
    source `wind_input` reads ("truth", a wind table's path)."""
    from airwake.discrepancy.data import load_flight

    flight = load_flight(flight_source, settings)
    if wind is None or isinstance(wind, np.ndarray):
        return flight, wind
    return flight, wind_input(wind, flight_source, flight)


def wind_input(source, flight_source, flight) -> np.ndarray | None:
    """The wind `source` names at the flight's samples, (T, 6) body axes (module docstring).

    source: None (still air), "truth", or a path to a wind table. flight_source: what the
    flight was loaded from (path / FlightTable / DataFrame: where `truth` reads its
    columns; the analysis itself never sees truth columns). flight: the loaded Flight."""
    if source is None:
        return None
    if str(source) == "truth":
        return _truth_wind(flight_source, flight)
    return _wind_table(Path(source), flight)


def _truth_wind(flight_source, flight) -> np.ndarray:
    import pandas as pd

    from airwake.heli.model import WIND_NAMES
    from airwake.record.flight_table import FlightTable, FlightTableError, load_flight_table

    cols = [f"truth_{n}" for n in WIND_NAMES]
    if isinstance(flight_source, FlightTable):
        df = flight_source.df
    elif isinstance(flight_source, pd.DataFrame):
        df = flight_source
    else:
        try:
            df = load_flight_table(flight_source, ("t_s",), cols).df
        except FlightTableError as exc:
            raise DiscrepancyError(str(exc)) from None
    missing = [c for c in cols if c not in df.columns]
    if missing:
        raise DiscrepancyError(f"--wind truth: {flight.name} has no {', '.join(missing)} "
                               "(only simulated flights carry their true wind; give a wind "
                               "table instead)")
    t = df["t_s"].to_numpy(float)
    return np.column_stack([np.interp(flight.t, t, df[c].to_numpy(float)) for c in cols])


def _wind_table(path: Path, flight) -> np.ndarray:
    from airwake.heli.model import WIND_NAMES
    from airwake.record.flight_table import (
        FlightTableError,
        flight_fingerprint,
        load_flight_table,
    )

    try:
        wt = load_flight_table(path, ("t_s",), (*WIND_NAMES, *NED_COLUMNS))
    except FlightTableError as exc:
        raise DiscrepancyError(f"--wind: {exc}") from None
    df = wt.df
    fp = wt.metadata.get("flight_fingerprint")
    here = flight_fingerprint(flight.df)
    if fp and fp != here:
        raise DiscrepancyError(f"--wind {path} was estimated from another flight ({fp}), not "
                               f"{flight.name} ({here})")
    body = all(c in df.columns for c in WIND_NAMES[:3])
    earth = all(c in df.columns for c in NED_COLUMNS)
    if not body and not earth:
        raise DiscrepancyError(
            f"--wind {path}: no wind columns; expected body axes {', '.join(WIND_NAMES[:3])} "
            f"(+ optional {', '.join(WIND_NAMES[3:])}) or earth axes {', '.join(NED_COLUMNS)}")
    t = df["t_s"].to_numpy(float)
    if t.size < 2 or not np.all(np.diff(t) > 0):
        raise DiscrepancyError(f"--wind {path}: t_s must increase strictly over >= 2 rows")
    if t[0] > flight.t[0] + 0.5 or t[-1] < flight.t[-1] - 0.5:
        raise DiscrepancyError(f"--wind {path} covers t = {t[0]:.2f} ... {t[-1]:.2f} s, not "
                               f"the flight's {flight.t[0]:.2f} ... {flight.t[-1]:.2f} s")
    use = WIND_NAMES[:3] if body else NED_COLUMNS
    for c in use:
        v = df[c].to_numpy(float)
        if not np.all(np.isfinite(v)):
            raise DiscrepancyError(f"--wind {path}: column {c} has "
                                   f"{int(np.sum(~np.isfinite(v)))} non-finite values")
    out = np.zeros((flight.t.size, 6))
    vel = np.column_stack([np.interp(flight.t, t, df[c].to_numpy(float)) for c in use])
    out[:, :3] = vel if body else body_from_ned(flight.df, vel)
    if body:
        for j, c in enumerate(WIND_NAMES[3:]):
            if c in df.columns:
                out[:, 3 + j] = np.interp(flight.t, t, np.nan_to_num(df[c].to_numpy(float)))
    return out
