"""The default wind estimator: an iterated extended Kalman filter and Rauch-Tung-Striebel
smoother over the helicopter model, with the wind prior's statistics learned from the
flight (expectation-maximisation).

    pre = prefilter(FlightData.from_flight(model, flight), model)
    res = WindSmoother(model, pre, WindPrior.from_physics(R)).run()
    res.mean, res.std            # (n, 6) smoothed eq 5.3 wind and its posterior std
    res.prior, res.noise_std     # the prior and channel noise the flight taught it

State of sample k (N = m + 12 + n_b):

    s = [h (m) rotor states (flapping, lead-lag, flybar, ...), mu (6) mean wind, xi (6)
         turbulence, b (n_b) the model's slow misfit on the channels given one],
    wind w = mu + xi

    dh/dt   = f_h(h, body(t), u(t), w)        the model's rotor dynamics (measured body motion)
    d mu/dt, d xi/dt                          the wind prior (`airwake.estimate.wind_prior`)
    db/dt   = -b / tau_b + noise              Gauss-Markov, stationary std sigma_b per channel
    z_k     = z_hat(h_k, body_k, u_k, w_k) + b_k + e_k,   e_k ~ N(0, diag(noise_std^2))

The bias states (`channel_bias` = (sigma_b (6,), tau_b)) are the model error that is not
white: a calibrated model of a foreign airframe misses a force or moment that depends on
the flight condition and so holds for tens of seconds (the still-air flight's
`model_error_offset`: the RMS of its 30 s blocks' mean misfit). Without them the smoother
reads such a misfit as a steady wind, with the confidence of white noise averaged over
the flight (docs/calibration.md "six channels, six unknowns"); with them a steady misfit
and a steady wind share the channel by their prior stds, and the interval says so. The
wind estimate uses them on request (`--model-error states`): with an anchor they find a
steady force exactly where the model fits; on the blade-element airframe the split by
prior stds is not better than the considered offsets (docs/wind-estimation.md "The
model's slow misfit as states").

on the front end's low-passed, decimated samples (`airwake.estimate.prefilter`).

Each step is linearised at a point s_bar (Jacobians by forward differences: one batched
model evaluation of 1 + m + 6 rows gives f_h or z_hat and their derivatives in h and w;
two more rows give f_h's slope and curvature in time as the measured body motion and
inputs move over the step), and the linear system is discretised over the step (one
matrix exponential of the half step gives the transition Phi and the exponential
Rosenbrock-Euler step for the mean with the inputs held to second order, exact for the
local affine dynamics, so the stiff rotor modes need no small steps and a state faster
than the step follows the inputs to the sample; Simpson's rule the process covariance Q):

    s_k^- = s_{k-1} + int_0^dt e^{A r} dr F(s_{k-1}),   P_k^- = Phi P_{k-1} Phi^T + Q
    K = P^- H^T (H P^- H^T + R)^-1,  s_k = s_k^- + K (z_k - z_hat_k),
    P_k = (I - K H) P^- (I - K H)^T + K R K^T     (Joseph form, symmetrised)

then the RTS smoother backwards (G_k = P_k Phi_{k+1}^T (P_{k+1}^-)^-1) with the lag-one
covariances C_{k+1,k} = P^s_{k+1} G_k^T. The offline map can use the whole flight, so the
smoothed estimate (both sides of every sample) is the product; the forward (filtered)
estimate is kept as `filtered_*` for what runs live.

Iterations: the first pass linearises along its own filtered estimate (an EKF); the next
`relinearise - 1` passes along the previous smoothed trajectory (the iterated extended
smoother, a Gauss-Newton step on the whole trajectory each); after every pass but the
last the turbulence std sigma per component and the channel noise are re-estimated from
the smoothed moments (EM for linear-Gaussian state-space models, Shumway & Stoffer 1982),
the correlation time tau staying the prior's (physics, `wind_prior`):

    xi:  a = e^{-dt/tau},  q = (S11 - 2 a S10 + a^2 S00) / n,  sigma^2 = q / (1 - a^2)
         (S10 = sum E[xi_k xi_{k-1}] from the lag-one covariances, S00, S11 likewise)
    R:   mean of (z_k - z_hat(s^s_k))^2 + (H P^s_k H^T)_cc

so sigma is the flow's own statistic as the measurements reveal it, and the channel noise
the model's actual misfit after the front end (model error included), not a guess. Each
continuous run of the flight is estimated on its own.

Where the flight hardly informs a component, EM hardly moves its sigma: on the
blade-element ship flights the two updates of the default passes leave sigma of the
rotation about the horizontal axes (w_x, w_y) at 0.48-0.51 1/s from its start of 0.5,
against the truth's spread of 0.13-0.20, while w_z's goes to 0.26-0.29 and the anchored
mean flow's to 0.21-0.32 m/s. So w_x and w_y do not keep the start: after each update
their sigma is the one the turbulence's structure gives for the mean flow's learned
sigma (`WindPrior.rotation_sigma`: the velocity difference across the rotor radius in
frozen isotropic turbulence, over the radius; learn item "rotation_from_mean_flow", on
by default; their error std fell from 0.16-0.31 to 0.11-0.22 1/s there, anchored,
docs/wind-estimation.md). w_z keeps its own EM update: the tail rotor and the fuselage's
yaw read it.
"""

from __future__ import annotations

import math
import time
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import cho_factor, cho_solve, expm

from airwake.calibrate.hidden import (
    HiddenPropagator,
    RowBatch,
    evaluate_rates_and_measurement,
    hidden_indices,
    single_blas_thread,
)
from airwake.estimate.prefilter import Prefiltered
from airwake.estimate.wind_prior import WindPrior

ITERATIONS = 3
RELINEARISE = 2
LEARN = ("sigma", "noise", "rotation_from_mean_flow")
# the rotation components whose sigma follows the mean flow's (`WindPrior.rotation_sigma`):
# about the horizontal axes, which the flight hardly informs (module docstring)
TIED_ROTATION = (3, 4)
SIGMA_FLOOR = np.array([0.02, 0.02, 0.02, 0.01, 0.01, 0.01])
MEAN_WALK_FLOOR = 1e-3
NOISE_FLOOR = 1e-4
# the bound's channel-error model: AR(p) per channel, p by Akaike's criterion up to this
# (2.1 s at 15 Hz). AR(4) smeared the blade-element misfit's 0.5 Hz peak into the wind's
# band (1.2-8.9x the Welch spectrum at 0.03-0.3 Hz; docs/wind-estimation.md)
NOISE_AR_MAX_ORDER = 32
NOISE_VAR_MAX_ORDER = 16  # the same for the vector AR (6 x 6 per lag: 1.1 s at 15 Hz)
NOISE_WHITE_FRACTION = 1e-3  # white noise added to the bound's AR channel error (conditioning)
FD_STEP_H = 1e-6
DEAD_VARIANCE = 1e-20  # of the largest predicted variance: a state nothing uncertain reaches
FD_STEP_W = 1e-4
FD_STEP_T = 1e-4  # s: the directional difference along the body motion and inputs
LOG_2PI = float(np.log(2.0 * np.pi))

def _smoother_gain(cross: np.ndarray, pred: np.ndarray) -> np.ndarray:
    """The RTS gain G = cross pred^-1, solved in the predicted covariance's own scale.

    A model's hidden states span many orders of magnitude of variance (the wind ~1, the
    flapping ~1e-9 rad^2), and a state the inputs alone drive (a servo lag's: nothing
    uncertain reaches it) has none at all, so pred is singular. Such states (variance
    below DEAD_VARIANCE of the largest) get no smoothing gain (there is nothing to
    correct in them); the rest is solved as D C D, D = sqrt(diag pred), C its correlation
    matrix (Cholesky; the pseudo-inverse where C is not positive definite)."""
    dg = np.diag(pred)
    live = dg > DEAD_VARIANCE * max(float(dg.max()), 0.0)
    if not live.any():
        return np.zeros_like(cross)
    d = np.sqrt(dg[live])
    corr = pred[np.ix_(live, live)] / np.outer(d, d)
    rhs = (cross[:, live] / d).T
    try:
        chol = cho_factor(corr, lower=True, check_finite=False)
        g_live = cho_solve(chol, rhs, check_finite=False).T
        if not np.all(np.isfinite(g_live)):
            raise np.linalg.LinAlgError("non-finite gain")
    except np.linalg.LinAlgError:
        g_live = rhs.T @ np.linalg.pinv(corr, rcond=1e-12, hermitian=True)
    g = np.zeros_like(cross)
    g[:, live] = g_live / d
    return g


@dataclass
class SmootherResult:
    """Per kept sample (n): t; mean, std (n, 6) smoothed wind; filtered_mean,
    filtered_std (n, 6) the forward (causal) pass.
    prior (learned), noise_std (6,), history (per pass: log-likelihood, prior, noise),
    seconds, evaluations (model rows); fast_std (n, 6) the smoothed posterior std of the
    turbulence part xi alone (the Gauss-Markov states, not the slow mean mu): the fast
    wind the flight did not show the smoother (`airwake.estimate.net_interval`);
    bias (n, 6) the channel-bias states' smoothed mean (NaN on a channel without one):
    the model's slow misfit per channel as the smoother split it from the wind."""

    t: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    filtered_mean: np.ndarray
    filtered_std: np.ndarray
    prior: WindPrior
    noise_std: np.ndarray
    history: list = field(default_factory=list)
    seconds: float = 0.0
    evaluations: int = 0
    fast_std: np.ndarray | None = None
    bias: np.ndarray | None = None


@dataclass
class _Lin:
    """Linearisation of one run: transition k-1 -> k at point tp[k] (row 0 unused):
    f0 (n, m) f_h, jt (n, m, m+6) [df/dh | df/dw], fr (n, 2, m) f_h's slope and half
curvature in time over the step as the measured body motion and the inputs move (the
inputs held to second order); measurement at point mp[k]: z0 (n, 6),
    jz (n, 6, m+6)."""

    tp: np.ndarray
    f0: np.ndarray
    jt: np.ndarray
    mp: np.ndarray
    z0: np.ndarray
    jz: np.ndarray
    fr: np.ndarray = None  # (n, 2, m) f_h's slope and half curvature over the step

    def __post_init__(self) -> None:
        if self.fr is None:
            self.fr = np.zeros((self.f0.shape[0], 2, self.f0.shape[1]))


@dataclass
class _Pass:
    """Forward + backward results of one run."""

    mf: np.ndarray
    pf: np.ndarray
    mp: np.ndarray
    pp: np.ndarray
    phi: np.ndarray
    ms: np.ndarray = None
    ps: np.ndarray = None
    cs: np.ndarray = None
    gain: np.ndarray = None  # (n, N, N) the RTS gains G_k (row n-1 unused)
    loglik: float = 0.0
    anchor_gain: np.ndarray = None  # (n, N, 3) the mean-flow anchor's gains; None: no anchor


def _consider_std(sens: np.ndarray, sig: np.ndarray) -> np.ndarray:
    """(n, 6) the wind's std from independent steady offsets of std `sig` (q,) through
    their sensitivities `sens` (n, 6, q): sqrt(sum_j (S_kj sigma_j)^2) per component."""
    return np.sqrt(np.einsum("kwc,c->kw", sens**2, sig**2))


def _channel_bias(channel_bias):
    """(channels (nb,) int, sigma (nb,), tau_s) from `channel_bias` = (sigma (6,), tau_s)
    or None (no bias states); a channel with sigma 0 gets none."""
    if channel_bias is None:
        return np.zeros(0, int), np.zeros(0), 1.0
    sigma, tau = channel_bias
    sigma = np.asarray(sigma, dtype=float)
    if sigma.shape != (6,) or np.any(~np.isfinite(sigma)) or np.any(sigma < 0):
        raise ValueError(f"channel_bias: sigma must be 6 numbers >= 0, got {sigma!r}")
    tau = float(tau)
    if not math.isfinite(tau) or tau <= 0:
        raise ValueError(f"channel_bias: tau_s must be > 0, got {tau!r}")
    on = np.flatnonzero(sigma > 0)
    return on, sigma[on], tau


def _offset_stds(offset_std) -> np.ndarray:
    sig = np.asarray(offset_std, dtype=float)
    if sig.shape != (6,) or np.any(~np.isfinite(sig)) or np.any(sig < 0):
        raise ValueError(f"offset_std must be 6 numbers >= 0, got {offset_std!r}")
    return sig


def _residual_for_noise(residual, order, max_order, what: str):
    """(residual (n, 6) as floats, its rows with every channel finite, the highest order
    to try) for a noise model's fit, or a ValueError naming what is wrong."""
    e = np.asarray(residual, dtype=float)
    if e.ndim != 2 or e.shape[1] != 6:
        raise ValueError(f"the residual must be (n, 6), got {e.shape}")
    ok = np.all(np.isfinite(e), axis=1)
    if ok.sum() < 10:
        raise ValueError(f"a residual of at least 10 finite rows is needed for a noise "
                         f"model, got {int(ok.sum())} finite of {e.shape[0]}")
    top = int(max_order) if order is None else int(order)
    if top < 0:
        raise ValueError(f"the {what} order must be >= 0, got {top}")
    return e, ok, top


def _levinson(acov: np.ndarray) -> list[tuple[np.ndarray, float]]:
    """Levinson-Durbin on autocovariances acov (p + 1,): [(AR coefficients (k,),
    innovation variance)] for every order k = 0 ... p (Yule-Walker's solutions)."""
    a = np.zeros(0)
    v = float(acov[0])
    out = [(a, v)]
    for k in range(1, acov.size):
        refl = (acov[k] - a @ acov[k - 1:0:-1]) / v
        a = np.concatenate([a - refl * a[::-1], [refl]])
        v *= 1.0 - refl * refl
        out.append((a, v))
    return out


@dataclass
class ChannelNoise:
    """Each measured channel's error as a Gaussian process: an AR(p) part
        n_k = sum_i ar[c, i] n_{k-i} + e_k,  Var e_k = innovation_var[c]
    at the front end's sample rate, plus white noise of variance white_var[c]. Fitted to
    a residual by `fit` (Yule-Walker), or white (`white`)."""

    ar: np.ndarray  # (6, p)
    innovation_var: np.ndarray  # (6,)
    white_var: np.ndarray  # (6,)

    @property
    def order(self) -> int:
        return int(self.ar.shape[1])

    def orders(self) -> list[int]:
        """Each channel's own AR order (its last non-zero coefficient)."""
        return [int(np.flatnonzero(row)[-1]) + 1 if np.any(row) else 0 for row in self.ar]

    @classmethod
    def white(cls, std) -> ChannelNoise:
        std = np.asarray(std, dtype=float)
        if std.shape != (6,) or np.any(~np.isfinite(std)) or np.any(std <= 0):
            raise ValueError(f"noise std must be 6 positive numbers, got {std!r}")
        return cls(np.zeros((6, 0)), np.zeros(6), std**2)

    @classmethod
    def fit(cls, residual: np.ndarray, runs, order: int | None = None,
            white_fraction: float = NOISE_WHITE_FRACTION,
            max_order: int = NOISE_AR_MAX_ORDER) -> ChannelNoise:
        """Yule-Walker AR per channel of `residual` (n, 6) over the contiguous `runs`
        (slices; rows with a non-finite value dropped from their run), each channel about
        its mean over the flight (a steady part is an offset, not noise). The
        autocovariances are pooled over the runs (the biased estimator: a positive definite
        Toeplitz matrix, so a stable AR). The order: `order` for every channel, or (None)
        each channel's by Akaike's information criterion, N ln(innovation variance) + 2p,
        over p = 0 ... `max_order` (Akaike 1974; the Levinson-Durbin recursion gives every
        order at once) — a misfit with a spectral peak needs more than a few coefficients,
        or the AR spreads the peak's power into the frequencies beside it. Either way at
        most one coefficient per 10 rows; channels of lower order are padded with zero
        coefficients. A white part of `white_fraction` of each channel's variance is added
        on top (it keeps the innovation covariance well conditioned)."""
        e, ok, top = _residual_for_noise(residual, order, max_order, "AR")
        top = min(top, int(ok.sum()) // 10 - 1)  # >= 10 rows per coefficient
        e = e - e[ok].mean(axis=0)
        acov = np.zeros((top + 1, 6))
        count = 0
        for run in runs:
            seg = e[run][ok[run]]
            count += seg.shape[0]
            for lag in range(min(top + 1, seg.shape[0])):
                acov[lag] += np.sum(seg[:seg.shape[0] - lag] * seg[lag:], axis=0)
        acov /= max(count, 1)
        var = acov[0]
        if np.any(var <= 0):
            raise ValueError(f"a channel of the residual is constant (variance {var!r})")
        fits = [_levinson(acov[:, c]) for c in range(6)]  # [(coefficients, innovation)]
        if order is None:
            pick = [int(np.argmin([count * np.log(v) + 2.0 * p
                                   for p, (_, v) in enumerate(f)])) for f in fits]
        else:
            pick = [top] * 6
        ar = np.zeros((6, max(pick)))
        innov = np.zeros(6)
        for c, p in enumerate(pick):
            coef, v = fits[c][p]
            ar[c, :p] = coef
            innov[c] = max(v, 1e-12 * var[c])
        return cls(ar, innov, white_fraction * var)

    def white_cov(self) -> np.ndarray:
        """(6, 6) the white part's covariance."""
        return np.diag(self.white_var)

    def companion(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The AR part as a linear state (what the bound augments its system with):
        (F (N, N) transition, Q (N, N) innovation covariance, S (6, N) which state adds to
        each channel), channel c's last p values in states c p ... c p + p - 1."""
        p = self.order
        f = np.zeros((6 * p, 6 * p))
        q = np.zeros((6 * p, 6 * p))
        sel = np.zeros((6, 6 * p))
        for c in range(6 if p else 0):
            o = c * p
            f[o, o:o + p] = self.ar[c]
            f[o + np.arange(1, p), o + np.arange(p - 1)] = 1.0
            q[o, o] = self.innovation_var[c]
            sel[c, o] = 1.0
        return f, q, sel

    def stationary_covariance(self) -> np.ndarray:
        """(6p, 6p) the AR states' stationary covariance (channels independent)."""
        from scipy.linalg import solve_discrete_lyapunov

        p = self.order
        out = np.zeros((6 * p, 6 * p))
        for c in range(6):
            if not p:
                break
            f = np.zeros((p, p))
            f[0] = self.ar[c]
            f[np.arange(1, p), np.arange(p - 1)] = 1.0
            q = np.zeros((p, p))
            q[0, 0] = self.innovation_var[c]
            blk = solve_discrete_lyapunov(f, q)
            out[c * p:(c + 1) * p, c * p:(c + 1) * p] = 0.5 * (blk + blk.T)
        return out

    def std(self) -> np.ndarray:
        """(6,) each channel's total std (AR part's stationary variance + white)."""
        cov = self.stationary_covariance()
        p = self.order
        ar_var = np.array([cov[c * p, c * p] for c in range(6)]) if p else np.zeros(6)
        return np.sqrt(ar_var + self.white_var)


@dataclass
class VectorNoise:
    """The six channels' error as one vector autoregressive process (VAR(p)):
        n_k = sum_i coef[i] n_{k-i} + e_k,  Cov e_k = innovation_cov (6, 6),
    plus white noise of variance white_var, at the front end's sample rate. Where the
    model's misfit has one cause in several channels (a lateral force error shows in a_y,
    in p-dot through the hub's height and in r-dot through the tail) the channels' errors
    are correlated, and part of one channel's misfit is predictable from another's; the
    per-channel `ChannelNoise` counts each as an independent corruption and so tells a
    bound that less is known than is. Fitted by `fit` (least squares)."""

    coef: np.ndarray  # (p, 6, 6)
    innovation_cov: np.ndarray  # (6, 6)
    white_var: np.ndarray  # (6,)

    @property
    def order(self) -> int:
        return int(self.coef.shape[0])

    def orders(self) -> list[int]:
        return [self.order] * 6

    @classmethod
    def fit(cls, residual: np.ndarray, runs, order: int | None = None,
            white_fraction: float = NOISE_WHITE_FRACTION,
            max_order: int = NOISE_VAR_MAX_ORDER) -> VectorNoise:
        """Least-squares VAR of `residual` (n, 6) over the contiguous `runs` (rows with a
        non-finite value end a stretch; each stretch's lags stay inside it), about the
        flight's mean (a steady part is an offset, not noise). The order: `order`, or
        (None) Akaike's criterion, N ln det(innovation covariance) + 2 * 36 p, over
        p = 0 ... `max_order` (Akaike 1974; Lutkepohl, New Introduction to Multiple Time
        Series Analysis, 2005, sec. 4.3), at most one lag per 10 rows per coefficient of
        an equation, and no order whose process is not stable (spectral radius < 1)."""
        e, ok, top = _residual_for_noise(residual, order, max_order, "VAR")
        top = max(min(top, int(ok.sum()) // 60 - 1), 0)  # >= 10 rows per coefficient (6 p)
        e = e - e[ok].mean(axis=0)
        var = e[ok].var(axis=0)
        if np.any(var <= 0):
            raise ValueError(f"a channel of the residual is constant (variance {var!r})")
        stretches = []
        for run in runs:
            seg_ok = ok[run]
            seg = e[run]
            edges = np.flatnonzero(np.diff(np.concatenate([[0], seg_ok.astype(int), [0]])))
            stretches += [seg[a:b] for a, b in zip(edges[::2], edges[1::2], strict=True)]
        best = None
        for p in range(top + 1) if order is None else (max(top, 0),):
            ys, xs = [], []
            for seg in stretches:
                if seg.shape[0] <= top:
                    continue
                # the same rows for every order (from `top` on), so AIC compares like
                ys.append(seg[top:])
                xs.append(np.hstack([seg[top - i:seg.shape[0] - i] for i in range(1, p + 1)])
                          if p else np.zeros((seg.shape[0] - top, 0)))
            if not ys:
                raise ValueError("no stretch of the residual is longer than the VAR order")
            y, x = np.vstack(ys), np.vstack(xs)
            b = np.linalg.lstsq(x, y, rcond=None)[0] if p else np.zeros((0, 6))
            res = y - x @ b
            cov = res.T @ res / y.shape[0]
            coef = b.T.reshape(6, p, 6).transpose(1, 0, 2) if p else np.zeros((0, 6, 6))
            if p and np.max(np.abs(np.linalg.eigvals(_var_companion(coef)))) >= 1.0:
                continue
            sign, logdet = np.linalg.slogdet(cov)
            if sign <= 0:
                continue
            aic = y.shape[0] * logdet + 2.0 * 36 * p
            if best is None or aic < best[0]:
                best = (aic, coef, cov)
        if best is None:
            raise ValueError("no stable VAR fits the residual")
        return cls(best[1], 0.5 * (best[2] + best[2].T), white_fraction * var)

    def white_cov(self) -> np.ndarray:
        """(6, 6) the white part's covariance (a VAR(0) is all white)."""
        return np.diag(self.white_var) + (0.0 if self.order else self.innovation_cov)

    def companion(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(F, Q, S) as `ChannelNoise.companion`: the states are n_k, n_k-1, ... n_k-p+1
        (6 each), S reads n_k."""
        p = self.order
        f = _var_companion(self.coef)
        q = np.zeros((6 * p, 6 * p))
        sel = np.zeros((6, 6 * p))
        if p:
            q[:6, :6] = self.innovation_cov
            sel[:, :6] = np.eye(6)
        return f, q, sel

    def stationary_covariance(self) -> np.ndarray:
        from scipy.linalg import solve_discrete_lyapunov

        f, q, _ = self.companion()
        if not self.order:
            return np.zeros((0, 0))
        cov = solve_discrete_lyapunov(f, q)
        return 0.5 * (cov + cov.T)

    def std(self) -> np.ndarray:
        cov = self.stationary_covariance()
        ar_var = np.diag(cov)[:6] if self.order else np.zeros(6)
        return np.sqrt(ar_var + self.white_var)


def _var_companion(coef: np.ndarray) -> np.ndarray:
    """(6p, 6p) the companion matrix of VAR coefficients coef (p, 6, 6)."""
    p = coef.shape[0]
    f = np.zeros((6 * p, 6 * p))
    if p:
        f[:6] = np.hstack(list(coef))
        f[6:, :-6] = np.eye(6 * (p - 1))
    return f


class WindSmoother:
    """Iterated EKF/RTS smoother with EM-learned prior (module docstring).

    model: HeliModel; pre: Prefiltered flight; prior: WindPrior (the start; a copy is
    learned); noise_std: (6,) channel noise to start from (default: 5 % of each filtered
    channel's std, floored at 0.01); iterations: passes; relinearise: how many of them
    relinearise the model; learn: which of "sigma", "noise" the EM updates, and
    "rotation_from_mean_flow" (with "sigma") w_x's and w_y's sigma from the mean flow's
    (module docstring); noise_floor:
    (6,) the least channel noise the EM may learn — the model's own error on its still-air
    calibration flight (`[calibration] model_error_std`), so that a misfit the model
    already has in still air is not explained as wind (None: NOISE_FLOOR only);
    anchor: (mean, std), each (n, 3) at the flight's kept samples — a mean-flow estimate
    made without the model (a still-air wind net's) taken as a measurement of v = mu + xi
    (its 3 components) after each sample's channel update, so that the rotation is read
    given that mean flow (NaN rows: no anchor there; None: none)."""

    def __init__(self, model, pre: Prefiltered, prior: WindPrior, noise_std=None,
                 iterations: int = ITERATIONS, relinearise: int = RELINEARISE,
                 learn=LEARN, noise_floor=None, anchor=None,
                 channel_bias=None) -> None:
        if iterations < 1:
            raise ValueError(f"iterations = {iterations!r}: must be >= 1")
        unknown = set(learn) - set(LEARN)
        if unknown:
            raise ValueError(f"learn: unknown item(s) {sorted(unknown)}; known {list(LEARN)}")
        self.model = model
        self.pre = pre
        self.prior = prior.copy()
        self.iterations = int(iterations)
        self.relinearise = max(1, min(int(relinearise), self.iterations))
        self.learn = tuple(learn)
        data = pre.data
        self.hid = hidden_indices(model)
        # attitude angles: their step differences are wrapped (yaw across +-pi)
        self._angles = np.array([i for i, nm in enumerate(model.state_names)
                                 if nm.endswith(("roll_rad", "pitch_rad", "yaw_rad"))], int)
        self.m = self.hid.size
        m = self.m
        self.mu, self.xi = slice(m, m + 6), slice(m + 6, m + 12)
        # the model's slowly varying error per channel: Gauss-Markov states after xi
        channels, sigma, self.bias_tau_s = _channel_bias(channel_bias)
        self._set_bias(channels, sigma)
        self.noise_floor = np.full(6, NOISE_FLOOR)
        if noise_floor is not None:
            floor = np.asarray(noise_floor, dtype=float)
            if floor.shape != (6,) or np.any(~np.isfinite(floor)) or np.any(floor < 0):
                raise ValueError(f"noise_floor must be 6 numbers >= 0, got {noise_floor!r}")
            self.noise_floor = np.maximum(floor, NOISE_FLOOR)
        if noise_std is None:
            noise_std = np.maximum(0.05 * np.std(data.z, axis=0), 0.01)
        noise_std = np.maximum(np.asarray(noise_std, dtype=float), self.noise_floor)
        self.noise_std = np.asarray(noise_std, dtype=float).copy()
        if self.noise_std.shape != (6,) or np.any(~np.isfinite(self.noise_std)) or np.any(
                self.noise_std <= 0):
            raise ValueError(f"noise_std must be 6 positive numbers, got {noise_std!r}")
        self.anchor = None
        if anchor is not None:
            a_mean, a_std = (np.asarray(a, dtype=float) for a in anchor)
            n = data.t.size
            if a_mean.shape != (n, 3) or a_std.shape != (n, 3):
                raise ValueError(f"anchor: mean and std must be ({n}, 3) at the flight's "
                                 f"samples, got {a_mean.shape} and {a_std.shape}")
            ok = np.all(np.isfinite(a_mean), axis=1) & np.all(np.isfinite(a_std), axis=1)
            if np.any(a_std[ok] <= 0):
                raise ValueError("anchor: its std must be > 0 where it is given")
            if not ok.any():
                raise ValueError("anchor: no sample has a finite mean and std")
            self.anchor = (np.where(ok[:, None], a_mean, np.nan), a_std, ok)
            self._anchor_rows = self._wind_rows()[:3]  # v = mu + xi: what the anchor reads
            self._eye = np.eye(self.n_state)
        self.prop = HiddenPropagator(model, data.dt, None, data.reference_row())
        if not self.prop.valid[0]:
            raise ValueError("the model's rotor dynamics cannot be linearised at this "
                             "flight's median state (non-finite or singular Jacobian)")
        self.evaluations = 0

    # -- model evaluations ------------------------------------------------------------
    def _jacobian_rows(self, x_body, u, env_row, h, w, motion=None):
        """f_h (m,), z (6,) at (h, w) and their derivatives [d/dh | d/dw] (m, m+6),
        (6, m+6) from one batched evaluation of 1 + m + 6 rows (forward differences);
        with `motion` = ((dx, du), ...) directions of the body state and the inputs, one
        row more each, and f_h's directional derivatives along them (len(motion), m) (a
        forward difference of FD_STEP_T along each) as a fifth value."""
        m = self.m
        extra = 0 if motion is None else len(motion)
        rows = 1 + m + 6 + extra
        eps_h = FD_STEP_H * np.maximum(1.0, np.abs(h))
        x = np.repeat(x_body[None], rows, 0)
        uu = np.repeat(u[None], rows, 0)
        for i, (dx, du) in enumerate(motion or ()):
            x[rows - extra + i] += FD_STEP_T * dx
            uu[rows - extra + i] += FD_STEP_T * du
        hh = np.repeat(h[None], rows, 0)
        hh[1 + np.arange(m), np.arange(m)] += eps_h
        x[:, self.hid] = hh
        ww = np.repeat(w[None], rows, 0)
        ww[1 + m + np.arange(6), np.arange(6)] += FD_STEP_W
        env = {k: np.full(rows, v) for k, v in env_row.items()}
        with np.errstate(all="ignore"):
            xd, z = evaluate_rates_and_measurement(self.model, x, uu, ww, env, None)
        self.evaluations += rows
        f = xd[:, self.hid]
        steps = np.concatenate([eps_h, np.full(6, FD_STEP_W)])
        n_fd = 1 + m + 6
        jf = ((f[1:n_fd] - f[0]) / steps[:, None]).T
        jz = ((z[1:n_fd] - z[0]) / steps[:, None]).T
        if motion is None:
            return f[0], z[0], jf, jz
        return f[0], z[0], jf, jz, (f[n_fd:] - f[0]) / FD_STEP_T

    def _transition_lin(self, k: int, point: np.ndarray):
        """f_h, [df/dh | df/dw] at the step's midpoint, and f_h's slope and half
        curvature in time over the step (2, m) as the measured body motion and inputs
        move: the parabola through sample k-1, the midpoint and sample k,
            v(r) = v_mid + v' (r - dt/2) + v''/2 (r - dt/2)^2,
            v' = (v_k - v_{k-1}) / dt,  v'' = 4 (v_k - 2 v_mid + v_{k-1}) / dt^2,
        so a state faster than the step (a servo lag of a few ms) follows the inputs to
        the sample, not to the midpoint."""
        d = self.pre
        data = d.data
        env = {n: v[k] for n, v in d.mid_env.items()}
        w = point[self.mu] + point[self.xi]
        dt = data.t[k] - data.t[k - 1]
        ahead = data.x[k] - d.mid_x[k]
        back = data.x[k - 1] - d.mid_x[k]
        for v in (ahead, back):
            v[self._angles] = np.angle(np.exp(1j * v[self._angles]))
        u_ahead = data.u[k] - d.mid_u[k]
        u_back = data.u[k - 1] - d.mid_u[k]
        motion = (((ahead - back) / dt, (u_ahead - u_back) / dt),
                  (2.0 * (ahead + back) / dt**2, 2.0 * (u_ahead + u_back) / dt**2))
        f, _, jf, _, fr = self._jacobian_rows(d.mid_x[k], d.mid_u[k], env, point[:self.m],
                                              w, motion)
        return f, jf, fr

    def _measurement_lin(self, k: int, point: np.ndarray):
        d = self.pre.data
        env = {n: v[k] for n, v in d.env.items()}
        w = point[self.mu] + point[self.xi]
        _, z, _, jz = self._jacobian_rows(d.x[k], d.u[k], env, point[:self.m], w)
        z[self.bias_channels] += point[self.bias]  # the channels' slow misfit
        return z, jz

    # -- building blocks ----------------------------------------------------------------
    def _h_matrix(self, jz: np.ndarray) -> np.ndarray:
        """(6, N) measurement Jacobian: dz/dh, and dz/dw for mu and xi alike."""
        m = self.m
        h = np.zeros((6, self.n_state))
        h[:, :m] = jz[:, :m]
        h[:, self.mu] = jz[:, m:]
        h[:, self.xi] = jz[:, m:]
        h[self.bias_channels, self._bias_cols] = 1.0
        return h

    def _wind_rows(self) -> np.ndarray:
        """(6, N): w = mu + xi."""
        c = np.zeros((6, self.n_state))
        c[:, self.mu] = np.eye(6)
        c[:, self.xi] = np.eye(6)
        return c

    def _initial(self, k0: int, prior: WindPrior, wind0=None):
        """Mean and covariance at a run's first sample: rotor states quasi-steady at the
        wind `wind0` (zero), their covariance through the quasi-steady sensitivity
        -J_h^-1 J_w."""
        m, n = self.m, self.n_state
        d = self.pre.data
        w0 = np.zeros(6) if wind0 is None else np.asarray(wind0, float)
        x = np.repeat(d.x[k0][None], 1, 0)
        rows = RowBatch(x, d.u[k0:k0 + 1], w0[None],
                        {name: v[k0:k0 + 1] for name, v in d.env.items()})
        with np.errstate(all="ignore"):
            h = self.prop.quasi_steady(self.prop.h_ref[0][None, None], rows, None)[0, 0]
        if not np.all(np.isfinite(h)):
            h = self.prop.h_ref[0].copy()
        s = np.zeros(n)
        s[:m] = h
        s[m:m + 6] = w0
        env = {name: v[k0] for name, v in d.env.items()}
        _, _, jf, _ = self._jacobian_rows(d.x[k0], d.u[k0], env, h, w0)
        try:
            sens = -np.linalg.solve(jf[:, :m], jf[:, m:])
        except np.linalg.LinAlgError:
            sens = np.zeros((m, 6))
        t = np.zeros((n, 12))
        t[:m, :6] = sens
        t[:m, 6:] = sens
        t[m:m + 12, :] = np.eye(12)
        p = t @ prior.initial_covariance() @ t.T
        p[:m, :m] += np.eye(m) * 1e-12
        p[self.bias, self.bias] = np.diag(self.bias_sigma**2)
        return s, 0.5 * (p + p.T)

    def _system(self, f0, jt, tp, s, prior: WindPrior):
        """Continuous A (N, N) and drift F(s) (N,) of the system linearised at tp."""
        m, n = self.m, self.n_state
        a = np.zeros((n, n))
        a[:m, :m] = jt[:, :m]
        a[:m, self.mu] = jt[:, m:]
        a[:m, self.xi] = jt[:, m:]
        a[m:m + 12, m:m + 12] = prior.drift_matrix()
        ds = s - tp
        dw = ds[self.mu] + ds[self.xi]
        drift = np.zeros(n)
        drift[:m] = f0 + jt[:, :m] @ ds[:m] + jt[:, m:] @ dw
        drift[self.xi] = -s[self.xi] / prior.tau_s
        if self.bias_channels.size:
            a[self._bias_cols, self._bias_cols] = -1.0 / self.bias_tau_s  # the diagonal
            drift[self.bias] = -s[self.bias] / self.bias_tau_s
        return a, drift

    def _diffusion(self, prior: WindPrior) -> np.ndarray:
        """(N,) the continuous process noise: none on the rotor states, the wind prior's
        on mu and xi, 2 sigma_b^2 / tau_b on each channel bias (its stationary std
        sigma_b)."""
        return np.concatenate([np.zeros(self.m), prior.diffusion(),
                               2.0 * self.bias_sigma**2 / self.bias_tau_s])

    def _discretise(self, a, drift, qc, dt, ramp=None):
        """Phi = e^{A dt}, Q = int_0^dt e^{A r} Qc e^{A^T r} dr and the mean step
        int_0^dt e^{A (dt-r)} F(r) dr with F(r) = F + G1 (r - h) + G2 (r - h)^2, h = dt/2
        (exponential Rosenbrock-Euler with the inputs held to second order: F the drift
        at the midpoint, `ramp` = (G1, G2) for the rotor states' rows, exact for the local
        affine system) from one matrix exponential of the half step over the states
        (d, a = 1, b = r, c = r^2/2):
            d' = A d + (F - G1 h + G2 h^2) a + (G1 - 2 h G2) b + 2 G2 c,  b' = a,  c' = b;
        E_h = e^{M h}, Phi = E_h[d,d]^2, step = E_h[d,d] E_h[d,a] + (E_h^2)[d,a] rest
        (a, b, c after the half step: 1, h, h^2/2); and Q by Simpson's rule over the step,
        Q = dt/6 (Qc + 4 E_h Qc E_h^T + E Qc E^T) (the noise enters the wind states only;
        against Van Loan's exact Q the difference is below 1 % of the wind block)."""
        n, m = self.n_state, self.m
        h = 0.5 * dt
        aug = np.zeros((n + 3, n + 3))
        aug[:n, :n] = a
        aug[:n, n] = drift
        if ramp is not None:
            g1, g2 = ramp
            aug[:m, n] += -g1 * h + g2 * h * h
            aug[:m, n + 1] = g1 - 2.0 * h * g2
            aug[:m, n + 2] = 2.0 * g2
        aug[n + 1, n] = 1.0
        aug[n + 2, n + 1] = 1.0
        e = expm(aug * h)
        e_h = e[:n, :n]
        phi = e_h @ e_h
        # the second half starts from (a, b, c) = (1, h, h^2/2)
        step = e[:n, n] + e_h @ e[:n, n] + e[:n, n + 1] * h + e[:n, n + 2] * (0.5 * h * h)
        w = slice(self.m, n)
        qw = qc[w]
        q = (e_h[:, w] * qw) @ e_h[:, w].T
        q *= 4.0
        q += (phi[:, w] * qw) @ phi[:, w].T
        q[w, w] += np.diag(qw)
        q *= dt / 6.0
        return phi, 0.5 * (q + q.T), step

    # -- one pass over one run ------------------------------------------------------
    def _forward(self, run: slice, prior: WindPrior, r_diag: np.ndarray, lin: _Lin | None,
                 online: bool, wind0=None, anchored: bool = True) -> tuple[_Pass, _Lin]:
        m, n_s = self.m, self.n_state
        d = self.pre.data
        idx = np.arange(run.start, run.stop)
        n = idx.size
        anchored = anchored and self.anchor is not None
        # the anchor's gains per sample (zero where it has none); None without an anchor
        anchor_gain = np.zeros((n, n_s, 3)) if anchored else None
        mf = np.empty((n, n_s))
        pf = np.empty((n, n_s, n_s))
        mp = np.empty((n, n_s))
        pp = np.empty((n, n_s, n_s))
        phi_all = np.zeros((n, n_s, n_s))
        if online:
            lin = _Lin(np.zeros((n, n_s)), np.zeros((n, m)), np.zeros((n, m, m + 6)),
                       np.zeros((n, n_s)), np.zeros((n, 6)), np.zeros((n, 6, m + 6)))
        qc = self._diffusion(prior)
        s, p = self._initial(idx[0], prior, wind0)
        r = np.diag(r_diag)
        eye = np.eye(n_s)
        loglik = 0.0
        for j, k in enumerate(idx):
            if j > 0:
                if online:
                    lin.tp[j] = s
                    lin.f0[j], lin.jt[j], lin.fr[j] = self._transition_lin(k, s)
                a, drift = self._system(lin.f0[j], lin.jt[j], lin.tp[j], s, prior)
                phi, q, step = self._discretise(a, drift, qc, d.t[k] - d.t[k - 1],
                                                lin.fr[j])
                s = s + step
                p = phi @ p @ phi.T + q
                phi_all[j] = phi
            mp[j] = s
            pp[j] = p
            if online:
                lin.mp[j] = s
                lin.z0[j], lin.jz[j] = self._measurement_lin(k, s)
            jz = lin.jz[j]
            h_mat = self._h_matrix(jz)
            innov = d.z[k] - (lin.z0[j] + h_mat @ (s - lin.mp[j]))
            ph = p @ h_mat.T
            s_cov = h_mat @ ph + r
            try:
                chol = np.linalg.cholesky(s_cov)
            except np.linalg.LinAlgError:
                chol = None  # no channel update here; the anchor reads no channel
            if chol is not None:
                gain = np.linalg.solve(s_cov, ph.T).T
                s = s + gain @ innov
                ikh = eye - gain @ h_mat
                p = ikh @ p @ ikh.T + gain @ r @ gain.T
                p = 0.5 * (p + p.T)
                y = np.linalg.solve(chol, innov)
                loglik -= 0.5 * (y @ y + 2.0 * np.sum(np.log(np.diag(chol))) + 6 * LOG_2PI)
            if anchored and self.anchor[2][k]:
                s, p, anchor_gain[j] = self._anchor_update(k, s, p)
            mf[j], pf[j] = s, p
        return _Pass(mf, pf, mp, pp, phi_all, loglik=loglik, anchor_gain=anchor_gain), lin

    def _anchor_update(self, k: int, s: np.ndarray, p: np.ndarray):
        """The anchor's mean flow at sample k as a measurement of v (Joseph form):
        (state, covariance, gain (N, 3))."""
        mean, std, _ = self.anchor
        h = self._anchor_rows
        r = np.diag(std[k] ** 2)
        ph = p @ h.T
        gain = np.linalg.solve(h @ ph + r, ph.T).T
        s = s + gain @ (mean[k] - h @ s)
        ikh = self._eye - gain @ h
        p = ikh @ p @ ikh.T + gain @ r @ gain.T
        return s, 0.5 * (p + p.T), gain

    @staticmethod
    def _backward(ps: _Pass) -> None:
        n = ps.mf.shape[0]
        ms = ps.mf.copy()
        pss = ps.pf.copy()
        cs = np.zeros_like(ps.pf)  # cs[k] = Cov(s_k, s_{k-1} | all)
        gains = np.zeros_like(ps.pf)
        for k in range(n - 2, -1, -1):
            pred = ps.pp[k + 1]
            cross = ps.pf[k] @ ps.phi[k + 1].T
            g = _smoother_gain(cross, pred)
            gains[k] = g
            ms[k] = ps.mf[k] + g @ (ms[k + 1] - ps.mp[k + 1])
            pk = ps.pf[k] + g @ (pss[k + 1] - pred) @ g.T
            pss[k] = 0.5 * (pk + pk.T)
            cs[k + 1] = pss[k + 1] @ g.T
        ps.ms, ps.ps, ps.cs, ps.gain = ms, pss, cs, gains

    # -- EM ---------------------------------------------------------------------------
    def _em(self, passes: list[tuple[slice, _Pass, _Lin]], prior: WindPrior,
            r_diag: np.ndarray) -> tuple[WindPrior, np.ndarray]:
        d = self.pre.data
        s00 = np.zeros(6)
        s11 = np.zeros(6)
        s10 = np.zeros(6)
        pairs = 0
        dts = []
        res2 = np.zeros(6)
        count = 0
        xi = self.xi
        for run, ps, lin in passes:
            ms, pss, cs = ps.ms, ps.ps, ps.cs
            n = ms.shape[0]
            if n >= 2:
                diag_p = np.einsum("kii->ki", pss)
                diag_c = np.einsum("kii->ki", cs)
                s11 += np.sum(ms[1:, xi] ** 2 + diag_p[1:, xi], 0)
                s00 += np.sum(ms[:-1, xi] ** 2 + diag_p[:-1, xi], 0)
                s10 += np.sum(ms[1:, xi] * ms[:-1, xi] + diag_c[1:, xi], 0)
                pairs += n - 1
                dts.append(np.diff(d.t[run]))
            for j in range(n):
                h_mat = self._h_matrix(lin.jz[j])
                e = d.z[run.start + j] - (lin.z0[j] + h_mat @ (ms[j] - lin.mp[j]))
                res2 += e * e + np.einsum("ij,jk,ik->i", h_mat, pss[j], h_mat)
            count += n
        new = prior.copy()
        if pairs > 0 and "sigma" in self.learn:
            dt = float(np.mean(np.concatenate(dts)))
            a = np.exp(-dt / prior.tau_s)  # tau from physics (wind_prior), sigma learned
            q = np.maximum((s11 - 2.0 * a * s10 + a * a * s00) / pairs, 0.0)
            new.sigma = np.maximum(np.sqrt(q / (1.0 - a * a)), SIGMA_FLOOR)
            if "rotation_from_mean_flow" in self.learn:
                tied = list(TIED_ROTATION)
                new.sigma[tied] = np.maximum(new.rotation_sigma()[[i - 3 for i in tied]],
                                             SIGMA_FLOOR[tied])
        new_r = r_diag
        if "noise" in self.learn and count > 0:
            new_r = np.maximum(res2 / count, self.noise_floor**2)
        return new, new_r

    # -- the whole flight -----------------------------------------------------------
    def run(self, progress=None) -> SmootherResult:
        t0 = time.perf_counter()
        d = self.pre.data
        prior = self.prior
        r_diag = self.noise_std**2
        history = []
        passes = []
        with single_blas_thread():
            for it in range(self.iterations):
                relin = it < self.relinearise
                passes_new = []
                for ri, run in enumerate(d.runs):
                    online = it == 0
                    lin = None
                    if not online:
                        _, old, lin = passes[ri]
                        if relin:
                            lin = self._relinearise(run, old)
                    ps, lin = self._forward(run, prior, r_diag, lin, online)
                    self._backward(ps)
                    passes_new.append((run, ps, lin))
                passes = passes_new
                loglik = float(sum(ps.loglik for _, ps, _ in passes))
                history.append({"pass": it + 1, "relinearised": relin,
                                "log_likelihood": loglik, "prior": prior.to_dict(),
                                "noise_std": np.sqrt(r_diag).tolist()})
                if progress is not None:
                    progress.update(it + 1, f"log-likelihood {loglik:.5g}")
                if it < self.iterations - 1:
                    prior, r_diag = self._em(passes, prior, r_diag)
        # the last pass, for what is asked of it afterwards (offset_std)
        self.last_passes, self.last_noise = passes, r_diag.copy()
        return self._result(passes, prior, np.sqrt(r_diag), history,
                            time.perf_counter() - t0)

    # -- steady measurement offsets ------------------------------------------------
    def offset_sensitivity(self, anchor: bool = False) -> np.ndarray:
        """(n, 6, 6) d(smoothed wind) / d(a constant offset on each measured channel), at
        every kept sample, for the last pass of `run` (its linearisation, gains and
        noise); with `anchor`, (n, 6, 3) for a constant offset on each component of the
        anchor's mean flow. The smoothed mean of a pass is affine in the measurements (the
        pass is linearised along a fixed trajectory), so a constant offset e_j moves it by
        exactly the response of the same filter and smoother to that offset:
            d_k^- = Phi_k d_{k-1},  d_k = d_k^- + K_k (e_j - H_k d_k^-)
            (then the anchor's update: d_k += K^a_k (e^a_j - H^a d_k))
            d^s_k = d_k + G_k (d^s_{k+1} - d^-_{k+1})
        (Schmidt's "consider" analysis: the estimate is not changed, its uncertainty
        is)."""
        passes = getattr(self, "last_passes", None)
        if passes is None:
            raise RuntimeError("offset_sensitivity: run() the smoother first")
        n_s = self.n_state
        q = 3 if anchor else 6
        out = np.full((self.pre.data.t.size, 6, q), np.nan)
        c = self._wind_rows()
        r = np.diag(self.last_noise)
        e_channels = np.zeros((6, q)) if anchor else np.eye(6)
        e_anchor = np.eye(3) if anchor else np.zeros((3, q))
        with single_blas_thread():
            for run, ps, lin in passes:
                n = ps.mf.shape[0]
                df = np.zeros((n, n_s, q))
                dp = np.zeros((n, n_s, q))
                d = np.zeros((n_s, q))
                for j in range(n):
                    if j > 0:
                        d = ps.phi[j] @ d
                    dp[j] = d
                    h_mat = self._h_matrix(lin.jz[j])
                    ph = ps.pp[j] @ h_mat.T
                    s_cov = h_mat @ ph + r
                    try:
                        np.linalg.cholesky(s_cov)
                        gain = np.linalg.solve(s_cov, ph.T).T
                        d = d + gain @ (e_channels - h_mat @ d)
                    except np.linalg.LinAlgError:
                        pass  # the filter made no channel update here either
                    if ps.anchor_gain is not None:  # (zero at samples without the anchor)
                        d = d + ps.anchor_gain[j] @ (e_anchor - c[:3] @ d)
                    df[j] = d
                ds = df.copy()
                for k in range(n - 2, -1, -1):
                    ds[k] = df[k] + ps.gain[k] @ (ds[k + 1] - dp[k + 1])
                out[run] = np.einsum("wi,kic->kwc", c, ds)
        return out

    def offset_std(self, offset_std) -> np.ndarray:
        """(n, 6) the wind's std from steady channel offsets of std `offset_std` (6,),
        independent per channel, that the estimate does not know of (the model's
        still-air `model_error_offset`): sqrt(sum_j (S_kj sigma_j)^2) per component."""
        return _consider_std(self.offset_sensitivity(), _offset_stds(offset_std))

    def anchor_offset_std(self, anchor_std) -> np.ndarray:
        """(n, 6) the wind's std from a steady error of std `anchor_std` (3,) on each
        component of the anchor's mean flow, which its per-sample measurement treats as
        white: a net's error is correlated over the flight (its bias, its smoothing)."""
        return _consider_std(self.offset_sensitivity(anchor=True),
                             np.asarray(anchor_std, dtype=float))

    def _relinearise(self, run: slice, old: _Pass) -> _Lin:
        """Linearisation of a run along its previous smoothed trajectory."""
        m, n_s = self.m, self.n_state
        idx = np.arange(run.start, run.stop)
        n = idx.size
        lin = _Lin(np.zeros((n, n_s)), np.zeros((n, m)), np.zeros((n, m, m + 6)),
                   old.ms.copy(), np.zeros((n, 6)), np.zeros((n, 6, m + 6)))
        for j, k in enumerate(idx):
            if j > 0:
                lin.tp[j] = old.ms[j - 1]
                lin.f0[j], lin.jt[j], lin.fr[j] = self._transition_lin(k, old.ms[j - 1])
            lin.z0[j], lin.jz[j] = self._measurement_lin(k, old.ms[j])
        return lin

    # -- the Cramer-Rao bound ------------------------------------------------------
    def open_loop(self, wind: np.ndarray) -> np.ndarray:
        """(n, 6) the model's prediction of the measured channels at every kept sample,
        its rotor states propagated by the smoother's own step from quasi-steady at each
        run's start, through the wind trajectory `wind` (n, 6), with no measurement
        update: how well the step integrates the model, apart from the filter."""
        m, n_s = self.m, self.n_state
        d = self.pre.data
        wind = np.asarray(wind, dtype=float)
        out = np.full((d.t.size, 6), np.nan)
        with single_blas_thread():
            for run in d.runs:
                idx = np.arange(run.start, run.stop)
                point, _ = self._initial(idx[0], self.prior, wind[idx[0]])
                for k in idx:
                    if k > idx[0]:
                        f0, jt, fr = self._transition_lin(k, point)
                        a, drift = self._system(f0, jt, point, point, self.prior)
                        _, _, step = self._discretise(a, drift, np.zeros(n_s),
                                                      d.t[k] - d.t[k - 1], fr)
                        point = point.copy()
                        point[:m] += step[:m]
                    point[self.mu] = wind[k]
                    point[self.xi] = 0.0
                    out[k], _ = self._measurement_lin(k, point)
        return out

    def bound(self, wind: np.ndarray, prior: WindPrior, noise_std,
              offset_std=None) -> np.ndarray:
        """(n, 6) posterior Cramer-Rao lower bound (std) of each wind component at every
        kept sample, for the wind trajectory `wind` (n, 6) (the truth, or an estimate),
        the prior and the channel noise `noise_std` (6,).

        Tichavsky, Muravchik & Nehorai (1998): for a Gauss-Markov state observed with
        Gaussian noise, the Bayesian information of the state obeys the Kalman
        covariance recursion with the Jacobians taken at the true trajectory; for the
        smoothed (whole-flight) estimate the bound is the RTS covariance. The rotor states
        along the truth are integrated with the same exponential step as the filter, the
        wind held at `wind`. Only the model's sensitivities, the noise and the prior
        enter: no measurement.

        noise_std: (6,) white channel noise, or a `ChannelNoise` — each channel's error as
        a coloured (autoregressive) Gaussian process, the model's misfit as it is: a
        misfit whose power sits at low frequency informs a slow wind less than white
        noise of the same RMS, one at high frequency more — or a `VectorNoise`, the six
        channels' errors as one vector AR process (a misfit with one cause in several
        channels is partly cancellable between them). offset_std (6,), optional:
        steady channel offsets (the model's still-air `model_error_offset`, an
        accelerometer's turn-on bias) as nuisance parameters, random constants of that
        prior std (0: none on that channel). Both enter as states of an augmented
        Gauss-Markov system (the AR process in companion form, the offsets constant), and
        the bound is the wind's marginal of its RTS covariance (`_bound_augmented`).
        Offsets are common to a run; runs are taken one by one (a flight with gaps gets
        no information about the offsets across them: a bound no lower than the exact
        one). The smoother's own channel-bias states are left out: the channel error given
        here is the misfit as it is, its slow part included."""
        with self._without_bias():
            return self._bound(wind, prior, noise_std, offset_std)

    @contextmanager
    def _without_bias(self):
        """The state without the channel-bias states, for the duration."""
        saved = (self.bias_channels, self.bias_sigma)
        self._set_bias(np.zeros(0, int), np.zeros(0))
        try:
            yield
        finally:
            self._set_bias(*saved)

    def _set_bias(self, channels: np.ndarray, sigma: np.ndarray) -> None:
        """The channel-bias states (after xi) and what follows from them: their slice and
        column indexes, the state's size."""
        self.bias_channels, self.bias_sigma = channels, sigma
        start = self.m + 12
        self._bias_cols = np.arange(start, start + channels.size)
        self.bias = slice(start, start + channels.size)
        self.n_state = start + channels.size

    def _bound(self, wind, prior, noise_std, offset_std) -> np.ndarray:
        m, n_s = self.m, self.n_state
        d = self.pre.data
        wind = np.asarray(wind, dtype=float)
        coloured = isinstance(noise_std, (ChannelNoise, VectorNoise))
        if offset_std is not None:
            offset_std = _offset_stds(offset_std)
            if not np.any(offset_std > 0):
                offset_std = None
        if not coloured and offset_std is not None:
            noise_std = ChannelNoise.white(noise_std)
            coloured = True
        r_diag = None if coloured else np.asarray(noise_std, float) ** 2
        out = np.full((d.t.size, 6), np.nan)
        c = self._wind_rows()
        with single_blas_thread():
            for run in d.runs:
                idx = np.arange(run.start, run.stop)
                n = idx.size
                lin = _Lin(np.zeros((n, n_s)), np.zeros((n, m)), np.zeros((n, m, m + 6)),
                           np.zeros((n, n_s)), np.zeros((n, 6)), np.zeros((n, 6, m + 6)))
                point, _ = self._initial(idx[0], prior, wind[idx[0]])
                for j, k in enumerate(idx):
                    if j > 0:
                        lin.tp[j] = point
                        lin.f0[j], lin.jt[j], lin.fr[j] = self._transition_lin(k, point)
                        a, drift = self._system(lin.f0[j], lin.jt[j], point, point, prior)
                        _, _, step = self._discretise(a, drift, np.zeros(n_s),
                                                      d.t[k] - d.t[k - 1], lin.fr[j])
                        point = point.copy()
                        point[:m] += step[:m]
                        point[self.mu] = wind[k]
                        point[self.xi] = 0.0
                    lin.mp[j] = point
                    lin.z0[j], lin.jz[j] = self._measurement_lin(k, point)
                if coloured:
                    cov = self._bound_augmented(run, lin, prior, noise_std, offset_std,
                                                wind[idx[0]])
                    out[run] = np.sqrt(np.maximum(np.einsum("ij,kjl,il->ki", c, cov, c), 0))
                    continue
                ps, _ = self._forward(run, prior, r_diag, lin, online=False,
                                      wind0=wind[idx[0]], anchored=False)
                self._backward(ps)
                out[run] = np.sqrt(np.maximum(np.einsum("ij,kjl,il->ki", c, ps.ps, c), 0))
        return out

    def _bound_augmented(self, run: slice, lin: _Lin, prior: WindPrior,
                         noise: ChannelNoise | VectorNoise, offset_std,
                         wind0) -> np.ndarray:
        """(n, N, N) the smoothed covariance of the model's states along `lin` when the
        channel noise is `noise` (AR per channel or one VAR, plus white) and steady
        offsets of std `offset_std` (or None) add to the channels: a covariance-only Kalman
        filter and RTS smoother over [states | the noise's companion states | the
        offsets]."""
        n_s = self.n_state
        d = self.pre.data
        on = np.zeros(6, bool) if offset_std is None else offset_std > 0
        n_b = int(on.sum())
        # the noise block (its companion form) and its innovation
        f_ar, q_ar, sel_ar = noise.companion()
        n_ar = f_ar.shape[0]
        n_a = n_s + n_ar + n_b
        ar = slice(n_s, n_s + n_ar)
        b = slice(n_s + n_ar, n_a)
        sel = np.zeros((6, n_a))  # which augmented states add to each channel
        sel[:, ar] = sel_ar
        sel[np.flatnonzero(on), b] = np.eye(n_b)
        r = noise.white_cov()
        idx = np.arange(run.start, run.stop)
        n = idx.size
        _, p0 = self._initial(idx[0], prior, wind0)
        p = np.zeros((n_a, n_a))
        p[:n_s, :n_s] = p0
        p[ar, ar] = noise.stationary_covariance()
        if n_b:
            p[b, b] = np.diag(offset_std[on] ** 2)
        qc = self._diffusion(prior)
        pf = np.empty((n, n_a, n_a))
        pp = np.empty((n, n_a, n_a))
        phis = np.zeros((n, n_a, n_a))
        eye = np.eye(n_a)
        for j, k in enumerate(idx):
            if j > 0:
                a, drift = self._system(lin.f0[j], lin.jt[j], lin.tp[j], lin.tp[j], prior)
                phi_s, q_s, _ = self._discretise(a, drift, qc, d.t[k] - d.t[k - 1], lin.fr[j])
                phi = eye.copy()
                phi[:n_s, :n_s] = phi_s
                phi[ar, ar] = f_ar
                p = phi @ p @ phi.T
                p[:n_s, :n_s] += q_s
                p[ar, ar] += q_ar
                phis[j] = phi
            pp[j] = p
            h_aug = sel.copy()
            h_aug[:, :n_s] = self._h_matrix(lin.jz[j])
            ph = p @ h_aug.T
            s_cov = h_aug @ ph + r
            try:
                gain = np.linalg.solve(s_cov, ph.T).T
            except np.linalg.LinAlgError:
                pf[j] = p
                continue
            ikh = eye - gain @ h_aug
            p = ikh @ p @ ikh.T + gain @ r @ gain.T
            p = 0.5 * (p + p.T)
            pf[j] = p
        ps = pf.copy()
        for k in range(n - 2, -1, -1):
            g = _smoother_gain(pf[k] @ phis[k + 1].T, pp[k + 1])
            pk = pf[k] + g @ (ps[k + 1] - pp[k + 1]) @ g.T
            ps[k] = 0.5 * (pk + pk.T)
        return ps[:, :n_s, :n_s]

    def _result(self, passes, prior, noise_std, history, seconds) -> SmootherResult:
        n = self.pre.data.t.size
        out = {k: np.full((n, 6), np.nan) for k in ("mean", "std", "fm", "fs", "xs", "bias")}
        c = self._wind_rows()
        for run, ps, _ in passes:
            out["mean"][run] = ps.ms @ c.T
            out["std"][run] = np.sqrt(np.maximum(np.einsum("ij,kjl,il->ki", c, ps.ps, c), 0))
            out["fm"][run] = ps.mf @ c.T
            out["fs"][run] = np.sqrt(np.maximum(np.einsum("ij,kjl,il->ki", c, ps.pf, c), 0))
            out["xs"][run] = np.sqrt(np.maximum(
                np.einsum("kii->ki", ps.ps[:, self.xi, self.xi]), 0))
            out["bias"][run, self.bias_channels] = ps.ms[:, self.bias]
        return SmootherResult(self.pre.data.t.copy(), out["mean"], out["std"], out["fm"],
                              out["fs"], prior, noise_std, history, seconds,
                              self.evaluations, out["xs"], out["bias"])
