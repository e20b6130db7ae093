"""The result of a calibration and the parameter-uncertainty / identifiability analysis.

Uncertainty (both methods, from the Jacobian J of the weighted residuals at the fit):

    Cov(p) = s^2 (J^T J)^-1,   s^2 = |r|^2 / (n - p)

valid for white, independent residuals. A calibration's residuals are neither: the front
end's low-pass colours them over ~f_s / (2 f_c) samples and the model's own error holds
over whole manoeuvres. With the residuals grouped in independent clusters g (the
calibration's windows), the cluster-robust ("sandwich") covariance

    Cov(p) = G/(G-1) (J^T J)^-1 (sum_g J_g^T r_g r_g^T J_g) (J^T J)^-1

takes whatever correlation the residuals have within a window from the residuals
themselves (on the blade-element still-air flight its 1-sigma are 6-35x the white ones).
It is used when there are at least `MIN_CLUSTERS_PER_PARAMETER` clusters per free
parameter (fewer make its middle matrix too poorly estimated); otherwise the white
formula, with a note that says so. It is still optimistic: windows next to each other are
not independent (a manoeuvre, a misfit lasts longer than 2 s), and model error shared by
all the windows is in neither formula.

A direction of parameter space J does not see (singular value below 1e-9
of the largest, columns normalised) gets infinite uncertainty instead of a made-up
number. Identifiability notes name: parameters at a bound, parameters whose 1-sigma is
more than `REL_STD_LIMIT` of their value, pairs correlated beyond `CORR_LIMIT`, and the
weakest parameter combinations (smallest singular vectors).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

REL_STD_LIMIT = 0.25
CORR_LIMIT = 0.95
SINGULAR_RCOND = 1e-9
MIN_CLUSTERS_PER_PARAMETER = 2


@dataclass
class Uncertainty:
    std: np.ndarray  # (p,) 1-sigma, inf where unidentifiable
    correlation: np.ndarray  # (p, p), NaN where undefined
    sigma2: float  # residual variance (weighted units)
    condition: float  # condition number of the column-normalised Jacobian
    weak_directions: list  # [(singular value ratio, [(name, loading), ...]), ...]
    kind: str = "white"  # "white" or "clustered" (sandwich over the clusters)
    std_white: np.ndarray | None = None  # (p,) the white-residual 1-sigma, for comparison
    clusters: int = 0  # clusters of the sandwich (0: none given)


def uncertainty(jac: np.ndarray, residual: np.ndarray, names, free_values,
                active=None, clusters=None) -> Uncertainty:
    """Parameter covariance from J (n, p) (d residual / d parameter, parameter units) and
    the residual vector r (n,). `active` (p,) marks parameters held at a bound: they are
    excluded from the covariance (std NaN). `clusters` (n,) labels the residuals' independent
    groups (the windows): the sandwich covariance when there are enough (module doc)."""
    n, p = jac.shape
    active = np.zeros(p, dtype=bool) if active is None else np.asarray(active, bool)
    use = ~active
    std = np.full(p, np.nan)
    corr = np.full((p, p), np.nan)
    dof = max(n - int(use.sum()), 1)
    sigma2 = float(residual @ residual / dof)
    weak = []
    cond = np.nan
    kind, std_white, n_clusters = "white", np.full(p, np.nan), 0
    if clusters is not None:
        if np.shape(clusters) != (n,):
            raise ValueError(f"clusters: {np.shape(clusters)} labels for {n} residuals")
        labels, inverse = np.unique(np.asarray(clusters), return_inverse=True)
        n_clusters = labels.size
    if use.any():
        j = jac[:, use]
        norms = np.linalg.norm(j, axis=0)
        norms = np.where(norms > 0, norms, 1.0)
        jn = j / norms
        _, s, vt = np.linalg.svd(jn, full_matrices=False)
        cond = float(s[0] / s[-1]) if s[-1] > 0 else np.inf
        good = s > SINGULAR_RCOND * s[0]
        inv_s2 = np.where(good, 1.0 / np.where(good, s, 1.0) ** 2, 0.0)
        cov_n = (vt.T * inv_s2) @ vt  # covariance of the normalised parameters / sigma2
        cov = sigma2 * cov_n / np.outer(norms, norms)
        # a parameter loading on a direction J cannot see has no finite uncertainty
        blind = np.any(np.abs(vt[~good]) > 1e-3, axis=0) if (~good).any() else np.zeros(
            use.sum(), bool)
        std_white[use] = np.where(blind, np.inf, np.sqrt(np.maximum(np.diag(cov), 0.0)))
        if n_clusters and n_clusters >= MIN_CLUSTERS_PER_PARAMETER * int(use.sum()):
            # per cluster the score J_g^T r_g (normalised columns), summed outer products
            scores = np.zeros((n_clusters, jn.shape[1]))
            np.add.at(scores, inverse, jn * residual[:, None])
            # centred: at a least-squares optimum the scores sum to zero; a PSO answer
            # (fitted on a subset of windows) need not be one
            scores -= scores.mean(axis=0)
            meat = scores.T @ scores * n_clusters / (n_clusters - 1)
            cov = cov_n @ meat @ cov_n / np.outer(norms, norms)
            kind = "clustered"
        d = np.where(blind, np.inf, np.sqrt(np.maximum(np.diag(cov), 0.0)))
        std[use] = d
        with np.errstate(invalid="ignore", divide="ignore"):
            c = cov / np.outer(np.sqrt(np.diag(cov)), np.sqrt(np.diag(cov)))
        sub = np.ix_(use, use)
        corr[sub] = c
        used_names = [nm for nm, u in zip(names, use, strict=True) if u]
        for k in range(1, min(3, s.size) + 1):
            v = vt[-k]
            order = np.argsort(-np.abs(v))[:3]
            weak.append((float(s[-k] / s[0]), [(used_names[i], float(v[i])) for i in order]))
    return Uncertainty(std, corr, sigma2, cond, weak, kind, std_white, n_clusters)


def identifiability_notes(names, values, unc: Uncertainty, at_bound) -> tuple[list, np.ndarray]:
    """(human-readable notes, identifiable mask (p,))."""
    notes = []
    values = np.asarray(values, dtype=float)
    rel = np.abs(unc.std) / np.maximum(np.abs(values), 1e-12)
    ident = np.isfinite(unc.std) & (rel <= REL_STD_LIMIT) & ~np.asarray(at_bound, bool)
    for i, nm in enumerate(names):
        if at_bound[i]:
            notes.append(f"{nm}: at its bound ({values[i]:.6g}); uncertainty not defined")
        elif not np.isfinite(unc.std[i]):
            notes.append(f"{nm}: not identifiable from this flight (the residuals do not "
                         "depend on it, alone or in combination)")
        elif rel[i] > REL_STD_LIMIT:
            notes.append(f"{nm}: poorly identified, 1-sigma {unc.std[i]:.3g} = "
                         f"{100 * rel[i]:.0f} % of its value")
    p = len(names)
    for a in range(p):
        for b in range(a + 1, p):
            c = unc.correlation[a, b]
            if np.isfinite(c) and abs(c) > CORR_LIMIT:
                notes.append(f"{names[a]} and {names[b]} strongly correlated (rho = {c:+.3f}): "
                             "the flight constrains a combination of them")
    if unc.clusters and unc.kind == "white" and (~np.isnan(unc.std)).any():
        notes.append(f"only {unc.clusters} windows for {int((~np.isnan(unc.std)).sum())} "
                     "free parameters: the 1-sigma assume white residuals and are "
                     "optimistic (a longer flight or more windows give the windows' own)")
    if np.isfinite(unc.condition) and unc.condition > 1e4:
        notes.append(f"Jacobian condition number {unc.condition:.3g} (columns normalised)")
    for ratio, loads in unc.weak_directions[:1]:
        combo = " ".join(f"{v:+.2f}*{n}" for n, v in loads)
        notes.append(f"weakest direction (singular value {ratio:.2g} of the largest): {combo}")
    return notes, ident


@dataclass
class FitResult:
    """A calibration: the fitted model and everything the report prints."""

    method: str
    model: object  # the fitted HeliModel
    names: list  # free parameter names
    start: np.ndarray  # their starting values
    values: np.ndarray  # fitted values
    std: np.ndarray  # 1-sigma (NaN at bounds, inf unidentifiable)
    correlation: np.ndarray
    at_bound: np.ndarray
    identifiable: np.ndarray
    notes: list
    rms_before: np.ndarray  # (6,) per-channel RMS, channel units
    rms_after: np.ndarray
    noise_scale: np.ndarray  # (6,) the channel weights' denominators
    cost_history: list = field(default_factory=list)  # weighted RMS per iteration
    std_white: np.ndarray | None = None  # 1-sigma if the residuals were white (comparison)
    uncertainty_kind: str = "white"  # how `std` was computed: "clustered" or "white"
    evaluations: int = 0  # parameter-set evaluations over the scored windows
    seconds: float = 0.0
    info: dict = field(default_factory=dict)

    @property
    def white_std(self) -> np.ndarray:
        """The 1-sigma if the residuals were white (`std` when no other was computed)."""
        return self.std if self.std_white is None else self.std_white

    def to_dict(self) -> dict:
        from airwake.heli.context import MEAS_CHANNELS

        def num(v):
            v = float(v)
            return v if np.isfinite(v) else (None if np.isnan(v) else "inf")

        return {
            "method": self.method,
            "seconds": self.seconds,
            "evaluations": self.evaluations,
            "channels": list(MEAS_CHANNELS),
            "rms_before": [float(v) for v in self.rms_before],
            "rms_after": [float(v) for v in self.rms_after],
            "rms_before_all": float(np.sqrt(np.mean(self.rms_before**2))),
            "rms_after_all": float(np.sqrt(np.mean(self.rms_after**2))),
            "noise_scale": [float(v) for v in self.noise_scale],
            "uncertainty": self.uncertainty_kind,
            "parameters": {
                n: {"start": float(s), "value": float(v), "std": num(d),
                    "std_white": num(w), "at_bound": bool(b), "identifiable": bool(i)}
                for n, s, v, d, w, b, i in zip(
                    self.names, self.start, self.values, self.std, self.white_std,
                    self.at_bound, self.identifiable, strict=True)
            },
            "identifiability": list(self.notes),
            "cost_history": [float(c) for c in self.cost_history],
            **{k: v for k, v in self.info.items() if isinstance(v, (int, float, str, bool))},
            **({"rms_after_weighting_fit": self.info["rms_after_weighting_fit"]}
               if self.info.get("rms_after_weighting_fit") else {}),
        }
