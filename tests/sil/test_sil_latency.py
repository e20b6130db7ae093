"""Stamp latencies through the whole chain: boards -> ptys -> daemon -> export.

The clean 12 s flight (hover, then the lateral chirp) against the truth world it was fed
from: each stream's time shift, fitted by least squares against its truth, is what is
left after `airwake export` removed the latencies the boards declare (`stamp_latency`
frames). Kept, these shifts look like servo lag or an input time skew to the analysis."""

from __future__ import annotations

import numpy as np
from airwake.record.export import export_recording
from airwake.record.reader import open_recording
from sil_harness import load_export, sim_time

# shifts tried, s: the fit is a grid search, refined by a parabola through the best three
LAGS_S = np.arange(-8e-3, 8e-3 + 1e-9, 0.05e-3)


def fitted_lag_s(t_sim: np.ndarray, measured: np.ndarray, t_truth: np.ndarray,
                 truth: np.ndarray) -> float:
    """tau minimising sum_i sum_c ((x_ic - mean x_c) - (y_c(t_i - tau) - mean))^2 / var x_c:
    how much later than its truth a stream's values sit on the table's timeline.
    Shapes: t_sim (N,), measured (N, C), t_truth (M,), truth (M, C)."""
    x = measured - measured.mean(axis=0)
    scale = x.std(axis=0)
    cost = np.zeros(LAGS_S.size)
    for k, lag in enumerate(LAGS_S):
        y = np.column_stack([np.interp(t_sim - lag, t_truth, truth[:, c])
                             for c in range(truth.shape[1])])
        cost[k] = np.sum(np.mean(((x - (y - y.mean(axis=0))) / scale) ** 2, axis=0))
    k = int(np.clip(np.argmin(cost), 1, LAGS_S.size - 2))
    a, b, c = cost[k - 1:k + 2]
    step = LAGS_S[1] - LAGS_S[0]
    return float(LAGS_S[k] + 0.5 * (a - c) / (a - 2 * b + c) * step)


def stream_lags_ms(df, meta, extra, truth_npz) -> dict[str, float]:
    """Per stream, its fitted shift against the truth (ms), scored from 0.5 s on (the
    boards boot at t = 0; the rotor speed and the RC channels need a frame or two)."""
    t = sim_time(df["t_s"].to_numpy(), meta, extra)
    keep = (t > 0.5) & (t < t[-1] - 0.1)
    t = t[keep]
    with np.load(truth_npz) as z:
        tt = z["t_s"]
        pairs = {
            # the lateral chirp: blade-pitch command vs the applied pitch (no servo model)
            "base/pilot_inputs": (["delta_lat_rad"], z["applied_rad"][:, [1]]),
            # INS rates and specific force (white noise + vibration; the attitude's
            # Gauss-Markov error would bias a fit)
            "rover/ins": (["p_rad_s", "q_rad_s", "acc_y_m_s2"],
                          np.column_stack([z["rates_rad_s"][:, :2],
                                           z["imu_specific_force_m_s2"][:, 1]])),
        }
        return {k: 1e3 * fitted_lag_s(t, df[cols].to_numpy()[keep], tt, y)
                for k, (cols, y) in pairs.items()}


def test_exported_streams_sit_on_their_truth_within_a_millisecond(clean_flight):
    # Why: the analysis reads a shift between the pilot inputs and the INS as servo lag;
    # the known stamp latencies (the INS packet's 1.455 ms to its last byte) must be gone,
    # and the pilot inputs stamped at their RC frame's start (not a 50 Hz tick)
    df, meta, extra = load_export(clean_flight)
    after = stream_lags_ms(df, meta, extra, clean_flight / "truth.npz")
    assert meta["stamp_latency"]["removed"]
    assert meta["stamp_latency"]["streams"]["rover/ins"]["latency_ms"] == 1.455
    assert meta["stamp_latency"]["streams"]["base/pilot_inputs"]["latency_ms"] == 0.0
    for stream, lag in after.items():
        assert abs(lag) < 0.5, (stream, after)
    # the same recording exported with the boards' stamps as they are: INS rows late by
    # the declared 1.455 ms, the pilot inputs (declared 0) where they were
    raw = export_recording(open_recording(clean_flight / "rec"), remove_stamp_latency=False)
    before = stream_lags_ms(raw.df, raw.metadata, extra, clean_flight / "truth.npz")
    assert abs(before["rover/ins"] - after["rover/ins"] - 1.455) < 0.2, (before, after)
    assert abs(before["base/pilot_inputs"] - after["base/pilot_inputs"]) < 0.2
