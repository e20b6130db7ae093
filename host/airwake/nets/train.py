"""Training the pilot-compensation networks: AdamW with early stopping, or the
reference's particle swarm (eq 4.11), on a chronological (or time-block) split, with
the linear ARX baseline fitted on the same rows.

    net = train_net([flight_a, flight_b], target="rates", trainer="adamw", seed=0)
    net.card["metrics"]["test"]      # net / arx / persistence per axis, held-out blocks

Deterministic: one torch thread, seeded torch and numpy generators, no shuffling that
does not come from them.
"""

from __future__ import annotations

import platform
import time
from dataclasses import asdict, dataclass, field

import numpy as np
import torch

from airwake.nets.data import INPUT_SOURCES, NetFlight
from airwake.nets.features import FeatureConfig, build_features, lagged
from airwake.nets.metrics import score_sets, smoothed_target
from airwake.nets.model import PilotNet, fit_arx
from airwake.nets.split import TEST, TRAIN, VAL, SplitConfig, split_labels

OUTPUTS = {"rates": ("p_rad_s", "q_rad_s", "r_rad_s"), "accel": ("pdot_rad_s2", "qdot_rad_s2")}
DEFAULT_RATE_LAG = {"rates": 1, "accel": 0}
# the rate target feeds back 30 past samples of each rate (0.2-0.25 s at 123-150 Hz): a
# real gyro's rotor vibration lines are predictable from them (docs/networks.md)
DEFAULT_RATE_HISTORY = {"rates": 30, "accel": 1}
# the training rows played 2 % and 1 % slower and faster (every rotor vibration line on a
# real gyro moves with the rotor speed, which changes in flight); "val": the net trains on
# them where its linear start fitted with them is better on the validation rows
STRETCH_FACTORS = (0.98, 0.99, 1.01, 1.02)
DEFAULT_TIME_STRETCH = {"rates": "val", "accel": ()}
# hidden layers of each axis' MLP
DEFAULT_HIDDEN = {"rates": (8,), "accel": (16, 8)}
TRAIN_TARGETS = ("measured", "lowpass")
# ridge values (x N, standardised weights) tried per axis when arx_ridge="val"
ARX_RIDGE_GRID = (1e-5, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1, 3e-1)

# eq 4.11 as the reference wrote it for the networks (§4.3.2): inertia m, C1, C2
PSO_INERTIA, PSO_C1, PSO_C2 = 0.2, 0.1, 0.2


@dataclass(frozen=True)
class AdamWConfig:
    """AdamW on the standardised MSE from the linear least-squares start, early stopping
    on the validation rows (docs/networks.md, "Network and training")."""

    lr: float = 2e-3
    weight_decay: float = 1e-4
    batch_size: int = 256
    max_epochs: int = 300
    patience: int = 10
    # per_axis: each output axis keeps the weights of its own best validation epoch (its
    # skip row and its MLP touch that axis only), so no axis ends worse on validation than
    # its linear start; stop when no axis has improved for `patience` epochs
    per_axis: bool = True
    # train_skip: AdamW also moves the linear skip away from its least-squares start
    # (False: the skip stays the least-squares solution, the MLPs learn what it leaves)
    train_skip: bool = False
    # min_gain_se: an epoch is kept only where its validation MSE is below the start's
    # (epoch 0, the linear least-squares model) by more than min_gain_se standard errors
    # of the difference, the error taken over means of `se_block_s` seconds of validation
    # rows (neighbouring rows' errors are correlated); 0: any lower validation MSE counts
    min_gain_se: float = 2.0
    se_block_s: float = 1.0


@dataclass(frozen=True)
class PSOConfig:
    particles: int = 48
    iterations: int = 300
    cost_rows: int = 1500
    spread: float = 0.5
    patience: int = 60
    bound: float = 10.0


@dataclass
class Dataset:
    """Feature rows of several flights with their set labels."""

    x: np.ndarray  # (N, F)
    y: np.ndarray  # (N, K) target in SI
    y_lp: np.ndarray  # (N, K) the target low-passed per flight (metrics.SCORE_LOWPASS)
    prev: np.ndarray | None  # (N, K) persistence baseline (rates lagged), None for accel
    labels: np.ndarray  # (N,) TRAIN / VAL / TEST / GUARD
    names: list[str]
    flights: list[dict] = field(default_factory=list)
    # (N, K) the same low-pass within each run of one set (train_target="lowpass"): the
    # centred kernel never reads across a block boundary into another set's rows
    y_lp_sets: np.ndarray | None = None
    # extra training rows: the training runs time-stretched (train_net's time_stretch);
    # x, y, the within-run low-passed y; empty arrays when none
    x_stretch: np.ndarray | None = None
    y_stretch: np.ndarray | None = None
    y_lp_stretch: np.ndarray | None = None
    # (N,) each row's time, the flights laid end to end (the validation gate's blocks)
    t_s: np.ndarray | None = None

    @property
    def t_val_s(self) -> np.ndarray:
        return self.t_s[self.labels == VAL]


def flight_features(flight: NetFlight, target: str, config: FeatureConfig):
    """X (T, F), names, y (T, K), persistence (T, K) or None for one flight."""
    if target == "rates" and config.use_rates and config.rate_lag_samples < 1:
        raise ValueError("the rate target needs rate_lag_samples >= 1 (lag 0 is the answer)")
    x, names = build_features(flight.inputs, flight.roll_rad, flight.pitch_rad,
                              flight.rates_rad_s, flight.rate_hz, config)
    if target == "rates":
        y = flight.rates_rad_s
        # persistence: the fed-back rates, or (pilot-only net) the previous sample's
        prev = x[:, -3:] if config.use_rates else lagged(y, 1)
    else:
        y = flight.accel_rad_s2
        prev = None
    return x, names, y, prev


def build_dataset(flights, target: str, config: FeatureConfig, split: SplitConfig,
                  rng, time_stretch=()) -> Dataset:
    xs, ys, lps, lss, ps, ls, meta, names = [], [], [], [], [], [], [], []
    sx, sy, slp, ts = [], [], [], []
    t_end = 0.0
    for f in flights:
        ts.append(f.t_s - f.t_s[0] + t_end)
        t_end = ts[-1][-1] + 10.0
        x, names, y, prev = flight_features(f, target, config)
        labels = split_labels(f.t_s, split, config.history_s(f.rate_hz), rng)
        for factor in time_stretch:
            for a, b, c in stretched_training_rows(f, labels, factor, target, config):
                sx.append(a)
                sy.append(b)
                slp.append(c)
        xs.append(x)
        ys.append(y)
        lps.append(smoothed_target(y, f.rate_hz))
        lss.append(lowpass_within_sets(y, labels, f.rate_hz))
        ps.append(prev)
        ls.append(labels)
        meta.append({"path": f.source, "fingerprint": f.fingerprint, "rows": len(f),
                     "rate_hz": f.rate_hz, "input_source": f.input_source,
                     "t_range_s": [float(f.t_s[0]), float(f.t_s[-1])],
                     "labels_rle": _rle(labels),
                     **{f"{k}_rows": int((labels == v).sum())
                        for k, v in (("train", TRAIN), ("val", VAL), ("test", TEST))}})
    prev = None if target == "accel" else np.concatenate(ps)
    k = ys[0].shape[1]

    def stack(parts, width: int) -> np.ndarray:
        return np.concatenate(parts) if parts else np.empty((0, width))

    return Dataset(np.concatenate(xs), np.concatenate(ys), np.concatenate(lps), prev,
                   np.concatenate(ls), names, meta, np.concatenate(lss),
                   stack(sx, len(names)), stack(sy, k), stack(slp, k), np.concatenate(ts))


def check_time_stretch(factors) -> tuple[float, ...]:
    """The time-stretch factors as floats, each in [0.5, 2] and not 1 (ValueError)."""
    out = tuple(float(v) for v in factors)
    for v in out:
        if not (np.isfinite(v) and 0.5 <= v <= 2.0) or v == 1.0:
            raise ValueError(f"time_stretch factors must be in [0.5, 2] and not 1, got {v!r}")
    return out


def played_faster(v: np.ndarray, factor: float) -> np.ndarray:
    """v (n, ...) played `factor` times faster at the same sample rate: band-limited (FFT)
    resampling to round(n / factor) samples. The end-to-end line is taken out first (the
    FFT's periodic extension then has no jump) and put back after."""
    from scipy.signal import resample

    v = np.asarray(v, float)
    n = v.shape[0]
    m = int(round(n / factor))

    def line(k: int) -> np.ndarray:
        return v[0] + np.multiply.outer(np.linspace(0.0, 1.0, k), v[-1] - v[0])

    return resample(v - line(n), m, axis=0) + line(m)


def stretched_training_rows(flight: NetFlight, labels: np.ndarray, factor: float, target: str,
                            config: FeatureConfig):
    """Each run of TRAIN rows of `flight` played `factor` times faster at the same sample
    rate (every channel alike: a 34 Hz vibration line moves to factor × 34 Hz), as
    (x, y, y low-passed within the run) of its rows past the features' history and away
    from the run's ends. Only training rows are read."""
    edge = 12  # samples at either end where the resampled run still rings
    skip = int(np.ceil(config.history_s(flight.rate_hz) * flight.rate_hz)) + edge
    change = np.flatnonzero(np.diff(labels)) + 1
    for a, b in zip(np.r_[0, change], np.r_[change, len(labels)], strict=True):
        if labels[a] != TRAIN or b - a < 2 * skip + 20:
            continue

        def play(v, a=a, b=b):
            return played_faster(v[a:b], factor)

        # d/dt of a signal played faster is that much larger
        accel = None if flight.accel_rad_s2 is None else play(flight.accel_rad_s2) * factor
        rates = play(flight.rates_rad_s)
        n = rates.shape[0]
        seg = NetFlight(flight.source, flight.t_s[a] + np.arange(n) / flight.rate_hz,
                        play(flight.inputs), flight.input_source, play(flight.roll_rad),
                        play(flight.pitch_rad), rates, accel, flight.rate_hz, flight.fingerprint)
        x, _, y, _ = flight_features(seg, target, config)
        y_lp = smoothed_target(y, flight.rate_hz)
        keep = slice(skip, n - edge)
        yield x[keep], y[keep], y_lp[keep]


def lowpass_within_sets(y: np.ndarray, labels: np.ndarray, rate_hz: float) -> np.ndarray:
    """smoothed_target applied to each run of equal labels on its own (edge-padded at
    the run's ends), so a training or validation target never reads a test row."""
    out = np.empty_like(np.asarray(y, dtype=float))
    change = np.flatnonzero(np.diff(labels)) + 1
    for a, b in zip(np.r_[0, change], np.r_[change, len(labels)], strict=True):
        out[a:b] = smoothed_target(y[a:b], rate_hz)
    return out


def _rle(labels: np.ndarray) -> list[list[int]]:
    """Run-length code [[label, count], ...]: the card stores each flight's split."""
    change = np.flatnonzero(np.diff(labels)) + 1
    starts = np.r_[0, change]
    counts = np.diff(np.r_[starts, labels.size])
    return [[int(labels[s]), int(c)] for s, c in zip(starts, counts, strict=True)]


def unrle(runs) -> np.ndarray:
    return np.concatenate([np.full(c, lab, dtype=int) for lab, c in runs])


class _ValGate:
    """Validation losses per axis and whether they beat the start's by `min_gain_se`
    standard errors of the per-row difference (AdamWConfig.min_gain_se, block_mean_gain
    over the rows' times t_va_s; None: 1 s = 150 rows)."""

    def __init__(self, net: PilotNet, z_va, y_va, cfg: AdamWConfig, t_va_s=None):
        self.net, self.z_va, self.y_va, self.cfg = net, z_va, y_va, cfg
        self.t = np.arange(y_va.shape[0]) / 150.0 if t_va_s is None else np.asarray(t_va_s)
        self.start_rows = self.rows()

    def rows(self) -> np.ndarray:
        """(N, K) squared validation errors of the net as it is now."""
        with torch.no_grad():
            return ((self.net.forward_standard(self.z_va) - self.y_va) ** 2).double().numpy()

    def losses(self) -> tuple[np.ndarray, np.ndarray]:
        """(per-axis MSE, per-axis 'below the start by min_gain_se standard errors')."""
        e = self.rows()
        mse = e.mean(axis=0)
        if self.cfg.min_gain_se <= 0:
            return mse, mse < self.start_rows.mean(axis=0)
        beats = []
        for k in range(e.shape[1]):
            mean, se = block_mean_gain(e[:, k] - self.start_rows[:, k], self.t,
                                       self.cfg.se_block_s)
            beats.append(mean < -self.cfg.min_gain_se * se)
        return mse, np.array(beats)


def train_adamw(net: PilotNet, z_tr, y_tr, z_va, y_va, cfg: AdamWConfig, gen: torch.Generator,
                progress=None, t_va_s=None) -> dict:
    """Minibatch AdamW on the standardised MSE; keeps the weights of the best validation
    loss (epoch 0 = the linear start; with min_gain_se, only epochs that beat it by that
    many standard errors count) and stops after `patience` epochs without a better one.
    t_va_s: the validation rows' times (the standard error's blocks)."""
    params = net.parameters() if cfg.train_skip else net.mlps.parameters()
    opt = torch.optim.AdamW(params, lr=cfg.lr, weight_decay=cfg.weight_decay)
    n = z_tr.shape[0]
    gate = _ValGate(net, z_va, y_va, cfg, t_va_s)

    if cfg.per_axis:
        return _train_adamw_per_axis(net, opt, z_tr, y_tr, gate, cfg, gen, progress)
    best = float(gate.losses()[0].mean())
    best_state = {k: v.clone() for k, v in net.state_dict().items()}
    best_epoch, history = 0, [best]
    for epoch in range(1, cfg.max_epochs + 1):
        net.train()
        perm = torch.randperm(n, generator=gen)
        for i in range(0, n, cfg.batch_size):
            idx = perm[i:i + cfg.batch_size]
            opt.zero_grad()
            loss = ((net.forward_standard(z_tr[idx]) - y_tr[idx]) ** 2).mean()
            loss.backward()
            opt.step()
        net.eval()
        mse, beats_start = gate.losses()
        v = float(mse.mean())
        history.append(v)
        if v < best and (cfg.min_gain_se <= 0 or beats_start.all()):
            best, best_epoch = v, epoch
            best_state = {k: t.clone() for k, t in net.state_dict().items()}
        if progress is not None:
            progress.update(epoch, f"val {v:.4g} (best {best:.4g} at {best_epoch})")
        if epoch - best_epoch >= cfg.patience:
            break
    net.load_state_dict(best_state)
    return {"epochs_run": len(history) - 1, "best_epoch": best_epoch,
            "best_val_mse_standard": best, "val_history": [round(h, 6) for h in history]}


def _epoch(net: PilotNet, opt, z_tr, y_tr, batch_size: int, gen) -> None:
    net.train()
    perm = torch.randperm(z_tr.shape[0], generator=gen)
    for i in range(0, z_tr.shape[0], batch_size):
        idx = perm[i:i + batch_size]
        opt.zero_grad()
        loss = ((net.forward_standard(z_tr[idx]) - y_tr[idx]) ** 2).mean()
        loss.backward()
        opt.step()
    net.eval()


def _axis_state(net: PilotNet, k: int) -> dict:
    """The parameters that act on output k only: its skip row and its MLP."""
    return {"skip_w": net.skip.weight[k].detach().clone(),
            "skip_b": net.skip.bias[k].detach().clone(),
            "mlp": {n: t.detach().clone() for n, t in net.mlps[k].state_dict().items()}}


def _set_axis_state(net: PilotNet, k: int, st: dict) -> None:
    with torch.no_grad():
        net.skip.weight[k].copy_(st["skip_w"])
        net.skip.bias[k].copy_(st["skip_b"])
    net.mlps[k].load_state_dict(st["mlp"])


def _train_adamw_per_axis(net: PilotNet, opt, z_tr, y_tr, gate: _ValGate, cfg: AdamWConfig,
                          gen, progress=None) -> dict:
    """train_adamw with early stopping per output axis (AdamWConfig.per_axis)."""
    k_out = net.n_outputs
    best = gate.losses()[0]
    best_states = [_axis_state(net, k) for k in range(k_out)]
    best_epochs, history = np.zeros(k_out, dtype=int), [float(best.mean())]
    for epoch in range(1, cfg.max_epochs + 1):
        _epoch(net, opt, z_tr, y_tr, cfg.batch_size, gen)
        v, beats_start = gate.losses()
        history.append(float(v.mean()))
        for k in np.flatnonzero((v < best) & beats_start):
            best[k], best_epochs[k] = v[k], epoch
            best_states[k] = _axis_state(net, int(k))
        if progress is not None:
            progress.update(epoch, f"val {v.mean():.4g} (best per axis at {best_epochs.tolist()})")
        if epoch - int(best_epochs.max()) >= cfg.patience:
            break
    for k in range(k_out):
        _set_axis_state(net, k, best_states[k])
    return {"epochs_run": len(history) - 1, "best_epoch": int(best_epochs.max()),
            "best_epoch_per_axis": best_epochs.tolist(),
            "best_val_mse_standard": float(best.mean()),
            "best_val_mse_per_axis": [round(float(v), 8) for v in best],
            "start_val_mse_per_axis": [round(float(v), 8)
                                       for v in gate.start_rows.mean(axis=0)],
            "val_history": [round(h, 6) for h in history]}


def block_means(values: np.ndarray, t_s: np.ndarray, block_s: float) -> np.ndarray:
    """Means of `values` (N,) or (N, K) over blocks of `block_s` seconds of their rows'
    times t_s (neighbouring rows' errors are correlated, blocks of them much less)."""
    block = np.floor((t_s - t_s[0]) / block_s).astype(int)
    _, inv = np.unique(block, return_inverse=True)
    v = np.asarray(values, float).reshape(len(t_s), -1)
    sums = np.stack([np.bincount(inv, weights=v[:, k]) for k in range(v.shape[1])], axis=1)
    means = sums / np.bincount(inv)[:, None]
    return means if np.ndim(values) > 1 else means[:, 0]


def block_mean_gain(diff: np.ndarray, t_s: np.ndarray, block_s: float) -> tuple[float, float]:
    """Mean and standard error of a per-row difference (N,), the error over its means of
    `block_s` seconds (block_means). Fewer than 2 blocks: the standard error is inf."""
    if diff.size == 0:
        return 0.0, float("inf")
    means = block_means(diff, t_s, block_s)
    if means.size < 2:
        return float(diff.mean()), float("inf")
    return float(diff.mean()), float(means.std(ddof=1) / np.sqrt(means.size))


def stretch_worse_on_validation(z_va, y_va, w_plain, w_stretched, t_va_s,
                                cfg: AdamWConfig) -> dict:
    """Whether the linear start fitted with the time-stretched rows is worse on the
    validation rows than the one without: the log of their squared-error ratio (summed
    over the axes, standardised units) per `se_block_s` block, its mean above
    cfg.min_gain_se standard errors. A ratio per block, so a few blocks of flying that
    neither model has seen (errors ten times the rest) do not decide it."""
    a = np.column_stack([z_va, np.ones(len(z_va))])
    e_plain = ((a @ w_plain.T - y_va) ** 2).sum(axis=1)
    e_st = ((a @ w_stretched.T - y_va) ** 2).sum(axis=1)
    out = {"none": float(e_plain.mean()), "stretched": float(e_st.mean())}
    if len(e_plain) == 0:
        return {**out, "log_ratio": 0.0, "log_ratio_se": float("inf"), "worse": False}
    means = block_means(np.column_stack([e_plain, e_st]), t_va_s, cfg.se_block_s)
    log_ratio = np.log(np.maximum(means[:, 1], 1e-300) / np.maximum(means[:, 0], 1e-300))
    se = (float(log_ratio.std(ddof=1) / np.sqrt(log_ratio.size)) if log_ratio.size > 1
          else float("inf"))
    mean = float(log_ratio.mean())
    return {**out, "log_ratio": mean, "log_ratio_se": se,
            "worse": bool(mean > max(cfg.min_gain_se, 0.0) * se)}


def choose_arx_ridge(z_tr, y_tr, z_va, y_va, grid=ARX_RIDGE_GRID):
    """Per output axis, the ridge of `grid` whose ARX fit on the training rows has the
    smallest validation RMS (standardised data; the test rows are not read).
    Returns (ridges per axis, {ridge: [val RMS per axis]})."""
    a_va = np.column_stack([z_va, np.ones(len(z_va))])
    table = {}
    for r in grid:
        w = fit_arx(z_tr, y_tr, r)
        table[float(r)] = np.sqrt(((a_va @ w.T - y_va) ** 2).mean(axis=0))
    rms = np.array([table[float(r)] for r in grid])
    ridges = [float(grid[i]) for i in rms.argmin(axis=0)]
    return ridges, {str(r): [round(float(v), 6) for v in table[float(r)]] for r in grid}


def _flat(net: PilotNet) -> np.ndarray:
    return torch.nn.utils.parameters_to_vector(net.parameters()).detach().double().numpy()


def batched_forward_standard(net: PilotNet, flat: torch.Tensor, z: torch.Tensor) -> torch.Tensor:
    """net.forward_standard for N parameter vectors at once: flat (N, D), z (M, F) ->
    (N, M, K). The vectors are laid out as parameters_to_vector(net.parameters())."""
    pieces, off = [], 0
    for p in net.parameters():
        pieces.append(flat[:, off:off + p.numel()].reshape(flat.shape[0], *p.shape))
        off += p.numel()
    it = iter(pieces)
    w, b = next(it), next(it)
    out = torch.einsum("nkf,mf->nmk", w, z) + b[:, None, :]
    cols = []
    for mlp in net.mlps:
        h = z.expand(flat.shape[0], *z.shape)
        for layer in mlp:
            if isinstance(layer, torch.nn.Linear):
                w, b = next(it), next(it)
                h = torch.baddbmm(b[:, None, :], h, w.transpose(1, 2))
            else:
                h = torch.tanh(h)
        cols.append(h)
    return out + torch.cat(cols, dim=-1)


def train_pso(net: PilotNet, z_tr, y_tr, z_va, y_va, cfg: PSOConfig, rng, progress=None) -> dict:
    """The reference's trainer (§4.3.2-4.3.3): a swarm over every weight and bias, eq 4.11
    with m = 0.2, C1 = 0.1, C2 = 0.2, cost = RMS error on a fixed seeded subset of the
    training rows; the global best is checked on validation and the best one kept
    (stopping after `patience` iterations without a better one). The swarm's first
    particle is the ARX start, so the result is never worse than it on the cost rows."""
    from airwake.calibrate.pso import initial_swarm, pso_update

    start = _flat(net)
    d = start.size
    lo = -np.maximum(cfg.bound, 2 * np.abs(start))
    hi = -lo
    free = np.ones(d, bool)
    rows = rng.choice(z_tr.shape[0], size=min(cfg.cost_rows, z_tr.shape[0]), replace=False)
    zc, yc = z_tr[np.sort(rows)], y_tr[np.sort(rows)]

    def cost(x: np.ndarray, z, y) -> np.ndarray:
        with torch.no_grad():
            pred = batched_forward_standard(net, torch.as_tensor(x, dtype=torch.float32), z)
            return torch.sqrt(((pred - y[None]) ** 2).mean(dim=(1, 2))).double().numpy()

    x = initial_swarm(start, cfg.particles, rng, free, lo, hi, cfg.spread)
    v = np.zeros_like(x)
    pcost = cost(x, zc, yc)
    pbest = x.copy()
    g = int(np.argmin(pcost))
    gbest, gcost = pbest[g].copy(), float(pcost[g])
    best_val = float(cost(gbest[None], z_va, y_va)[0])
    best_vec, best_it, history = gbest.copy(), 0, [gcost]
    for it in range(1, cfg.iterations + 1):
        x, v = pso_update(x, v, pbest, gbest, rng, free, lo, hi,
                          inertia=PSO_INERTIA, c1=PSO_C1, c2=PSO_C2)
        c = cost(x, zc, yc)
        better = c < pcost
        pbest[better], pcost[better] = x[better], c[better]
        g = int(np.argmin(pcost))
        if pcost[g] < gcost:
            gbest, gcost = pbest[g].copy(), float(pcost[g])
            val = float(cost(gbest[None], z_va, y_va)[0])
            if val < best_val:
                best_val, best_vec, best_it = val, gbest.copy(), it
        history.append(gcost)
        if progress is not None:
            progress.update(it, f"cost {gcost:.4g}, val {best_val:.4g}")
        if it - best_it >= cfg.patience:
            break
    torch.nn.utils.vector_to_parameters(torch.as_tensor(best_vec, dtype=torch.float32),
                                        net.parameters())
    return {"iterations_run": len(history) - 1, "best_iteration": best_it,
            "best_val_rms_standard": best_val, "inertia": PSO_INERTIA, "c1": PSO_C1,
            "c2": PSO_C2, "dimensions": int(d),
            "cost_history": [round(h, 6) for h in history[:: max(1, len(history) // 50)]]}


def train_net(flights, target: str = "rates", trainer: str = "adamw", seed: int = 0,
              features: FeatureConfig | None = None, split: SplitConfig | None = None,
              hidden=None, adamw: AdamWConfig | None = None, pso: PSOConfig | None = None,
              progress: bool = False, threads: int = 1, train_target: str = "measured",
              arx_ridge: float | str = 1e-3, time_stretch=None) -> PilotNet:
    """Train a pilot-compensation net on `flights` (NetFlight list); returns it with its
    model card (`net.card`: features, windows, flights and their split, metrics on the
    held-out test rows for the net, the ARX baseline and persistence, versions).

    train_target: "measured" (the logged target) or "lowpass" (it low-passed with
        metrics.SCORE_LOWPASS, the centred eq 2.3, within each run of one set so no target
        reads a test row; the target only, the features stay causal): where the gyro
        carries rotor vibration, fit the dynamics, not the tone.
        Net, ARX and early stopping all use it; scores are against both as always.
    arx_ridge: the ARX ridge (x N on standardised weights), or "val": per axis the value of
        ARX_RIDGE_GRID with the smallest validation RMS (card: arx_ridge, arx_ridge_val).
    time_stretch: factors (e.g. 0.98, 1.02) by which the training rows are also played
        faster or slower, as extra training rows of the net; () for none; "val" (the rate
        target's default, DEFAULT_TIME_STRETCH): STRETCH_FACTORS if the linear start fitted
        with them has the smaller validation MSE, else none (card: time_stretch,
        time_stretch_val). The ARX baseline stays least squares on the real training rows.
    features: default FeatureConfig with DEFAULT_RATE_LAG and DEFAULT_RATE_HISTORY.
    hidden: each axis' MLP hidden sizes (DEFAULT_HIDDEN).
    split: default SplitConfig(): chronological.
    """
    if target not in OUTPUTS:
        raise ValueError(f"target must be one of {tuple(OUTPUTS)}, got {target!r}")
    if trainer not in ("adamw", "pso"):
        raise ValueError(f"trainer must be 'adamw' or 'pso', got {trainer!r}")
    if not flights:
        raise ValueError("train_net needs at least one flight")
    if train_target not in TRAIN_TARGETS:
        raise ValueError(f"train_target must be one of {TRAIN_TARGETS}, got {train_target!r}")
    if isinstance(arx_ridge, str) and arx_ridge != "val":
        raise ValueError(f"arx_ridge must be a number >= 0 or 'val', got {arx_ridge!r}")
    if not isinstance(arx_ridge, str) and not (np.isfinite(arx_ridge) and arx_ridge >= 0):
        raise ValueError(f"arx_ridge must be a number >= 0 or 'val', got {arx_ridge!r}")
    sources = {f.input_source for f in flights}
    if len(sources) > 1:
        raise ValueError(f"flights mix pilot-input sources {sorted(sources)}: "
                         + ", ".join(f"{f.source}: {f.input_source}" for f in flights))
    rates = [f.rate_hz for f in flights]
    if max(rates) > 1.1 * min(rates):
        raise ValueError(f"flights sampled at different rates {[round(r, 3) for r in rates]} Hz")
    features = features or FeatureConfig(rate_lag_samples=DEFAULT_RATE_LAG[target],
                                         rate_history_samples=DEFAULT_RATE_HISTORY[target])
    split = split or SplitConfig()
    hidden = DEFAULT_HIDDEN[target] if hidden is None else tuple(hidden)
    if time_stretch is None:
        time_stretch = DEFAULT_TIME_STRETCH[target]
    choose_stretch = isinstance(time_stretch, str)
    if choose_stretch and time_stretch != "val":
        raise ValueError(f"time_stretch must be factors or 'val', got {time_stretch!r}")
    time_stretch = check_time_stretch(STRETCH_FACTORS if choose_stretch else time_stretch)
    t0 = time.perf_counter()
    old_threads = torch.get_num_threads()
    torch.set_num_threads(threads)
    try:
        rng = np.random.default_rng(seed)
        torch.manual_seed(seed)
        gen = torch.Generator().manual_seed(seed)
        ds = build_dataset(flights, target, features, split, rng, time_stretch)
        tr, va = ds.labels == TRAIN, ds.labels == VAL
        if tr.sum() < 10 * ds.x.shape[1] or va.sum() < 10:
            raise ValueError(f"too little data: {int(tr.sum())} training and {int(va.sum())} "
                             f"validation rows for {ds.x.shape[1]} features (fly longer or use "
                             "smaller blocks)")
        # the rate target learns the change since the fed-back rates (the last 3 features)
        base = None if target == "accel" or not features.use_rates else \
            [ds.x.shape[1] - 3 + k for k in range(3)]
        y_fit = ds.y if train_target == "measured" else ds.y_lp_sets
        net = PilotNet(ds.x.shape[1], ds.y.shape[1], hidden, base)
        net.set_scaling(ds.x[tr], y_fit[tr])
        z = net.standardise(ds.x)
        ystd = net.standardise_target(ds.x, y_fit)
        z_np, y_np = z.double().numpy(), ystd.double().numpy()
        ridge_val = None
        if arx_ridge == "val":
            ridges, ridge_val = choose_arx_ridge(z_np[tr], y_np[tr], z_np[va], y_np[va])
        else:
            ridges = float(arx_ridge)
        # the net trains on the training rows and their time-stretched copies
        y_st = ds.y_stretch if train_target == "measured" else ds.y_lp_stretch
        z_st = net.standardise(ds.x_stretch)
        ystd_st = net.standardise_target(ds.x_stretch, y_st)
        w_arx = fit_arx(z_np[tr], y_np[tr], ridges)
        start, stretch_val = None, None
        if len(z_st):
            start = fit_arx(np.concatenate([z_np[tr], z_st.double().numpy()]),
                            np.concatenate([y_np[tr], ystd_st.double().numpy()]), ridges)
        if start is not None and choose_stretch:
            stretch_val = stretch_worse_on_validation(
                z_np[va], y_np[va], w_arx, start, ds.t_val_s, (adamw or AdamWConfig()))
            if stretch_val["worse"]:
                start, time_stretch = None, ()
                z_st, ystd_st = z_st[:0], ystd_st[:0]
        net.set_arx(w_arx, start=start)
        bar = None
        if progress:
            from airwake.progress import Progress

            total = (adamw or AdamWConfig()).max_epochs if trainer == "adamw" else \
                (pso or PSOConfig()).iterations
            bar = Progress(f"nets train ({trainer})", total, " epochs" if trainer == "adamw"
                           else " iterations")
        tr_t, va_t = torch.as_tensor(tr), torch.as_tensor(va)
        z_tr, y_tr = torch.cat([z[tr_t], z_st]), torch.cat([ystd[tr_t], ystd_st])
        if trainer == "adamw":
            info = train_adamw(net, z_tr, y_tr, z[va_t], ystd[va_t],
                               adamw or AdamWConfig(), gen, bar, ds.t_val_s)
            settings = asdict(adamw or AdamWConfig())
        else:
            info = train_pso(net, z_tr, y_tr, z[va_t], ystd[va_t], pso or PSOConfig(),
                             rng, bar)
            settings = asdict(pso or PSOConfig())
        if bar is not None:
            bar.finish()
        net.eval()
        pred = net.predict_numpy(ds.x)
        arx = net.predict_arx(ds.x)
    finally:
        torch.set_num_threads(old_threads)
    metrics = score_sets(target, ds.y, ds.y_lp, pred, arx, ds.prev, ds.labels)
    net.card = {
        "target": target, "outputs": list(OUTPUTS[target]), "features": ds.names,
        "feature_config": features.to_dict(), "split": asdict(split),
        "input_source": flights[0].input_source,
        "input_columns": list(INPUT_SOURCES[flights[0].input_source]),
        "rate_hz": float(np.mean(rates)), "trainer": trainer, "trainer_settings": settings,
        "train_target": train_target, "time_stretch": list(time_stretch),
        "train_rows_stretched": int(len(z_st)),
        **({"time_stretch_val": stretch_val} if stretch_val is not None else {}),
        "arx_ridge": ridges if isinstance(ridges, list) else [ridges] * ds.y.shape[1],
        **({"arx_ridge_val": ridge_val} if ridge_val is not None else {}),
        "training": info, "seed": int(seed), "training_flights": ds.flights, "metrics": metrics,
        "train_seconds": round(time.perf_counter() - t0, 3), "versions": versions(),
    }
    return net


def versions() -> dict:
    import airwake

    return {"airwake": airwake.__version__, "torch": torch.__version__, "numpy": np.__version__,
            "python": platform.python_version()}
