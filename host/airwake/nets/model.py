"""The pilot-compensation network and its file: weights + model card, no pickled objects.

    net = PilotNet(n_features, n_outputs, hidden=(16, 8))
    y = net.predict_numpy(X)          # (T, F) features -> (T, K) in the target's SI unit
    save_net(net, "net.pt");  net = load_net("net.pt")   # net.card: the model card

The network is the linear ARX map plus one small tanh MLP per output axis (the reference
trained one network per channel, §2.2.2), all on standardised features:

    z = (x - x_mean) / x_std
    y_k = x_base(k) + y_mean_k + y_std_k * (A_k z + b_k + MLP_k(z))

x_base(k) is the feature in `base_columns[k]` (for the rate target: the fed-back previous
rate of that axis) or 0: the net then learns the change since then, and where it has to
extrapolate it falls back towards persistence rather than towards an offset. A (the
skip) starts at a ridge-regularised least-squares solution (the ARX, or the same on the
training rows and their time-stretched copies) and every MLP's last layer at zero, so
training starts from a linear model and early stopping on validation can only keep an
MLP that beats it there (train.AdamWConfig: by default the skip stays put). The .pt file
is a dict of tensors and strings (format, card JSON, state_dict) read with
`torch.load(weights_only=True)`.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import torch
from torch import nn

from airwake.errors import AirwakeError

FORMAT = "airwake-net/1"


class NetFileError(AirwakeError):
    """A network file that cannot be used (file and what is wrong named)."""


class PilotNet(nn.Module):
    """ARX skip + per-axis MLPs on standardised features; see the module docstring."""

    def __init__(self, n_features: int, n_outputs: int, hidden=(16, 8),
                 base_columns=None, card: dict | None = None) -> None:
        super().__init__()
        self.card = dict(card or {})  # the model card (train_net / load_net fill it)
        if base_columns is not None:
            base_columns = tuple(int(c) for c in base_columns)
            if len(base_columns) != n_outputs or not all(0 <= c < n_features for c in base_columns):
                raise ValueError(f"PilotNet base_columns {base_columns}: need {n_outputs} "
                                 f"feature indexes in [0, {n_features})")
        self.base_columns = base_columns
        if n_features < 1 or n_outputs < 1:
            raise ValueError(
                f"PilotNet needs >= 1 feature and output, got {n_features}, {n_outputs}")
        self.n_features, self.n_outputs = int(n_features), int(n_outputs)
        self.hidden = tuple(int(h) for h in hidden)
        for name, size in (("x_mean", n_features), ("y_mean", n_outputs)):
            self.register_buffer(name, torch.zeros(size, dtype=torch.float64))
        for name, size in (("x_std", n_features), ("y_std", n_outputs)):
            self.register_buffer(name, torch.ones(size, dtype=torch.float64))
        # the least-squares baseline, kept apart from the trained skip for comparison
        self.register_buffer("arx_weight",
                             torch.zeros(n_outputs, n_features + 1, dtype=torch.float64))
        self.skip = nn.Linear(n_features, n_outputs)
        self.mlps = nn.ModuleList(_mlp(n_features, self.hidden) for _ in range(n_outputs))

    def base(self, x) -> torch.Tensor:
        """(N, K) x_base: the base columns of the features, or zeros."""
        x = torch.as_tensor(x, dtype=torch.float64)
        if self.base_columns is None:
            return torch.zeros(x.shape[0], self.n_outputs, dtype=torch.float64)
        return x[:, list(self.base_columns)]

    def set_scaling(self, x: np.ndarray, y: np.ndarray) -> None:
        """Standardise with the training rows' mean and std (a constant column: std 1)."""
        y = y - self.base(x).numpy()
        xs, ys = x.std(axis=0), y.std(axis=0)
        self.x_mean.copy_(torch.as_tensor(x.mean(axis=0)))
        self.x_std.copy_(torch.as_tensor(np.where(xs > 1e-12, xs, 1.0)))
        self.y_mean.copy_(torch.as_tensor(y.mean(axis=0)))
        self.y_std.copy_(torch.as_tensor(np.where(ys > 1e-12, ys, 1.0)))

    def standardise_target(self, x, y) -> torch.Tensor:
        """Targets (N, K) in SI -> what forward_standard predicts."""
        r = torch.as_tensor(y, dtype=torch.float64) - self.base(x)
        return ((r - self.y_mean) / self.y_std).to(torch.float32)

    def standardise(self, x) -> torch.Tensor:
        x = torch.as_tensor(x, dtype=torch.float64)
        return ((x - self.x_mean) / self.x_std).to(torch.float32)

    def forward_standard(self, z: torch.Tensor) -> torch.Tensor:
        """Standardised features (N, F) -> standardised outputs (N, K)."""
        return self.skip(z) + torch.cat([m(z) for m in self.mlps], dim=-1)

    def forward(self, x) -> torch.Tensor:
        out = self.forward_standard(self.standardise(x)).to(torch.float64)
        return out * self.y_std + self.y_mean + self.base(x)

    @torch.no_grad()
    def predict_numpy(self, x: np.ndarray) -> np.ndarray:
        return self.forward(x).numpy()

    def set_arx(self, weight_standard: np.ndarray, start: np.ndarray | None = None) -> None:
        """Store the ARX solution (K, F+1) on standardised data and start the skip there,
        or at `start` (the same least squares on more rows: train_net's time-stretched
        copies); every MLP's output layer starts at zero (the net starts linear)."""
        w = torch.as_tensor(weight_standard, dtype=torch.float64)
        self.arx_weight.copy_(w)
        if start is not None:
            w = torch.as_tensor(start, dtype=torch.float64)
        with torch.no_grad():
            self.skip.weight.copy_(w[:, :-1].float())
            self.skip.bias.copy_(w[:, -1].float())
            for m in self.mlps:
                m[-1].weight.zero_()
                m[-1].bias.zero_()

    @torch.no_grad()
    def predict_arx(self, x: np.ndarray) -> np.ndarray:
        z = (torch.as_tensor(x, dtype=torch.float64) - self.x_mean) / self.x_std
        out = z @ self.arx_weight[:, :-1].T + self.arx_weight[:, -1]
        return (out * self.y_std + self.y_mean + self.base(x)).numpy()


def _mlp(n_in: int, hidden) -> nn.Sequential:
    layers: list[nn.Module] = []
    for h in hidden:
        layers += [nn.Linear(n_in, h), nn.Tanh()]
        n_in = h
    layers.append(nn.Linear(n_in, 1))
    return nn.Sequential(*layers)


def fit_arx(z: np.ndarray, y: np.ndarray, ridge=1e-3) -> np.ndarray:
    """Least squares y ~ [z, 1] W^T on standardised data, (N, F), (N, K) -> W (K, F+1),
    with a ridge penalty ridge * N * |A|^2 on the weights (not the bias): the line-fit
    intercepts and the low-passed inputs are nearly collinear, and unpenalised their
    large opposite coefficients extrapolate badly. `ridge` is one value or one per output
    (train.choose_arx_ridge picks them on the validation blocks)."""
    a = np.column_stack([z, np.ones(len(z))])
    gram, rhs = a.T @ a, a.T @ y

    def solve(r: float, b: np.ndarray) -> np.ndarray:
        reg = r * len(z) * np.eye(a.shape[1])
        reg[-1, -1] = 0.0
        return np.linalg.solve(gram + reg, b)

    if np.ndim(ridge) == 0:
        return solve(float(ridge), rhs).T
    ridges = [float(r) for r in ridge]
    if len(ridges) != y.shape[1]:
        raise ValueError(f"fit_arx: {len(ridges)} ridge values for {y.shape[1]} outputs")
    return np.array([solve(r, rhs[:, k]) for k, r in enumerate(ridges)])


def save_net(net: PilotNet, path) -> Path:
    """Write weights + net.card; the card carries what load_net needs to rebuild the net."""
    p = Path(path)
    if p.suffix != ".pt":
        raise NetFileError(f"{p}: a network file ends in .pt")
    if not p.parent.is_dir():
        raise NetFileError(f"{p}: folder {p.parent} does not exist")
    card = {**net.card, "format": FORMAT, "n_features": net.n_features,
            "n_outputs": net.n_outputs, "hidden": list(net.hidden),
            "base_columns": None if net.base_columns is None else list(net.base_columns)}
    blob = {"format": FORMAT, "card_json": json.dumps(card, sort_keys=True),
            "state_dict": {k: v.detach().clone() for k, v in net.state_dict().items()}}
    tmp = p.with_name(f".{p.name}.tmp")
    torch.save(blob, tmp)
    tmp.replace(p)
    return p


def load_net(path) -> PilotNet:
    """Read a file written by save_net; nothing but tensors and strings is unpickled."""
    p = Path(path)
    if not p.is_file():
        raise NetFileError(f"network file {p} not found")
    try:
        blob = torch.load(p, map_location="cpu", weights_only=True)
    except Exception as exc:  # noqa: BLE001 — a corrupt or foreign file is a user error
        raise NetFileError(f"{p}: not a network file ({type(exc).__name__}: "
                           f"{str(exc).splitlines()[0] if str(exc) else ''})") from None
    if not isinstance(blob, dict) or blob.get("format") != FORMAT:
        fmt = blob.get("format") if isinstance(blob, dict) else type(blob).__name__
        raise NetFileError(f"{p}: format {fmt!r}, expected {FORMAT!r}")
    card = json.loads(blob["card_json"])
    net = PilotNet(card["n_features"], card["n_outputs"], tuple(card["hidden"]),
                   card.get("base_columns"), card)
    try:
        net.load_state_dict(blob["state_dict"], strict=True)
    except RuntimeError as exc:
        first = str(exc).splitlines()[0]
        raise NetFileError(f"{p}: weights do not match the card: {first}") from None
    net.eval()
    return net
