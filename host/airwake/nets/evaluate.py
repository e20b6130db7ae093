"""Applying a trained net to flights: predictions, residuals and held-out scores.

    pred = predict(net, "flight.parquet")     # DataFrame: t_s, p_pred_rad_s, …, p_resid_rad_s, …
    report = evaluate_net(net, [flight, …])   # per flight and overall, held-out rows only

`predict` is what airwake-intensity code builds on: the residual (measured − predicted)
is the part of the motion the pilot's inputs do not explain. The previous rates fed to
the net are the measured ones (teacher forcing, as the reference's recurrent nets).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from airwake.nets.data import NetFlight, load_net_flight, net_flight_from_df
from airwake.nets.features import FeatureConfig
from airwake.nets.metrics import UNITS, score_rows, smoothed_target
from airwake.nets.model import NetFileError, PilotNet
from airwake.nets.split import TEST
from airwake.nets.train import flight_features, unrle
from airwake.record.flight_table import FlightTable, FlightTableError

_SUFFIX = {"rates": "rad_s", "accel": "rad_s2"}


def as_net_flight(net: PilotNet, table, from_s=None, to_s=None) -> NetFlight:
    """A path, DataFrame, FlightTable or NetFlight as the NetFlight this net reads."""
    target, src = net.card["target"], net.card["input_source"]
    if isinstance(table, NetFlight):
        flight = table
    elif isinstance(table, FlightTable):
        flight = net_flight_from_df(table.df, str(table.path or "<table>"), target, src)
    elif isinstance(table, pd.DataFrame):
        flight = net_flight_from_df(table, "<table>", target, src)
    else:
        flight = load_net_flight(table, target, src)
    if from_s is not None or to_s is not None:
        flight = flight.crop(from_s, to_s)
    if flight.input_source != src:
        raise FlightTableError(
            f"{flight.source}: pilot inputs from {flight.input_source} columns, the net was "
            f"trained on {src} ({net.card['input_columns']})")
    rate = net.card["rate_hz"]
    if not 0.9 * rate <= flight.rate_hz <= 1.1 * rate:
        raise FlightTableError(f"{flight.source}: sampled at {flight.rate_hz:.4g} Hz, the net was "
                               f"trained at {rate:.4g} Hz (its lagged-rate input is in samples)")
    return flight


def _predict_flight(net: PilotNet, flight: NetFlight):
    cfg = FeatureConfig.from_dict(net.card["feature_config"])
    x, names, y, prev = flight_features(flight, net.card["target"], cfg)
    if names != net.card["features"]:
        raise NetFileError(f"the net's card lists features {net.card['features']}, this code "
                           f"builds {names} (a net from another airwake version?)")
    return x, y, prev, net.predict_numpy(x), net.predict_arx(x), cfg


def predict(net: PilotNet, table, from_s=None, to_s=None) -> pd.DataFrame:
    """Per sample: t_s, <axis>_pred_<unit>, <axis>_resid_<unit> (measured − predicted) and
    history_valid (0 where the features' history reaches before the first sample)."""
    flight = as_net_flight(net, table, from_s, to_s)
    _, y, _, pred, _, cfg = _predict_flight(net, flight)
    sfx = _SUFFIX[net.card["target"]]
    out = {"t_s": flight.t_s}
    for k, col in enumerate(net.card["outputs"]):
        axis = col.split("_")[0]
        out[f"{axis}_pred_{sfx}"] = pred[:, k]
    for k, col in enumerate(net.card["outputs"]):
        axis = col.split("_")[0]
        out[f"{axis}_resid_{sfx}"] = y[:, k] - pred[:, k]
    warm = (flight.t_s - flight.t_s[0]) >= cfg.history_s(flight.rate_hz)
    out["history_valid"] = warm.astype(np.int8)
    return pd.DataFrame(out)


def _training_entry(net: PilotNet, flight: NetFlight):
    for entry in net.card.get("training_flights", []):
        if entry["fingerprint"] == flight.fingerprint:
            return entry
    return None


def held_out_rows(net: PilotNet, flight: NetFlight) -> tuple[np.ndarray, str]:
    """The rows of `flight` this net never trained or early-stopped on: a training flight's
    test rows (its last part, or its test blocks), or every row of another flight past the
    features' history."""
    entry = _training_entry(net, flight)
    if entry is not None:
        labels = unrle(entry["labels_rle"])
        if labels.size != len(flight):
            raise NetFileError(f"{flight.source}: matches a training flight of the net but has "
                               f"{len(flight)} rows, the card {labels.size}")
        split = net.card.get("split", {})
        if split.get("order", "blocks") == "blocks":
            return labels == TEST, "test blocks of a training flight"
        return labels == TEST, (f"test rows of a training flight (its last "
                                f"{100 * split.get('test_fraction', 0.2):.0f} %)")
    cfg = FeatureConfig.from_dict(net.card["feature_config"])
    rows = (flight.t_s - flight.t_s[0]) >= cfg.history_s(flight.rate_hz)
    return rows, "whole flight (not a training flight)"


def evaluate_net(net: PilotNet, flights) -> dict:
    """Scores per flight and over all flights' held-out rows (see held_out_rows); a
    simulated flight with truth_* columns of the target is also scored against them."""
    target = net.card["target"]
    per_flight, parts = [], []
    for flight in flights:
        x, y, prev, pred, arx, _ = _predict_flight(net, flight)
        rows, what = held_out_rows(net, flight)
        y_lp = smoothed_target(y, flight.rate_hz)
        scores = score_rows(target, y, y_lp, pred, arx, prev, rows, flight.truth)
        per_flight.append({"path": flight.source, "scored": what, **scores})
        parts.append([None if a is None else a[rows]
                      for a in (y, y_lp, pred, arx, prev, flight.truth)])
    cat = [np.concatenate([p[i] for p in parts]) if all(p[i] is not None for p in parts)
           else None for i in range(6)]
    overall = score_rows(target, *cat[:5], np.ones(len(cat[0]), bool), cat[5])
    return {"target": target, "unit": UNITS[target], "flights": per_flight, "overall": overall}
