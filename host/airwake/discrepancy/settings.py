"""Analysis settings shared by every step (compare, where, diagnose, add, report).

The same two choices are applied everywhere, so numbers from different steps agree:

- **start-up transient**: the first `skip_start_s` of every continuous run of samples is
  left out of every statistic (the rotor's reconstructed hidden states start
  quasi-steady and settle within ~0.3 s; after a gap in time they restart);
- **analysis band**: residuals (and any regressor compared with them) are low-pass
  filtered with a zero-phase Butterworth filter (order `filter_order`, run forward and
  backward with `scipy.signal.sosfiltfilt`: no delay, gain 0.5 (-6 dB) at `lowpass_hz`,
  8th-order roll-off above). This removes rotor vibration (1/rev ~26 Hz, 2/rev ~52 Hz)
  and most sensor noise while keeping the rigid-body dynamics (< ~5 Hz). `lowpass_hz =
  0` switches it off. `edge_s` more seconds at both ends of every run are left out
  (filter edge transients).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from airwake.discrepancy.errors import DiscrepancyError


@dataclass(frozen=True)
class AnalysisSettings:
    skip_start_s: float = 0.5  # start-up transient left out at the start of every run
    lowpass_hz: float = 12.0  # analysis band (zero-phase low-pass); 0 = no filter
    filter_order: int = 4
    edge_s: float = 0.1  # left out at both ends of every run (filter edges)
    n_blocks: int = 10  # contiguous time blocks for cross-validation / significance
    alpha: float = 0.01  # family-wise significance level (Bonferroni over candidates)
    min_explained: float = 0.05  # practical effect size: CV share of residual variance
    min_noise_ratio: float = 0.5  # ... and an explained RMS >= this x noise floor somewhere
    free_sim_window_s: float = 1.5  # open-loop simulation windows (compare)
    free_sim_windows: int = 12  # at most this many windows, spread over the flight
    free_sim_substeps: int = 4  # RK4 steps per sample interval

    def __post_init__(self) -> None:
        checks = {
            "skip_start_s": self.skip_start_s >= 0,
            "lowpass_hz": self.lowpass_hz >= 0,
            "filter_order": 1 <= self.filter_order <= 10,
            "edge_s": self.edge_s >= 0,
            "n_blocks": 3 <= self.n_blocks <= 100,
            "alpha": 0 < self.alpha < 1,
            "min_explained": 0 <= self.min_explained < 1,
            "min_noise_ratio": self.min_noise_ratio >= 0,
            "free_sim_window_s": self.free_sim_window_s > 0,
            "free_sim_windows": self.free_sim_windows >= 0,
            "free_sim_substeps": 1 <= self.free_sim_substeps <= 50,
        }
        for name, ok in checks.items():
            if not ok:
                raise DiscrepancyError(
                    f"analysis setting {name} = {getattr(self, name)!r} is out of range")

    def as_dict(self) -> dict:
        return asdict(self)
