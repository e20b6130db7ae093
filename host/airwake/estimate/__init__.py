"""Wind estimation from the helicopter's dynamics: the active particle filter of
reference §5.4 (eq 5.17) over the 6-D eq 5.3 wind (docs/wind-estimation.md).

    from airwake.estimate import estimate_wind, score_wind, write_wind
    est = estimate_wind("flight.parquet", model="fitted.toml", n_particles=2000, seed=0)
    write_wind(est, "wind.parquet")

Pieces: `resample` (pure resamplers (weights, rng) -> indexes), `wind_model` (the
state-space model: wind random walk + helicopter measurement model with per-particle
rotor states), `particle_filter` (the algorithm), `wind` (flight in, table out, score).
The names below are imported on first use (`airwake.lazy`): `airwake --help` imports
this package and must not pay for scipy and numba.
"""

from airwake.lazy import lazy_exports

__all__ = ["TABLE_5_3", "WindEstimationError", "estimate_wind", "score_wind", "write_wind"]
__getattr__, __dir__ = lazy_exports(__name__, {
    "WindEstimationError": "airwake.estimate.errors",
    **dict.fromkeys(["TABLE_5_3", "estimate_wind", "score_wind", "write_wind"],
                    "airwake.estimate.wind"),
})
