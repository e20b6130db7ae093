"""Compiled (numba) effect stages: the `@kernel` decorator and row helpers for kernels.

A *kernel stage* is an effect's stage written for ONE row, compiled with numba:

    @register_effect("ground_effect")
    class GroundEffect(Effect):
        PARAMETERS = (Parameter("strength", 1.0, "-", (0.0, 3.0), "Cheeseman-Bennett"),)

        @kernel
        def inflow(q, p, s, ds, load, scratch):
            z = q[Q.height_agl_m] / ...
            q[Q.inflow_0] *= 1.0 - p.strength * ...

Arguments (the model passes them; a stage uses what it needs):
    q        (K,) this row's context: shared quantities at the slots of `layout.Q`
             (vectors at consecutive slots: q[Q.vel_b_m_s + 2] is w)
    p        the effect's parameters, a namedtuple of floats: p.strength
    s, ds    (k,) the effect's own states (read) and their derivatives (write)
    load     (6,) the effect's force (0:3) and moment about the CG (3:6), body axes;
             accumulate with +=; class attribute LOAD_SENSED = False for field forces
    scratch  (SCRATCH,) private per-row storage kept between this effect's stages

Kernels are compiled without fastmath and with numpy's error model (x/0 -> inf/nan, as
the numpy effects behave), cached on disk, and called from one generated function per
effect composition (the package's code generator, `airwake.heli.codegen`), so a
single-row evaluation is one compiled call. Helpers a kernel calls must be
`@kernel_function`s (module level; inlined into the kernel). Use math.* / np.* on
scalars, no allocation.
"""

from __future__ import annotations

import numba
import numpy as np

from airwake.heli.codegen.jit import JIT_OPTIONS, disk_cached, is_kernel, mark_kernel
from airwake.heli.layout import Q


def kernel_function(fn):
    """Compile a module-level helper for kernels (inlined into its callers)."""
    return numba.njit(inline="always", **JIT_OPTIONS)(fn)


def kernel(fn):
    """Mark an effect's stage method as a compiled kernel (see the module docstring).
    Compiled once per process on first use and cached on disk, except for effects defined
    inside a function (their parameter type cannot be pickled)."""
    on_disk = "<locals>" not in fn.__qualname__
    disp = numba.njit(cache=on_disk, **JIT_OPTIONS)(disk_cached(fn))
    return staticmethod(mark_kernel(disp))


@kernel_function
def cross(ax, ay, az, bx, by, bz):
    """a x b for scalars."""
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@kernel_function
def air_velocity_at(q, rx, ry, rz):
    """Air velocity relative to the body point r (body axes, from the CG): the eq 5.3 wind
    at r minus the point's velocity v_H + omega_H x r. Returns (vx, vy, vz)."""
    ox = rx - q[Q.wind_origin_m]
    oy = ry - q[Q.wind_origin_m + 1]
    oz = rz - q[Q.wind_origin_m + 2]
    wx, wy, wz = cross(q[Q.wind_w_rad_s], q[Q.wind_w_rad_s + 1], q[Q.wind_w_rad_s + 2],
                       ox, oy, oz)
    px, py, pz = cross(q[Q.omega_b_rad_s], q[Q.omega_b_rad_s + 1], q[Q.omega_b_rad_s + 2],
                       rx, ry, rz)
    return (
        (q[Q.wind_v_m_s] + wx) - (q[Q.vel_b_m_s] + px),
        (q[Q.wind_v_m_s + 1] + wy) - (q[Q.vel_b_m_s + 1] + py),
        (q[Q.wind_v_m_s + 2] + wz) - (q[Q.vel_b_m_s + 2] + pz),
    )


@kernel_function
def add_load(load, fx, fy, fz, mx, my, mz):
    load[0] += fx
    load[1] += fy
    load[2] += fz
    load[3] += mx
    load[4] += my
    load[5] += mz


@kernel_function
def solve3(m00, m01, m02, m10, m11, m12, m20, m21, m22, r0, r1, r2):
    """Solve a 3x3 system by Cramer's rule (as the numpy `solve3`)."""
    a, b, c = m00, m01, m02
    d, e, f = m10, m11, m12
    g, h, i = m20, m21, m22
    co0 = e * i - f * h
    co1 = f * g - d * i
    co2 = d * h - e * g
    det = a * co0 + b * co1 + c * co2
    y0 = r0 * co0 + b * (f * r2 - r1 * i) + c * (r1 * h - e * r2)
    y1 = a * (r1 * i - f * r2) + r0 * co1 + c * (d * r2 - r1 * g)
    y2 = a * (e * r2 - r1 * h) + b * (r1 * g - d * r2) + r0 * co2
    inv = 1.0 / det
    return y0 * inv, y1 * inv, y2 * inv


__all__ = ["Q", "add_load", "air_velocity_at", "cross", "is_kernel", "kernel",
           "kernel_function", "np", "solve3"]
