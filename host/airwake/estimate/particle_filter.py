"""Active particle filter (reference §5.4, eq 5.17), regularised, NaN-proof.

    pf = ParticleFilter(WindMeasurementModel(model, data), n_particles=2000, sigma=0.5,
                        resampler=systematic, rng=np.random.default_rng(0))
    out = pf.run()                       # FilterOutput: mean, std (T, 6), ess (T,), ...

Per sample k (the model supplies the physics, this class only the algorithm):
  1. propagate: every particle's wind takes a random-walk step (k > 0);
  2. predict + weight: the 6 channels for all particles in one batched model call (the
     model also completes its rotor-state step with it), log w_j += -||(z - z_hat_j)/s||
     / sigma (eq 5.17), normalised in log space
     (subtract the maximum before exp: no underflow, no NaN; non-finite -> weight 0; if
     every particle is non-finite the sample is skipped and flagged);
  3. estimate: posterior mean and std of each component, ESS = 1/sum w^2;
  4. resample when ESS < ess_threshold * N (default 1/2; the reference's roulette wheel
     = multinomial with threshold 1, i.e. every sample), then regularise: every wind gets
     a Gaussian kernel jitter with covariance (b h_opt)^2 Sigma + floor^2, Sigma the
     weighted covariance before resampling, h_opt = (4/(N (d+2)))^(1/(d+4)) (Silverman;
     Musso, Oudjane & Le Gland 2001), b = `jitter` (0.2: b = 1 resampled on most samples
     acts as a large extra process noise, see docs/wind-estimation.md), floor = 10 % of
     the process step, so the cloud never collapses onto a few copies.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from airwake.calibrate.hidden import single_blas_thread
from airwake.estimate.resample import effective_sample_size, systematic


@dataclass
class FilterOutput:
    """Per sample: mean, std (T, D) posterior of the wind; ess (T,); resampled (T,) bool;
    skipped (T,) bool (no particle had a finite likelihood: the update was skipped)."""

    mean: np.ndarray
    std: np.ndarray
    ess: np.ndarray
    resampled: np.ndarray
    skipped: np.ndarray


class ParticleFilter:
    """Sequential importance resampling with regularisation over a state-space `model`
    (see module docstring; `model` needs n_steps, initial(n, rng), propagate(p, k, rng),
    log_likelihood(p, k, sigma), clip(wind), process_step_std(k); particles need `wind`
    (N, D) and take(indexes))."""

    def __init__(self, model, n_particles: int = 2000, sigma: float = 0.5,
                 resampler=systematic, ess_threshold: float = 0.5, jitter: float = 0.2,
                 rng: np.random.Generator | None = None) -> None:
        if n_particles < 2:
            raise ValueError(f"n_particles = {n_particles}: need at least 2")
        if not (np.isfinite(sigma) and sigma > 0):
            raise ValueError(f"sigma = {sigma!r}: must be a positive number")
        if not 0.0 <= ess_threshold <= 1.0:
            raise ValueError(f"ess_threshold = {ess_threshold!r}: must be in [0, 1]")
        if not (np.isfinite(jitter) and jitter >= 0):
            raise ValueError(f"jitter = {jitter!r}: must be >= 0")
        self.model = model
        self.n = int(n_particles)
        self.sigma = float(sigma)
        self.resampler = resampler
        self.ess_threshold = float(ess_threshold)
        self.jitter = float(jitter)
        self.rng = rng if rng is not None else np.random.default_rng()
        d = 6
        self.h_opt = (4.0 / (self.n * (d + 2))) ** (1.0 / (d + 4))
        self.particles = None
        self.log_w = np.zeros(self.n)

    # -- one sample -------------------------------------------------------------------
    def step(self, k: int):
        """Process sample k; returns (mean (D,), std (D,), ess, resampled, skipped)."""
        m = self.model
        if k == 0 or self.particles is None:
            self.particles = m.initial(self.n, self.rng)
            self.log_w = np.zeros(self.n)
        else:
            m.propagate(self.particles, k, self.rng)
        p = self.particles
        ll = m.log_likelihood(p, k, self.sigma)
        log_w = self.log_w + ll
        top = np.max(log_w)
        skipped = not np.isfinite(top)
        if skipped:  # no particle explains the sample: keep the previous weights
            log_w = self.log_w
            top = np.max(log_w)
        w = np.exp(log_w - top)
        w /= w.sum()
        self.log_w = np.log(np.maximum(w, 1e-300))
        mean = w @ p.wind
        dev = p.wind - mean
        var = w @ (dev * dev)
        std = np.sqrt(np.maximum(var, 0.0))
        ess = effective_sample_size(w)
        resampled = ess < self.ess_threshold * self.n or self.ess_threshold >= 1.0
        if resampled:
            cov = (dev * w[:, None]).T @ dev
            idx = self.resampler(w, self.rng)
            self.particles = p.take(idx)
            self.log_w = np.zeros(self.n)
            self._regularise(cov, k)
        return mean, std, ess, resampled, skipped

    def _regularise(self, cov: np.ndarray, k: int) -> None:
        floor = 0.1 * self.model.process_step_std(k)
        c = (self.jitter * self.h_opt) ** 2 * cov + np.diag(floor**2 + 1e-18)
        try:
            chol = np.linalg.cholesky(c)
        except np.linalg.LinAlgError:
            chol = np.diag(np.sqrt(np.maximum(np.diag(c), 1e-18)))
        p = self.particles
        p.wind = self.model.clip(p.wind + self.rng.standard_normal(p.wind.shape) @ chol.T)

    # -- a whole flight ----------------------------------------------------------------
    def run(self, steps: int | None = None, progress=None) -> FilterOutput:
        t = self.model.n_steps if steps is None else min(int(steps), self.model.n_steps)
        mean = np.empty((t, 6))
        std = np.empty((t, 6))
        ess = np.empty(t)
        res = np.zeros(t, dtype=bool)
        skip = np.zeros(t, dtype=bool)
        with single_blas_thread():
            for k in range(t):
                mean[k], std[k], ess[k], res[k], skip[k] = self.step(k)
                if progress is not None and k % 150 == 0:
                    progress.update(k, f"ESS {ess[k]:.0f}")
        return FilterOutput(mean, std, ess, res, skip)
