"""From compensated samples to a gridded wind map (reference §3.4).

    wmap = build_windmap(samples)        # locations, their volume fits, the 5 cm grid

1. Locations: the samples are binned in cubes of `location_m`, and the cubes merged,
   most-filled first, into locations at least `location_m` apart; a location holding at
   least `min_seconds` of data is kept (the reference's stations), at its samples' mean
   position, with their mean flow (the measured mean flow there).
2. Volume fits: around each location, every sample within the volume
   `volume_m` = 1.3 x 1.3 x 0.6 m (centred there) fits eq 3.15 and eq 5.3
   (`linear_models`); the turbulence there is the norm of the per-component std of the
   samples after removing the eq 3.15 model (reference §3.4).
3. Grid: points every `grid_m` = 5 cm over the locations' bounding box, kept inside their
   convex hull. Each grid point g lies in one Delaunay tetrahedron of the locations, with
   barycentric weights b_k (linear interpolation, the 3-D form of the reference's
   bilinear one):

       measured  u(g)    = sum_k b_k ubar_k
       eq 3.15   u12(g)  = sum_k b_k d_k        (the steady-state mean-flow parameter)
       eq 5.3    u6(g)   = sum_k b_k v_k

   and the other parameters (A, omega, turbulence) interpolated the same way. (Carrying
   each volume's gradient to g, sum_k b_k (d_k + A_k (g - c_k)), was tried: on the
   two-fan survey it is further from both the measured flow and the field, the 1.3 m
   volumes' gradients being poor slopes of jets ~0.5 m wide.)
4. Model error (Fig 3.14B, "the interpolated steady-state flow parameters compared
   against the interpolated measured flow"): |u12(g) - u(g)| as a percentage of the
   source wind `source_speed_m_s` (the reference's 7.24 m/s at the fans), over the grid.
`sampled` marks the grid points whose 5 cm voxel holds at least one sample.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from airwake.windmap.compensate import CompensatedSamples
from airwake.windmap.errors import WindMapError
from airwake.windmap.linear_models import fit_linear12, fit_rotation6

VOLUME_M = (1.3, 1.3, 0.6)
GRID_M = 0.05
LOCATION_M = 0.2
MIN_SECONDS = 2.0
SOURCE_SPEED_M_S = 7.24
REFERENCE_ERROR_PCT = (3.0, 11.0)
MIN_VOLUME_SAMPLES = 50
FLOW = ("u_m_s", "v_m_s", "w_m_s")
GRADIENT = tuple(f"d{c}_d{x}_1_s" for c in "uvw" for x in "xyz")


@dataclass
class WindMap:
    """locations (DataFrame, one row per location: centre, samples, measured mean flow,
    eq 3.15 and eq 5.3 parameters, turbulence); grid (DataFrame, one row per 5 cm point:
    x/y/z_m (NED), measured flow, m12_*, m6_*, gradient, rotation, sigma, model error,
    sampled); settings; model_error (statistics); samples."""

    locations: object
    grid: object
    settings: dict
    model_error: dict
    samples: CompensatedSamples
    score: dict | None = field(default=None)


def _check_positive(name: str, values) -> None:
    for v in np.atleast_1d(np.asarray(values, float)):
        if not (np.isfinite(v) and v > 0):
            raise WindMapError(f"{name} {values!r}: must be positive numbers")


def find_locations(s: CompensatedSamples, location_m: float, min_seconds: float):
    """(centres (L, 3), mean flow (L, 3), samples (L,)): cubes of `location_m` merged,
    most-filled first, into the first location whose centre lies within `location_m`
    (a station whose sway straddles a cube face stays one location); locations holding
    >= min_seconds are kept."""
    idx = np.floor(s.pos / location_m).astype(np.int64)
    _, inverse, counts = np.unique(idx, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    k = counts.size
    n = counts.astype(float)
    centre = np.column_stack([np.bincount(inverse, s.pos[:, j], k) / n for j in range(3)])
    owner = np.full(k, -1)
    accepted: list[int] = []
    for c in np.argsort(-counts, kind="stable"):
        if accepted:
            d = np.linalg.norm(centre[accepted] - centre[c], axis=1)
            near = int(np.argmin(d))
            if d[near] <= location_m:
                owner[c] = accepted[near]
                continue
        owner[c] = c
        accepted.append(int(c))
    loc_of = owner[inverse]
    m = np.bincount(loc_of, minlength=k).astype(float)
    keep = m * s.dt >= min_seconds - 1e-9
    if not keep.any():
        raise WindMapError(f"no {location_m:g} m location holds {min_seconds:g} s of "
                           "anemometer data: dwell longer or lower --min-seconds")
    safe = np.maximum(m, 1.0)
    centre = np.column_stack([np.bincount(loc_of, s.pos[:, j], k) / safe for j in range(3)])
    flow = np.column_stack([np.bincount(loc_of, s.wind[:, j], k) / safe for j in range(3)])
    return centre[keep], flow[keep], m[keep].astype(np.int64)


def fit_volumes(s: CompensatedSamples, centres: np.ndarray, volume_m) -> dict:
    """Per location: eq 3.15 and eq 5.3 fits on the samples in the volume around it."""
    from scipy.spatial import cKDTree

    half = 0.5 * np.asarray(volume_m, float)
    scale = half[0] / half  # the box becomes a cube of half-side half[0] (Chebyshev ball)
    tree = cKDTree(s.pos * scale)
    groups = tree.query_ball_point(centres * scale, r=half[0], p=np.inf)
    out = {k: [] for k in ("d", "a", "rank12", "v", "omega", "rank6", "sigma", "n")}
    for c, members in zip(centres, groups, strict=True):
        members = np.asarray(members, dtype=np.int64)
        if members.size < MIN_VOLUME_SAMPLES:
            raise WindMapError(f"the volume at {np.round(c, 2).tolist()} holds only "
                               f"{members.size} samples")
        r = s.pos[members] - c
        u = s.wind[members]
        f12 = fit_linear12(r, u)
        f6 = fit_rotation6(r, u)
        res = u - f12(r)
        out["d"].append(f12.d)
        out["a"].append(f12.a)
        out["rank12"].append(f12.rank)
        out["v"].append(f6.v)
        out["omega"].append(f6.omega)
        out["rank6"].append(f6.rank)
        out["sigma"].append(float(np.linalg.norm(res.std(axis=0))))
        out["n"].append(members.size)
    return {k: np.asarray(v) for k, v in out.items()}


def _delaunay(points: np.ndarray):
    from scipy.spatial import Delaunay, QhullError

    try:
        return Delaunay(points)
    except QhullError:
        try:  # a regular lattice of stations is degenerate: joggle it
            return Delaunay(points, qhull_options="QJ")
        except QhullError as exc:
            raise WindMapError(f"the {len(points)} locations do not span a volume (all on "
                               f"a plane or a line?): {str(exc).splitlines()[0]}") from None


def barycentric(tri, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(inside (m,), vertex indexes (m_in, 4), weights (m_in, 4)) of `points` (m, 3)."""
    simplex = tri.find_simplex(points)
    inside = simplex >= 0
    s = simplex[inside]
    tr = tri.transform[s]
    b3 = np.einsum("nij,nj->ni", tr[:, :3, :], points[inside] - tr[:, 3, :])
    w = np.column_stack([b3, 1.0 - b3.sum(axis=1)])
    return inside, tri.simplices[s], w


def sampled_mask(grid_pts: np.ndarray, pos: np.ndarray, grid_m: float, origin) -> np.ndarray:
    """(m,) True where the grid point's voxel (side grid_m, centred on it) holds a sample."""
    def key(ijk):
        return (ijk[:, 0] * 1_000_003 + ijk[:, 1]) * 1_000_003 + ijk[:, 2]

    vs = np.unique(key(np.rint((pos - origin) / grid_m).astype(np.int64)))
    return np.isin(key(np.rint((grid_pts - origin) / grid_m).astype(np.int64)), vs)


def error_statistics(err_pct: np.ndarray) -> dict:
    """Summary of model errors in % (Fig 3.14B)."""
    e = err_pct[np.isfinite(err_pct)]
    lo, hi = REFERENCE_ERROR_PCT
    q = np.percentile(e, [5, 25, 50, 75, 95]) if e.size else [np.nan] * 5
    return {"points": int(e.size), "mean_pct": float(e.mean()) if e.size else np.nan,
            "p5_pct": float(q[0]), "p25_pct": float(q[1]), "median_pct": float(q[2]),
            "p75_pct": float(q[3]), "p95_pct": float(q[4]),
            "fraction_below_3_pct": float(np.mean(e < lo)) if e.size else np.nan,
            "fraction_3_to_11_pct": float(np.mean((e >= lo) & (e <= hi))) if e.size
            else np.nan,
            "fraction_below_11_pct": float(np.mean(e <= hi)) if e.size else np.nan}


def build_windmap(s: CompensatedSamples, *, volume_m=VOLUME_M, grid_m: float = GRID_M,
                  location_m: float = LOCATION_M, min_seconds: float = MIN_SECONDS,
                  source_speed_m_s: float = SOURCE_SPEED_M_S) -> WindMap:
    """Samples -> locations -> volume fits -> grid (module docstring)."""
    import pandas as pd

    _check_positive("--volume-m", volume_m)
    if np.size(volume_m) != 3:
        raise WindMapError(f"--volume-m {volume_m!r}: expected three sizes X,Y,Z")
    _check_positive("--grid-m", grid_m)
    _check_positive("--location-m", location_m)
    _check_positive("--source-speed-m-s", source_speed_m_s)
    if not (np.isfinite(min_seconds) and min_seconds >= 0):
        raise WindMapError(f"--min-seconds {min_seconds!r}: must be >= 0")
    centres, flow, counts = find_locations(s, location_m, min_seconds)
    if len(centres) < 5:
        raise WindMapError(f"only {len(centres)} location(s) hold {min_seconds:g} s of data: "
                           "a map needs at least 5 spanning a volume")
    fits = fit_volumes(s, centres, volume_m)
    loc = pd.DataFrame({"x_m": centres[:, 0], "y_m": centres[:, 1], "z_m": centres[:, 2],
                        "samples": counts, "seconds": counts * s.dt,
                        "volume_samples": fits["n"]})
    for j, n in enumerate(FLOW):
        loc[n] = flow[:, j]
        loc[f"m12_{n}"] = fits["d"][:, j]
        loc[f"m6_{n}"] = fits["v"][:, j]
    a = fits["a"].reshape(-1, 9)
    for j, n in enumerate(GRADIENT):
        loc[n] = a[:, j]
    for j, n in enumerate(("wx_rad_s", "wy_rad_s", "wz_rad_s")):
        loc[n] = fits["omega"][:, j]
    loc["rank12"] = fits["rank12"]
    loc["rank6"] = fits["rank6"]
    loc["sigma_m_s"] = fits["sigma"]

    tri = _delaunay(centres)
    lo, hi = centres.min(0), centres.max(0)
    axes = [lo[j] + grid_m * np.arange(int(np.floor((hi[j] - lo[j]) / grid_m + 1e-9)) + 1)
            for j in range(3)]
    gx, gy, gz = np.meshgrid(*axes, indexing="ij")
    pts = np.column_stack([gx.ravel(), gy.ravel(), gz.ravel()])
    inside, verts, w = barycentric(tri, pts)
    g = pts[inside]
    if len(g) == 0:
        raise WindMapError("no grid point lies inside the locations' hull")
    meas = np.einsum("mk,mkj->mj", w, flow[verts])
    m12 = np.einsum("mk,mkj->mj", w, fits["d"][verts])
    m6 = np.einsum("mk,mkj->mj", w, fits["v"][verts])
    grid = pd.DataFrame({"x_m": g[:, 0], "y_m": g[:, 1], "z_m": g[:, 2]})
    for j, n in enumerate(FLOW):
        grid[n] = meas[:, j]
        grid[f"m12_{n}"] = m12[:, j]
        grid[f"m6_{n}"] = m6[:, j]
    a_g = np.einsum("mk,mkj->mj", w, a[verts])
    for j, n in enumerate(GRADIENT):
        grid[n] = a_g[:, j]
    om = np.einsum("mk,mkj->mj", w, fits["omega"][verts])
    for j, n in enumerate(("wx_rad_s", "wy_rad_s", "wz_rad_s")):
        grid[n] = om[:, j]
    grid["sigma_m_s"] = np.einsum("mk,mk->m", w, fits["sigma"][verts])
    grid["speed_m_s"] = np.linalg.norm(meas, axis=1)
    # model error as a percentage of the source wind                        (Fig 3.14B)
    err12 = 100.0 * np.linalg.norm(m12 - meas, axis=1) / source_speed_m_s
    err6 = 100.0 * np.linalg.norm(m6 - meas, axis=1) / source_speed_m_s
    grid["m12_error_pct"] = err12
    grid["m6_error_pct"] = err6
    grid["sampled"] = sampled_mask(g, s.pos, grid_m, lo)
    for c in grid.columns:
        if grid[c].dtype == np.float64 and c not in ("x_m", "y_m", "z_m"):
            grid[c] = grid[c].astype(np.float32)
    settings = {"frame": "site (NED)", "pose": s.pose, "lever_arm_m": s.lever_arm_m.tolist(),
                "mount_quat_wxyz": (None if s.mount_quat_wxyz is None
                                    else s.mount_quat_wxyz.tolist()),
                "volume_m": [float(v) for v in np.asarray(volume_m, float)],
                "grid_m": float(grid_m), "location_m": float(location_m),
                "min_seconds": float(min_seconds), "source_speed_m_s": float(source_speed_m_s),
                "samples": int(s.t.size), "sample_rate_hz": 1.0 / s.dt if s.dt > 0 else None}
    model_error = {"eq_3_15": error_statistics(err12), "eq_5_3": error_statistics(err6),
                   "reference_pct": list(REFERENCE_ERROR_PCT)}
    return WindMap(loc, grid, settings, model_error, s)
