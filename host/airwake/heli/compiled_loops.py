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

# ruff: noqa: F821  (row, unmanaged, N_SLOTS, … are globals of the generated module)

import numpy as np


def evaluate_rows(n, c, cs, x, xs, xdot, meas, loads, scratch, u, us, w, ws, hagl, hs,
                  omm, oms, params, ps):
    """n rows; c/loads/scratch (1 or n, …) with stride cs (0: reuse one row)."""
    c, x, xdot, meas, loads, scratch = (unmanaged(c), unmanaged(x), unmanaged(xdot),
                                        unmanaged(meas), unmanaged(loads), unmanaged(scratch))
    u, w, params = unmanaged(u), unmanaged(w), unmanaged(params)
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
    x, u, w, params, out = unmanaged(x), unmanaged(u), unmanaged(w), unmanaged(params), \
        unmanaged(out)
    work = work_arrays()
    for i in range(n):
        rk4_one(x[i * xs], u[i * us], w[i * ws], hagl[i * hs], omm[i * oms], params[i * ps],
                dt, out[i], work)


def simulate_rows(n, x0, xs, steps, dt, every, u, ut, us, w, wt, ws, hagl, ht, hs, omm, ot,
                  oms, params, ps, xout):
    """Integrate n rows over `steps` RK4 steps; inputs sampled per step: u (T, R, 4) read
    at [k * ut, i * us] (ut, us in {0, 1}), likewise w (T, R, 6), hagl and omm (T, R).
    Keeps every `every`-th state (step 0 included) in xout (steps // every + 1, n, S)."""
    x0, u, w, params, xout = unmanaged(x0), unmanaged(u), unmanaged(w), unmanaged(params), \
        unmanaged(xout)
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


def foh_weights(lam, dt):
    """exp(lam dt) and the first-order-hold input weights phi1, phi2 of one mode:
    z(dt) = e z(0) + phi1 b(0) + phi2 (b(dt) - b(0)) solves z' = lam z + b, b linear."""
    x = lam * dt
    ea = np.exp(x)
    if abs(x) < 0.1:  # series: the closed forms cancel badly for small lam dt
        phi1 = dt * (1.0 + x * (1.0 / 2 + x * (1.0 / 6 + x * (1.0 / 24 + x * (
            1.0 / 120 + x * (1.0 / 720 + x * (1.0 / 5040 + x / 40320)))))))
        phi2 = dt * (1.0 / 2 + x * (1.0 / 6 + x * (1.0 / 24 + x * (1.0 / 120 + x * (
            1.0 / 720 + x * (1.0 / 5040 + x * (1.0 / 40320 + x / 362880)))))))
    else:
        em1 = ea - 1.0
        phi1 = dt * em1 / x
        phi2 = dt * (em1 - x) / (x * x)
    return ea, phi1, phi2


def hidden_rates(i, h, xr, x, u, w, ws, hagl, hs, omm, oms, pk, a0, vinv, g, b, mr, work):
    """f_h at sample i with hidden states h: g = f_h - A0 h, b = V^-1 g; measurement mr."""
    q, ld, sc, _m, xd = work[0], work[1], work[2], work[3], work[4]
    m = h.shape[0]
    xr[:] = x[i]
    for j in range(m):
        xr[HIDDEN[j]] = h[j]
    row(q, xr, xd, mr, ld, sc, u[i], w[i * ws], hagl[i * hs], omm[i * oms], pk, HAS, SENSED)
    for j in range(m):
        acc = xd[HIDDEN[j]]
        for l in range(m):
            acc -= a0[j, l] * h[l]
        g[j] = acc
    for j in range(m):
        acc = 0.0 + 0.0j
        for l in range(m):
            acc += vinv[j, l] * g[l]
        b[j] = acc


def hidden_pass(nk, nt, t, x, u, w, ws, hagl, hs, omm, oms, params, ps, lam, vec, vinv, a0,
                h0, scale, tol, max_iter, hout, mout, stats):
    """Hidden states of nk parameter sets along a flight, sample by sample.

    Between samples the hidden dynamics h' = A0 h + g(t) are integrated exactly in the
    eigenbasis of A0 = V diag(lam) V^-1 with g = f_h - A0 h linear over the step (first-
    order hold); g at the new sample depends on the new h, so each step is solved by
    fixed-point iteration (contraction |Phi2 (J - A0)| << 1), started from g extrapolated
    linearly. Converged when the hidden state moves less than tol * scale; the accepted
    h is the one evaluated last (its measurement goes to mout). stats[k] = (largest
    number of iterations, largest final relative change)."""
    m = N_HIDDEN
    x, u, w, params = unmanaged(x), unmanaged(u), unmanaged(w), unmanaged(params)
    work = work_arrays()
    xr = np.empty(N_STATES)
    g = np.empty(m)
    b = np.empty(m, dtype=np.complex128)
    bn = np.empty(m, dtype=np.complex128)
    bprev = np.empty(m, dtype=np.complex128)
    z = np.empty(m, dtype=np.complex128)
    base = np.empty(m, dtype=np.complex128)
    ea = np.empty(m, dtype=np.complex128)
    p1 = np.empty(m, dtype=np.complex128)
    p2 = np.empty(m, dtype=np.complex128)
    hc = np.empty(m)
    hn = np.empty(m)
    mr = np.empty(6)
    for kk in range(nk):
        pk = params[kk * ps]
        lk, vk, vik, ak = lam[kk], vec[kk], vinv[kk], a0[kk]
        worst_it = 0
        worst_change = 0.0
        for j in range(m):
            hc[j] = h0[kk, j]
        hidden_rates(0, hc, xr, x, u, w, ws, hagl, hs, omm, oms, pk, ak, vik, g, b, mr, work)
        for j in range(m):
            acc = 0.0 + 0.0j
            for l in range(m):
                acc += vik[j, l] * hc[l]
            z[j] = acc
            bprev[j] = b[j]
            hout[kk, 0, j] = hc[j]
        mout[kk, 0, :] = mr
        last_dt = -1.0
        for k in range(nt - 1):
            dt = t[k + 1] - t[k]
            if dt != last_dt:
                for j in range(m):
                    ea[j], p1[j], p2[j] = foh_weights(lk[j], dt)
                last_dt = dt
            for j in range(m):
                base[j] = ea[j] * z[j] + p1[j] * b[j] - p2[j] * b[j]
                bn[j] = 2.0 * b[j] - bprev[j]  # predictor: g extrapolated
            change = np.inf
            it = 0
            while it < max_iter:
                it += 1
                for j in range(m):
                    acc = 0.0
                    for l in range(m):
                        acc += (vk[j, l] * (base[l] + p2[l] * bn[l])).real
                    hn[j] = acc
                if it > 1:
                    change = 0.0
                    for j in range(m):
                        d = abs(hn[j] - hc[j]) / scale[kk, j]
                        if d > change:
                            change = d
                    if change < tol:
                        break
                for j in range(m):
                    hc[j] = hn[j]
                hidden_rates(k + 1, hc, xr, x, u, w, ws, hagl, hs, omm, oms, pk, ak, vik, g,
                             bn, mr, work)
            # accept the last evaluated state hc (rates bn, measurement mr)
            for j in range(m):
                z[j] = base[j] + p2[j] * bn[j]
                bprev[j] = b[j]
                b[j] = bn[j]
                hout[kk, k + 1, j] = hc[j]
            mout[kk, k + 1, :] = mr
            if it > worst_it:
                worst_it = it
            if change > worst_change:
                worst_change = change
        stats[kk, 0] = worst_it
        stats[kk, 1] = worst_change
