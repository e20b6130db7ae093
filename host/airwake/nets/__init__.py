"""Pilot-input compensation networks (reference ch. 2 §2.1.4-2.2.2, §4.3).

Networks predict the body rates (or roll/pitch angular accelerations) a helicopter's
pilot inputs explain; what they cannot predict is the disturbance (the airwake).

    from airwake.nets import load_net_flight, train_net, save_net, load_net, predict
    net = train_net([load_net_flight("still.parquet")], target="rates", seed=0)
    save_net(net, "rates.pt")
    residuals = predict(load_net("rates.pt"), "ship.parquet")
    # -> t_s, p_pred_rad_s, …, p_resid_rad_s, …, history_valid

Files: features (eq 2.1-2.3), data (partial flight tables), split (chronological or time
blocks), model (the network, its .pt file and model card), train (AdamW, PSO eq 4.11, ARX),
metrics, evaluate (predict / held-out scores), commands (`airwake nets`), bench. The names
below are imported on first use (`airwake.lazy`): `airwake --help` must not load torch.
"""

from airwake.lazy import lazy_exports

__all__ = [
    "AdamWConfig", "FeatureConfig", "NetFileError", "NetFlight", "PSOConfig", "PilotNet",
    "SplitConfig", "build_features", "evaluate_net", "load_net", "load_net_flight",
    "net_flight_from_df", "predict", "save_net", "train_net",
]
__getattr__, __dir__ = lazy_exports(__name__, {
    **dict.fromkeys(["NetFlight", "load_net_flight", "net_flight_from_df"], "airwake.nets.data"),
    **dict.fromkeys(["evaluate_net", "predict"], "airwake.nets.evaluate"),
    **dict.fromkeys(["FeatureConfig", "build_features"], "airwake.nets.features"),
    **dict.fromkeys(["NetFileError", "PilotNet", "load_net", "save_net"], "airwake.nets.model"),
    "SplitConfig": "airwake.nets.split",
    **dict.fromkeys(["AdamWConfig", "PSOConfig", "train_net"], "airwake.nets.train"),
})
