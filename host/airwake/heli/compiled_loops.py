"""Compiled loops over rows and time, one copy per effect composition.

These functions are *templates*: `airwake.heli.codegen` copies their source into each
generated composition module, where the global `row` is that composition's fused
single-row evaluation

    row(q, x, xdot, meas, loads, scratch, u, w, height_agl_m, rotor_speed_rad_s, params,
        has_load, sensed)

and N_SLOTS, N_LOADS, N_SCRATCH, N_STATES, N_HIDDEN, HIDDEN (indices of the hidden
states), HAS, SENSED are that composition's constants. They are compiled there with
`numba.njit(cache=True)`, so each composition gets its own cached machine code. Do not
call them from here.

Broadcast convention: an input array with a leading row axis is read at row `i * stride`
with stride 1 (one entry per row) or 0 (one entry for all rows).
"""

# ruff: noqa: F821  (row, N_SLOTS, … are globals of the generated module)

import numpy as np


def evaluate_rows(n, c, cs, x, xs, xdot, meas, loads, scratch, u, us, w, ws, hagl, hs,
                  omm, oms, params, ps):
    """n rows; c/loads/scratch (1 or n, …) with stride cs (0: reuse one row)."""
    for i in range(n):
        row(c[i * cs], x[i * xs], xdot[i], meas[i], loads[i * cs], scratch[i * cs],
            u[i * us], w[i * ws], hagl[i * hs], omm[i * oms], params[i * ps], HAS, SENSED)


def rk4_one(xi, ui, wi, hi, oi, pi, dt, out, work):
    """Classical RK4 step of one row with inputs held over the step, into out (S,)."""
    q, ld, sc, mr, k1, k2, k3, k4, xt = work
    row(q, xi, k1, mr, ld, sc, ui, wi, hi, oi, pi, HAS, SENSED)
    for j in range(N_STATES):
        xt[j] = xi[j] + 0.5 * dt * k1[j]
    row(q, xt, k2, mr, ld, sc, ui, wi, hi, oi, pi, HAS, SENSED)
    for j in range(N_STATES):
        xt[j] = xi[j] + 0.5 * dt * k2[j]
    row(q, xt, k3, mr, ld, sc, ui, wi, hi, oi, pi, HAS, SENSED)
    for j in range(N_STATES):
        xt[j] = xi[j] + dt * k3[j]
    row(q, xt, k4, mr, ld, sc, ui, wi, hi, oi, pi, HAS, SENSED)
    for j in range(N_STATES):
        out[j] = xi[j] + (dt / 6.0) * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])


def work_arrays():
    """Per-call buffers of one row: context, loads, scratch, measurement, RK4 stages."""
    return (np.empty(N_SLOTS), np.empty((N_LOADS, 6)), np.empty(N_SCRATCH), np.empty(6),
            np.empty(N_STATES), np.empty(N_STATES), np.empty(N_STATES), np.empty(N_STATES),
            np.empty(N_STATES))


def rk4_rows(n, x, xs, u, us, w, ws, hagl, hs, omm, oms, params, ps, dt, out):
    """One RK4 step for each of n rows: out (n, S)."""
    work = work_arrays()
    for i in range(n):
        rk4_one(x[i * xs], u[i * us], w[i * ws], hagl[i * hs], omm[i * oms], params[i * ps],
                dt, out[i], work)


def simulate_rows(n, x0, xs, steps, dt, every, u, ut, us, w, wt, ws, hagl, ht, hs, omm, ot,
                  oms, params, ps, xout):
    """Integrate n rows over `steps` RK4 steps; inputs sampled per step: u (T, R, 4) read
    at [k * ut, i * us] (ut, us in {0, 1}), likewise w (T, R, 6), hagl and omm (T, R).
    Keeps every `every`-th state (step 0 included) in xout (steps // every + 1, n, S)."""
    work = work_arrays()
    xi = np.empty(N_STATES)
    xn = np.empty(N_STATES)
    for i in range(n):
        xi[:] = x0[i * xs]
        for k in range(steps + 1):
            if k % every == 0:
                xout[k // every, i] = xi
            if k == steps:
                break
            rk4_one(xi, u[k * ut, i * us], w[k * wt, i * ws], hagl[k * ht, i * hs],
                    omm[k * ot, i * oms], params[i * ps], dt, xn, work)
            xi[:] = xn
