"""Small helpers the catalogue effects share (numpy stages on a batched context)."""

from __future__ import annotations

import numpy as np


def vec3(x, y, z) -> np.ndarray:
    """Three parameters (floats or (N,) arrays) -> (N or 1, 3)."""
    return np.stack(np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float),
                                        np.asarray(z, float)), -1).reshape(-1, 3)


def cross(a, b) -> np.ndarray:
    """a x b for (..., 3) arrays."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], -1)


def rotor_radius(ctx) -> np.ndarray | float:
    """Main-rotor radius R of the evaluated model (tip speed / rotor speed, or the spec)."""
    tip = getattr(ctx, "tip_speed_m_s", None)
    if tip is not None:
        om = np.asarray(ctx.rotor_speed_rad_s, float)
        return np.asarray(tip, float) / np.where(om != 0.0, om, 1.0)
    return float(ctx.model["main_rotor"].parameters()["radius_m"])


def inertia(ctx) -> tuple:
    """(I_xx, I_yy, I_zz, I_xz), each a float or (N,) array."""
    i = ctx.inertia
    if isinstance(i, tuple | list):
        return tuple(i)
    arr = np.asarray(i, float)
    if arr.ndim == 2:
        return tuple(arr[:, k] for k in range(4))
    return tuple(arr[k] for k in range(4))


def smooth_fade(x, x0, x1) -> np.ndarray:
    """1 for x <= x0, 0 for x >= x1, cubic (C1) in between; arrays broadcast."""
    x0 = np.asarray(x0, float)
    x1 = np.asarray(x1, float)
    width = np.maximum(x1 - x0, 1e-9)
    s = np.clip((np.asarray(x, float) - x0) / width, 0.0, 1.0)
    return 1.0 - s * s * (3.0 - 2.0 * s)


def finite_height(ctx) -> np.ndarray:
    """Hub height above ground, with unknown (+inf) heights mapped to 1e9 m."""
    z = np.asarray(ctx.height_agl_m, float)
    return np.where(np.isfinite(z), z, 1e9)


def stash(ctx, key: str, value) -> None:
    """Keep a per-evaluation array between an effect's stages."""
    cache = getattr(ctx, "_cache", None)
    if isinstance(cache, dict):
        cache[key] = value
    else:
        object.__setattr__(ctx, "_airwake_" + key.replace(".", "_"), value)


def fetch(ctx, key: str):
    cache = getattr(ctx, "_cache", None)
    if isinstance(cache, dict):
        return cache[key]
    return object.__getattribute__(ctx, "_airwake_" + key.replace(".", "_"))
