"""Direct wind networks (reference §4.6): the eq 5.3 local wind — mean flow v and rotation
coefficient ω (whose roll / pitch components are the vorticities a_z, b_z of eq 4.14),
body axes at the hub — estimated per sample from the helicopter's measured motion and the
pilot's inputs, trained on simulated flights' truth (`truth_wind_*`).

    net = train_wind_net([table_a, table_b], seed=0)     # FlightTable or path list
    est = predict_wind(net, table)                       # t_s, wind_vx_m_s, ..., wind_wz_rad_s
    save_net(net, "wind.pt")                             # nets.model's file and card

Inputs (§4.6.2 used the swash-plate inputs, the three rates, the measured roll/pitch
acceleration and the tilt; a wind also shows in how the helicopter moves through the
air, so the INS body velocity and specific force join them): per pilot-input channel the
features of `nets.features` (eq 2.1-2.3, trailing windows), roll and pitch, the current
p, q, r and their causal low-pass, ṗ and q̇, vel_u/v/w and acc_x/y/z, each with its
causal low-pass over `context_s` (the wind changes over seconds, the noise per sample).
The network is `nets.model.PilotNet` (ARX skip + per-output MLP, no base column) trained
by `nets.train.train_adamw` on a time-block split for early stopping; every row of a
flight that is not a training flight is held out.

Estimates are per sample and causal; `smooth_s` (a centred Gaussian, default 0: on the
ship flights it raised the error, the truth wind changes within a second) smooths them.

Still-air labels (`train_wind_net(..., still_air=True)`, `nets train --target wind
--still-air`): a user has no truth wind, but in still air the helicopter's velocity
through the air is its INS body velocity. Trained on still-air flights, the net learns
the air-relative velocity from the dynamics (the velocity itself is then no input:
`AIR_MOTION`), and at sea the mean flow is what the INS velocity has beyond it,

    v_wind = v_body(INS) - v_air(net)          (body axes; ω is not estimated: NaN)

— the speed derivatives a model-based estimator calibrates, learned from the same kind
of flight with no model (docs/networks.md "Still-air labels").
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd
import torch

from airwake.nets.air_envelope import air_envelope, inside_share
from airwake.nets.features import FeatureConfig, build_features, gaussian_lowpass, gaussian_smooth
from airwake.nets.model import PilotNet, fit_arx
from airwake.nets.split import TEST, TRAIN, VAL, SplitConfig, split_labels
from airwake.record.flight_table import FlightTableError

WIND_TRUTH = ("truth_wind_vx_m_s", "truth_wind_vy_m_s", "truth_wind_vz_m_s",
              "truth_wind_wx_rad_s", "truth_wind_wy_rad_s", "truth_wind_wz_rad_s")
WIND_OUTPUTS = tuple(c[len("truth_"):] for c in WIND_TRUTH)
MOTION = ("pdot_rad_s2", "qdot_rad_s2", "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
          "acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2")
BODY_VELOCITY = ("vel_u_m_s", "vel_v_m_s", "vel_w_m_s")
# a still-air net's motion inputs: without the velocity it is trained to predict
AIR_MOTION = tuple(c for c in MOTION if c not in BODY_VELOCITY)
TARGET = "wind"
LABELS = ("truth", "still_air")
# a still-air training flight whose truth wind (when it has one) is above this RMS is no
# still-air flight
STILL_AIR_MAX_RMS_M_S = 0.3
STILL_AIR_SMOOTH_S = 0.5


@dataclass(frozen=True)
class WindNetConfig:
    """Feature windows (s) beyond nets.features' and the output smoothing."""

    context_sigma_s: float = 0.5  # causal Gaussian low-pass of the motion channels
    context_length_s: float = 1.5
    smooth_s: float = 0.0  # centred Gaussian on the estimates (0: raw per-sample)
    labels: str = "truth"  # "truth" (truth_wind_*) or "still_air" (module doc)

    @property
    def motion(self) -> tuple:
        """The motion channels the net reads."""
        return AIR_MOTION if self.labels == "still_air" else MOTION

    def __post_init__(self) -> None:
        if self.labels not in LABELS:
            raise ValueError(f"WindNetConfig.labels = {self.labels!r}: one of {LABELS}")
        for name in ("context_sigma_s", "context_length_s"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"WindNetConfig.{name} = {v!r}: must be a positive number")
        if not (np.isfinite(self.smooth_s) and self.smooth_s >= 0):
            raise ValueError(f"WindNetConfig.smooth_s = {self.smooth_s!r}: must be >= 0")


def _loaded(table):
    """A FlightTable or DataFrame as given; a path loaded once (the helpers below read its
    columns several times)."""
    from airwake.record.flight_table import FlightTable, load_flight_table

    if isinstance(table, FlightTable | pd.DataFrame):
        return table
    return load_flight_table(table, required=())


def _df(table):
    table = _loaded(table)
    if isinstance(table, pd.DataFrame):
        return table, "<table>"
    return table.df, str(table.path or "<table>")


def wind_feature_matrix(inputs, roll_rad, pitch_rad, rates_rad_s, motion, rate_hz: float,
                        feature_config: FeatureConfig, config: WindNetConfig):
    """(X (T, F), names (F,)) from arrays: the pilot-input features, then the motion
    channels (T, len(config.motion)) and their causal low-pass (the daemon's live wind
    calls this too)."""
    x, names = build_features(inputs, roll_rad, pitch_rad, rates_rad_s, rate_hz,
                              feature_config)
    lp = gaussian_lowpass(motion, rate_hz, config.context_sigma_s, config.context_length_s)
    cols = config.motion
    return (np.column_stack([x, motion, lp]),
            [*names, *cols, *(f"{c}_context" for c in cols)])


def history_s(feature_config: FeatureConfig, config: WindNetConfig, rate_hz: float) -> float:
    """How far back the features of one sample reach (s)."""
    return max(feature_config.history_s(rate_hz), config.context_length_s)


def wind_features(table, feature_config: FeatureConfig, config: WindNetConfig):
    """(t_s (T,), X (T, F), names (F,), rate_hz, truth (T, 6) or None) of one flight."""
    from airwake.nets.data import net_flight_from_df

    df, source = _df(table)
    flight = net_flight_from_df(df, source, "accel", "delta")
    need = MOTION if config.labels == "still_air" else config.motion  # + the velocity
    missing = [c for c in need if c not in df.columns or df[c].isna().all()]
    if missing:
        raise FlightTableError(f"{source}: column(s) {missing} missing; a wind net reads "
                               f"{list(need)}")
    # the net flight may have cropped or dropped nothing: align by time
    motion = np.column_stack([np.interp(flight.t_s, df["t_s"].to_numpy(float),
                                        df[c].to_numpy(float)) for c in config.motion])
    x, names = wind_feature_matrix(flight.inputs, flight.roll_rad, flight.pitch_rad,
                                   flight.rates_rad_s, motion, flight.rate_hz, feature_config,
                                   config)
    truth = None
    if all(c in df.columns for c in WIND_TRUTH):
        truth = np.column_stack([np.interp(flight.t_s, df["t_s"].to_numpy(float),
                                           df[c].to_numpy(float)) for c in WIND_TRUTH])
    return flight.t_s, x, names, flight.rate_hz, truth


def body_velocity(table, t_s: np.ndarray) -> np.ndarray:
    """(T, 3) the flight's INS body velocity (vel_u/v/w) at the times t_s."""
    df, _ = _df(table)
    tf = df["t_s"].to_numpy(float)
    return np.column_stack([np.interp(t_s, tf, df[c].to_numpy(float)) for c in BODY_VELOCITY])


def still_air_labels(table, t_s: np.ndarray, truth) -> np.ndarray:
    """(T, 6) a still-air flight's labels: the air-relative velocity (= the INS body
    velocity in still air) in the mean-flow outputs, zero rotation. A flight whose truth
    wind says it was not still air is refused."""
    if truth is not None:
        rms = float(np.sqrt(np.mean(truth[:, :3] ** 2)))
        if rms > STILL_AIR_MAX_RMS_M_S:
            raise FlightTableError(
                f"{_df(table)[1]}: --still-air, but its truth wind is {rms:.2f} m/s RMS: "
                "not a still-air flight")
    return np.column_stack([body_velocity(table, t_s), np.zeros((t_s.size, 3))])


def train_wind_net(tables, seed: int = 0, hidden=(32, 16), config: WindNetConfig | None = None,
                   split: SplitConfig | None = None, adamw=None,
                   max_rows: int = 60000, still_air: bool = False) -> PilotNet:
    """A wind net trained on simulated flights (their truth_wind_* columns), or with
    `still_air` on still-air flights of any kind (their INS velocity; module doc); the
    card holds the features, windows, flights, validation RMS per output (net and ARX)."""
    from dataclasses import replace

    from airwake.nets.train import AdamWConfig, train_adamw, versions

    if still_air:
        # smoothed after the subtraction: the INS velocity's and the net's noise are
        # independent, the wind's mean flow changes over seconds (0.5 s, chosen on ship
        # seeds 41 and 42: v_x error std 0.33 -> 0.19; docs/networks.md)
        config = replace(config or WindNetConfig(smooth_s=STILL_AIR_SMOOTH_S),
                         labels="still_air")
    config = config or WindNetConfig()
    split = split or SplitConfig(order="blocks")
    fcfg = FeatureConfig(rate_lag_samples=0)
    t0 = time.perf_counter()
    rng = np.random.default_rng(seed)
    xs, ys, labels, flights, names, rates, airs = [], [], [], [], None, [], []
    for table in map(_loaded, tables):
        t, x, names, rate_hz, truth = wind_features(table, fcfg, config)
        if config.labels == "still_air":
            truth = still_air_labels(table, t, truth)
            airs.append(truth[:, :3])  # the air velocity is the label
        elif truth is None:
            raise FlightTableError(f"{_df(table)[1]}: no truth_wind_* columns: a wind net "
                                   "trains on simulated flights (or on still-air flights "
                                   "with --still-air)")
        else:
            airs.append(body_velocity(table, t) - truth[:, :3])
        lab = split_labels(t, split, history_s(fcfg, config, rate_hz), rng)
        lab = np.where(lab == TEST, TRAIN, lab)  # other flights are the test set
        xs.append(x)
        ys.append(truth)
        labels.append(lab)
        rates.append(rate_hz)
        flights.append({"path": _df(table)[1], "rows": int(t.size)})
    x, y, lab = np.concatenate(xs), np.concatenate(ys), np.concatenate(labels)
    tr = np.flatnonzero(lab == TRAIN)
    va = np.flatnonzero(lab == VAL)
    # every k-th training row: neighbouring rows at 150 Hz are near-copies
    step = max(1, int(np.ceil(tr.size / max_rows)))
    tr = tr[::step]
    old = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        torch.manual_seed(seed)
        gen = torch.Generator().manual_seed(seed)
        net = PilotNet(x.shape[1], y.shape[1], hidden, None)
        net.set_scaling(x[tr], y[tr])
        z = net.standardise(x)
        ys_ = net.standardise_target(x, y)
        net.set_arx(fit_arx(z[tr].double().numpy(), ys_[tr].double().numpy()))
        cfg = adamw or AdamWConfig(lr=2e-3, max_epochs=60, patience=8, per_axis=False,
                                   train_skip=True, min_gain_se=0.0)
        info = train_adamw(net, z[tr], ys_[tr], z[va], ys_[va], cfg, gen)
        net.eval()
        pred_va, arx_va = net.predict_numpy(x[va]), net.predict_arx(x[va])
    finally:
        torch.set_num_threads(old)
    rms = {o: {"net": float(np.sqrt(np.mean((pred_va[:, k] - y[va, k]) ** 2))),
               "arx": float(np.sqrt(np.mean((arx_va[:, k] - y[va, k]) ** 2)))}
           for k, o in enumerate(WIND_OUTPUTS)}
    net.card = {"target": TARGET, "outputs": list(WIND_OUTPUTS), "features": names,
                "feature_config": fcfg.to_dict(), "wind_net_config": asdict(config),
                "split": asdict(split), "input_source": "delta",
                "rate_hz": float(np.mean(rates)), "trainer": "adamw",
                "trainer_settings": asdict(cfg), "training": info, "seed": int(seed),
                "training_flights": flights, "training_rows": int(tr.size),
                "validation_rms": rms, "train_seconds": round(time.perf_counter() - t0, 3),
                "air_velocity_envelope": air_envelope(np.concatenate(airs),
                                                      float(np.mean(rates))),
                "versions": versions()}
    return net


def envelope_share(net: PilotNet, table, est: pd.DataFrame) -> float | None:
    """The share of the estimate's samples whose air velocity (the INS body velocity less
    the estimated mean flow) lies inside the net's training flights' (`air_envelope`);
    None for a net whose card has no envelope (trained before it was kept) or a flight
    with no finite estimate."""
    env = net.card.get("air_velocity_envelope")
    if env is None:
        return None
    t = est["t_s"].to_numpy(float)
    air = body_velocity(table, t) - est[list(WIND_OUTPUTS[:3])].to_numpy(float)
    share = inside_share(env, air)
    return None if not np.isfinite(share) else share


def predict_wind(net: PilotNet, table, smooth_s: float | None = None) -> pd.DataFrame:
    """t_s and the six wind_* estimates per sample (body axes, SI), smoothed by the net's
    `smooth_s` (or the given one; 0 = raw)."""
    from airwake.nets.model import NetFileError

    if net.card.get("target") != TARGET:
        raise NetFileError(f"a {net.card.get('target')!r} net is not a wind net")
    config = WindNetConfig(**net.card["wind_net_config"])
    fcfg = FeatureConfig.from_dict(net.card["feature_config"])
    table = _loaded(table)
    t, x, names, rate_hz, _ = wind_features(table, fcfg, config)
    if names != net.card["features"]:
        raise NetFileError(f"the wind net's card lists features {net.card['features']}, "
                           f"this code builds {names}")
    rate = net.card["rate_hz"]
    if not 0.9 * rate <= rate_hz <= 1.1 * rate:
        raise FlightTableError(f"sampled at {rate_hz:.4g} Hz, the wind net was trained at "
                               f"{rate:.4g} Hz")
    est = net.predict_numpy(x)
    if config.labels == "still_air":
        # the net's mean-flow outputs are the air-relative velocity; ω it never saw
        est = np.column_stack([body_velocity(table, t) - est[:, :3],
                               np.full((t.size, 3), np.nan)])
    smooth = config.smooth_s if smooth_s is None else smooth_s
    if smooth > 0:
        est = gaussian_smooth(est, rate_hz, smooth, 3.0 * smooth)
    return pd.DataFrame({"t_s": t, **{o: est[:, k] for k, o in enumerate(WIND_OUTPUTS)}})


def score_against_truth(est: pd.DataFrame, table, at_t_s: np.ndarray | None = None,
                        burn_in_s: float = 2.0) -> dict:
    """RMS and mean error per component against the flight's truth_wind_*, at the
    estimate's samples or (interpolated) at `at_t_s` (another estimator's samples), after
    `burn_in_s`."""
    df, source = _df(table)
    if any(c not in df.columns for c in WIND_TRUTH):
        raise FlightTableError(f"{source}: no truth_wind_* columns to score against")
    tf = df["t_s"].to_numpy(float)
    te = est["t_s"].to_numpy(float)
    t = te if at_t_s is None else np.asarray(at_t_s, float)
    t = t[(t >= te[0] + burn_in_s) & (t <= te[-1])]
    out = {"samples": int(t.size)}
    for o, c in zip(WIND_OUTPUTS, WIND_TRUTH, strict=True):
        e = np.interp(t, te, est[o].to_numpy(float)) - np.interp(t, tf, df[c].to_numpy(float))
        out[o] = {"rms": float(np.sqrt(np.mean(e**2))), "mean": float(np.mean(e))}
    return out
