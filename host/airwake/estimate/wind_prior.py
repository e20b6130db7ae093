"""The wind's prior: what the estimator assumes about the air before it sees the flight.

The eq 5.3 wind w = [v_x v_y v_z w_x w_y w_z] (body axes at the hub) is written as a slowly
drifting mean plus turbulence,

    w(t) = mu(t) + xi(t)
    d mu = q_mu dB                               random walk: the mean flow changes as the
                                                 helicopter moves through the wake
    d xi = -xi / tau dt + sigma sqrt(2/tau) dB   first-order Gauss-Markov turbulence:
                                                 std sigma, correlation time tau

per component, independent. Why this and not the reference's pure random walk (§5.4.2):
a random walk wide enough to follow turbulence lets the wind wander without bound along
any direction the measurements see weakly (near hover, v_x against w_y and v_y against
w_x), and the estimate drifts there; turbulence is stationary, and a Gauss-Markov state
says so. The mean keeps its own slow walk so that a non-zero mean (the 1 m/s headwind of a
ship flight, a swirl's mean rotation) stays estimable rather than shrunk to zero.

Defaults from physics, then from the flight itself (`airwake.estimate.smoother` refits
sigma to each flight by expectation-maximisation, Shumway & Stoffer 1982; tau and q_mu
stay as set here):

- tau from Taylor's frozen turbulence: eddies of size L carried past the rotor at the
  airspeed U decorrelate in L/U. The mean-flow components average the flow over the rotor
  (L ~ the turbulence integral scale, taken as 2 rotor diameters to start); the rotation
  components are gradients across the disc, which decorrelate once the air has moved one
  diameter (L ~ 2R). U = `airspeed_m_s` (3 m/s unless given).
- sigma: 0.5 m/s and 0.5 rad/s to start — moderate turbulence (TI ~ 15 % at 3 m/s) — so the
  first pass does not squeeze the wind before the flight has been heard.
- q_mu: 0.05 m/s/sqrt(s) and 0.02 (1/s)/sqrt(s): the mean moves ~0.4 m/s over a minute.
- mean at the start: N(0, (3 m/s)^2) horizontally, (1.5 m/s)^2 vertically, (0.5 1/s)^2.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

AIRSPEED_M_S = 3.0
TAU_BOUNDS_S = (0.08, 8.0)


def _vec(name, v, n=6, positive=True):
    a = np.asarray(v, dtype=float).reshape(-1)
    if a.size == 1:
        a = np.full(n, float(a[0]))
    if a.shape != (n,) or not np.all(np.isfinite(a)) or (positive and np.any(a <= 0)):
        raise ValueError(f"{name} must be {n} positive numbers, got {v!r}")
    return a


@dataclass
class WindPrior:
    """Gauss-Markov prior of the eq 5.3 wind (module docstring). All (6,): sigma (m/s x3,
    1/s x3), tau_s (s), mean_walk (per sqrt(s)), mean_std0 (the mean's std at the start)."""

    sigma: np.ndarray
    tau_s: np.ndarray
    mean_walk: np.ndarray
    mean_std0: np.ndarray
    source: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.sigma = _vec("sigma", self.sigma)
        self.tau_s = _vec("tau_s", self.tau_s)
        self.mean_walk = _vec("mean_walk", self.mean_walk)
        self.mean_std0 = _vec("mean_std0", self.mean_std0)

    @classmethod
    def from_physics(cls, rotor_radius_m: float, airspeed_m_s: float = AIRSPEED_M_S,
                     sigma=(0.5, 0.5, 0.5, 0.5, 0.5, 0.5)) -> WindPrior:
        """The starting prior for a rotor of radius R flown at `airspeed_m_s` relative to
        the air (module docstring)."""
        if not (np.isfinite(rotor_radius_m) and rotor_radius_m > 0):
            raise ValueError(f"rotor_radius_m = {rotor_radius_m!r}: must be > 0")
        u = max(float(airspeed_m_s), 0.5)
        diameter = 2.0 * rotor_radius_m
        tau_v = 2.0 * diameter / u
        tau_w = diameter / u
        tau = np.clip([tau_v] * 3 + [tau_w] * 3, *TAU_BOUNDS_S)
        return cls(sigma=sigma, tau_s=tau, mean_walk=(0.05, 0.05, 0.05, 0.02, 0.02, 0.02),
                   mean_std0=(3.0, 3.0, 1.5, 0.5, 0.5, 0.5),
                   source={"rotor_radius_m": float(rotor_radius_m), "airspeed_m_s": u,
                           "rule": "tau = 2D/U (mean flow), D/U (rotation); EM-refined"})

    def copy(self) -> WindPrior:
        return WindPrior(self.sigma.copy(), self.tau_s.copy(), self.mean_walk.copy(),
                         self.mean_std0.copy(), dict(self.source))

    def fitted_to(self, wind, t, floor=None) -> WindPrior:
        """A copy whose turbulence std `sigma` describes the wind trajectory `wind` (n, 6)
        sampled at times `t` (n,): the Gauss-Markov innovation of each component about its
        mean at this prior's tau, q = mean (w_k+1 - a w_k)^2 with a = exp(-dt / tau) over
        the regular steps (a gap of more than 1.5 median steps breaks the chain), sigma =
        sqrt(q / (1 - a^2)) (the EM's update with the trajectory in place of its smoothed
        states), floored at `floor`. What the bound at the truth uses: the prior that
        describes the air actually flown through."""
        w = np.asarray(wind, dtype=float)
        t = np.asarray(t, dtype=float)
        if w.ndim != 2 or w.shape[1] != 6 or t.shape != (w.shape[0],) or w.shape[0] < 3:
            raise ValueError(f"wind must be (n >= 3, 6) with t (n,), got {w.shape} and "
                             f"{t.shape}")
        ok = np.all(np.isfinite(w), axis=1)
        w = w - w[ok].mean(axis=0)
        dt = np.diff(t)
        step = np.median(dt)
        pair = ok[1:] & ok[:-1] & (dt > 0) & (dt <= 1.5 * step)
        if not pair.any():
            raise ValueError("the wind trajectory has no two consecutive finite samples")
        a = np.exp(-dt[pair, None] / self.tau_s)
        q = np.mean((w[1:][pair] - a * w[:-1][pair]) ** 2, axis=0)
        sigma = np.sqrt(q / (1.0 - np.exp(-2.0 * step / self.tau_s)))
        out = self.copy()
        out.sigma = np.maximum(sigma, 1e-9 if floor is None else floor)
        out.source = {**out.source, "sigma": "fitted to a wind trajectory"}
        return out

    def rotation_sigma(self, mean_flow_sigma=None) -> np.ndarray:
        """(3,) the rotation's turbulence std (1/s) that goes with a mean-flow std (3,)
        (default: this prior's), for frozen isotropic turbulence whose correlation falls as
        exp(-r / L) (module docstring; L = the integral scale of the mean-flow tau rule,
        2 diameters): the velocity differs across the rotor radius R by
        sigma_v sqrt(2 (1 - exp(-R / L))) (the structure function at r = R), and a rotation
        omega moves the air at R by omega R, so sigma_omega = that difference / R, with
        sigma_v the RMS of the three mean-flow components (isotropy)."""
        r = float(self.source.get("rotor_radius_m", float("nan")))
        u = float(self.source.get("airspeed_m_s", float("nan")))
        if not (np.isfinite(r) and r > 0 and np.isfinite(u) and u > 0):
            raise ValueError("rotation_sigma needs a prior made by from_physics (its rotor "
                             "radius and airspeed)")
        sv = self.sigma[:3] if mean_flow_sigma is None else np.asarray(mean_flow_sigma, float)
        scale = float(self.tau_s[0]) * u  # the mean flow's integral scale L = tau U
        diff = float(np.sqrt(np.mean(sv**2))) * np.sqrt(2.0 * (1.0 - np.exp(-r / scale)))
        return np.full(3, diff / r)

    # -- the linear SDE of the 12 wind states [mu (6), xi (6)] --------------------------
    def drift_matrix(self) -> np.ndarray:
        """(12, 12): d[mu, xi]/dt = F [mu, xi] + noise."""
        f = np.zeros((12, 12))
        f[6:, 6:] = np.diag(-1.0 / self.tau_s)
        return f

    def diffusion(self) -> np.ndarray:
        """(12,) white-noise intensities (variance per second) of [mu, xi]."""
        return np.concatenate([self.mean_walk**2, 2.0 * self.sigma**2 / self.tau_s])

    def initial_covariance(self) -> np.ndarray:
        """(12, 12) covariance of [mu, xi] at the start of a run."""
        return np.diag(np.concatenate([self.mean_std0**2, self.sigma**2]))

    def to_dict(self) -> dict:
        return {"sigma": self.sigma.tolist(), "tau_s": self.tau_s.tolist(),
                "mean_walk": self.mean_walk.tolist(), "mean_std0": self.mean_std0.tolist(),
                "source": dict(self.source)}
