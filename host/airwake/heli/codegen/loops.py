"""Compiled loops over rows and time, compiled once for every effect composition.

A composition is one C-callable function (`compose.py`), its single-row evaluation

    row(q, x, xdot, meas, loads, scratch, u, w, height_agl_m, rotor_speed_rad_s, params)

with pointer arguments (the context (N_SLOTS,), states and their rates (S,), measurement
(6,), loads (E, 6), scratch, inputs (4,), hub wind (6,), the parameters) and the two
environment floats. The loops here take its address as their first argument and call
through it (`jit.call_row_at`), so they type and compile once per machine, not once per
composition (the hidden-state pass alone took ~10 s to compile for each composition, the
batch and RK4 loops a few seconds). `dims` = (S, E, scratch size) sizes the work arrays;
`hidden` indexes the hidden states in x.

Broadcast convention: an input array with a leading row axis is read at row `i * stride`
with stride 1 (one entry per row) or 0 (one entry for all rows).
"""

import numba
import numpy as np

from airwake.heli.codegen.jit import JIT_OPTIONS, call_row_at, disk_cached, unmanaged
from airwake.heli.layout import N_SLOTS


def _compiled(fn):
    # cached under the heli fingerprint (cache.KernelCacheLocator): they read the layout
    return numba.njit(cache=True, **JIT_OPTIONS)(disk_cached(fn))


def _inlined(fn):
    return numba.njit(inline="always", **JIT_OPTIONS)(fn)


@_inlined
def call_row(row, q, x, xdot, meas, loads, scratch, u, w, hagl, omm, params):
    """One evaluation of the composition's row (`row`: its address)."""
    call_row_at(row, q, x, xdot, meas, loads, scratch, u, w, hagl, omm, params)


@_compiled
def evaluate_rows(row, n, c, cs, x, xs, xdot, meas, loads, scratch, u, us, w, ws, hagl, hs,
                  omm, oms, params, ps):
    """n rows; c/loads/scratch (1 or n, …) with stride cs (0: reuse one row)."""
    c, x, xdot, meas, loads, scratch = (unmanaged(c), unmanaged(x), unmanaged(xdot),
                                        unmanaged(meas), unmanaged(loads), unmanaged(scratch))
    u, w, params = unmanaged(u), unmanaged(w), unmanaged(params)
    for i in range(n):
        call_row(row, c[i * cs], x[i * xs], xdot[i], meas[i], loads[i * cs], scratch[i * cs],
                 u[i * us], w[i * ws], hagl[i * hs], omm[i * oms], params[i * ps])


@_inlined
def work_arrays(dims):
    """Per-call buffers of one row: context, loads, scratch, measurement, RK4 stages."""
    s = dims[0]
    return (np.empty(N_SLOTS), np.empty((dims[1], 6)), np.empty(dims[2]), np.empty(6),
            np.empty(s), np.empty(s), np.empty(s), np.empty(s), np.empty(s))


@_inlined
def rk4_one(row, xi, ui, wi, hi, oi, pi, dt, out, work):
    """Classical RK4 step of one row with inputs held over the step, into out (S,)."""
    q, ld, sc, mr, k1, k2, k3, k4, xt = work
    s = xi.shape[0]
    call_row(row, q, xi, k1, mr, ld, sc, ui, wi, hi, oi, pi)
    for j in range(s):
        xt[j] = xi[j] + 0.5 * dt * k1[j]
    call_row(row, q, xt, k2, mr, ld, sc, ui, wi, hi, oi, pi)
    for j in range(s):
        xt[j] = xi[j] + 0.5 * dt * k2[j]
    call_row(row, q, xt, k3, mr, ld, sc, ui, wi, hi, oi, pi)
    for j in range(s):
        xt[j] = xi[j] + dt * k3[j]
    call_row(row, q, xt, k4, mr, ld, sc, ui, wi, hi, oi, pi)
    for j in range(s):
        out[j] = xi[j] + (dt / 6.0) * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])


@_compiled
def rk4_rows(row, dims, n, x, xs, u, us, w, ws, hagl, hs, omm, oms, params, ps, dt, out):
    """One RK4 step for each of n rows: out (n, S)."""
    x, u, w, params, out = unmanaged(x), unmanaged(u), unmanaged(w), unmanaged(params), \
        unmanaged(out)
    work = work_arrays(dims)
    for i in range(n):
        rk4_one(row, x[i * xs], u[i * us], w[i * ws], hagl[i * hs], omm[i * oms],
                params[i * ps], dt, out[i], work)


@_compiled
def simulate_rows(row, dims, n, x0, xs, steps, dt, every, u, ut, us, w, wt, ws, hagl, ht, hs,
                  omm, ot, oms, params, ps, xout):
    """Integrate n rows over `steps` RK4 steps; inputs sampled per step: u (T, R, 4) read
    at [k * ut, i * us] (ut, us in {0, 1}), likewise w (T, R, 6), hagl and omm (T, R).
    Keeps every `every`-th state (step 0 included) in xout (steps // every + 1, n, S)."""
    x0, u, w, params, xout = unmanaged(x0), unmanaged(u), unmanaged(w), unmanaged(params), \
        unmanaged(xout)
    work = work_arrays(dims)
    xi = np.empty(dims[0])
    xn = np.empty(dims[0])
    for i in range(n):
        xi[:] = x0[i * xs]
        for k in range(steps + 1):
            if k % every == 0:
                xout[k // every, i] = xi
            if k == steps:
                break
            rk4_one(row, xi, u[k * ut, i * us], w[k * wt, i * ws], hagl[k * ht, i * hs],
                    omm[k * ot, i * oms], params[i * ps], dt, xn, work)
            xi[:] = xn


@_inlined
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


@_inlined
def matvec_add(out, a_t, v):
    """out += A v with A given transposed (a_t = A.T): the inner loop runs over the
    independent outputs, so it vectorises without reordering any sum."""
    m = v.shape[0]
    for l in range(m):
        vl = v[l]
        for j in range(m):
            out[j] += a_t[l, j] * vl


@_inlined
def hidden_rates(row, hidden, i, h, xr, x, u, w, ws, hagl, hs, omm, oms, pk, a0_t, g, mr,
                 work):
    """g = f_h - A0 h at sample i with hidden states h; measurement into mr."""
    q, ld, sc, xd = work[0], work[1], work[2], work[4]
    m = hidden.shape[0]
    xr[:] = x[i]
    for j in range(m):
        xr[hidden[j]] = h[j]
    call_row(row, q, xr, xd, mr, ld, sc, u[i], w[i * ws], hagl[i * hs], omm[i * oms], pk)
    for j in range(m):
        g[j] = xd[hidden[j]]
    for l in range(m):
        hl = h[l]
        for j in range(m):
            g[j] -= a0_t[l, j] * hl


@_inlined
def modal_matrix(vr, vi, wr, wi, vir, vii, out_t):
    """out_t = Re(V diag(w) V^-1).T from real and imaginary parts."""
    m = out_t.shape[0]
    for j in range(m):
        for l in range(m):
            acc = 0.0
            for k in range(m):
                # (V diag(w))[j, k] * Vinv[k, l], real part
                ar = vr[j, k] * wr[k] - vi[j, k] * wi[k]
                ai = vr[j, k] * wi[k] + vi[j, k] * wr[k]
                acc += ar * vir[k, l] - ai * vii[k, l]
            out_t[l, j] = acc


@_compiled
def hidden_pass(row, dims, hidden, nk, nt, t, x, u, w, ws, hagl, hs, omm, oms, params, ps,
                lam, vec, vinv, a0, h0, scale, tol, max_iter, hout, mout, stats):
    """Hidden states of nk parameter sets along a flight, sample by sample.

    Between samples the hidden dynamics h' = A0 h + g(t) are integrated exactly with
    g = f_h - A0 h linear over the step (first-order hold):
        h_{k+1} = E h_k + (Phi1 - Phi2) g_k + Phi2 g_{k+1},
        E = V e^{lam dt} V^-1, Phi1,2 = V diag(phi1,2(lam, dt)) V^-1   (real matrices)
    computed once for the first step's dt and reused while dt stays within 1e-9 of it
    (irregular steps use the eigen-decomposition directly). g_{k+1} depends on h_{k+1}:
    fixed-point iteration (contraction |Phi2 (J - A0)| << 1) from g extrapolated
    linearly, until h moves less than tol * scale; the accepted h is the one evaluated
    last (its measurement goes to mout). stats[k] = (most iterations in a step, largest
    final change, model evaluations)."""
    m = hidden.shape[0]
    x, u, w, params = unmanaged(x), unmanaged(u), unmanaged(w), unmanaged(params)
    work = work_arrays(dims)
    xr = np.empty(dims[0])
    mr = np.empty(6)
    gk = np.empty(m)
    gprev = np.empty(m)
    gp = np.empty(m)
    hc = np.empty(m)
    hn = np.empty(m)
    base = np.empty(m)
    e_t = np.empty((m, m))  # E, Phi1 - Phi2, Phi2, transposed (see matvec_add)
    f_t = np.empty((m, m))
    p2_t = np.empty((m, m))
    a0_t = np.empty((m, m))
    wr = np.empty(m)
    wi = np.empty(m)
    war = np.empty(m)
    wai = np.empty(m)
    p2r = np.empty(m)
    p2i = np.empty(m)
    zr = np.empty(m)
    zi = np.empty(m)
    dt_ref = t[1] - t[0] if nt > 1 else 0.0
    for kk in range(nk):
        pk = params[kk * ps]
        lk, sk = lam[kk], scale[kk]
        a0_t[:, :] = a0[kk].T
        vr, vi = vec[kk].real.copy(), vec[kk].imag.copy()
        vir, vii = vinv[kk].real.copy(), vinv[kk].imag.copy()
        if nt > 1:
            for j in range(m):
                ea, p1, p2 = foh_weights(lk[j], dt_ref)
                wr[j], wi[j] = ea.real, ea.imag
                war[j], wai[j] = (p1 - p2).real, (p1 - p2).imag
                p2r[j], p2i[j] = p2.real, p2.imag
            modal_matrix(vr, vi, wr, wi, vir, vii, e_t)
            modal_matrix(vr, vi, war, wai, vir, vii, f_t)
            modal_matrix(vr, vi, p2r, p2i, vir, vii, p2_t)
        worst_it = 0
        worst_change = 0.0
        evaluations = 1
        for j in range(m):
            hc[j] = h0[kk, j]
            hout[kk, 0, j] = hc[j]
        hidden_rates(row, hidden, 0, hc, xr, x, u, w, ws, hagl, hs, omm, oms, pk, a0_t, gk, mr,
                     work)
        mout[kk, 0, :] = mr
        gprev[:] = gk
        for k in range(nt - 1):
            dt = t[k + 1] - t[k]
            uniform = abs(dt - dt_ref) <= 1e-9 * abs(dt_ref)
            if uniform:
                base[:] = 0.0
                matvec_add(base, e_t, hc)
                matvec_add(base, f_t, gk)
            else:  # irregular step: exact weights of this dt, in the eigenbasis
                for j in range(m):
                    ea, p1, p2 = foh_weights(lk[j], dt)
                    wr[j], wi[j] = ea.real, ea.imag
                    war[j], wai[j] = (p1 - p2).real, (p1 - p2).imag
                    p2r[j], p2i[j] = p2.real, p2.imag
                for j in range(m):  # z = ea V^-1 h + (phi1 - phi2) V^-1 g
                    hr = 0.0
                    hi = 0.0
                    gr = 0.0
                    gi = 0.0
                    for l in range(m):
                        hr += vir[j, l] * hc[l]
                        hi += vii[j, l] * hc[l]
                        gr += vir[j, l] * gk[l]
                        gi += vii[j, l] * gk[l]
                    zr[j] = wr[j] * hr - wi[j] * hi + war[j] * gr - wai[j] * gi
                    zi[j] = wr[j] * hi + wi[j] * hr + war[j] * gi + wai[j] * gr
                for j in range(m):
                    acc = 0.0
                    for l in range(m):
                        acc += vr[j, l] * zr[l] - vi[j, l] * zi[l]
                    base[j] = acc
            for j in range(m):
                gp[j] = 2.0 * gk[j] - gprev[j]  # predictor: g extrapolated
            change = np.inf
            it = 0
            while it < max_iter:
                it += 1
                # hn = base + Phi2 gp
                if uniform:
                    hn[:] = base
                    matvec_add(hn, p2_t, gp)
                else:
                    for j in range(m):
                        gr = 0.0
                        gi = 0.0
                        for l in range(m):
                            gr += vir[j, l] * gp[l]
                            gi += vii[j, l] * gp[l]
                        zr[j] = p2r[j] * gr - p2i[j] * gi
                        zi[j] = p2r[j] * gi + p2i[j] * gr
                    for j in range(m):
                        acc = base[j]
                        for l in range(m):
                            acc += vr[j, l] * zr[l] - vi[j, l] * zi[l]
                        hn[j] = acc
                if it > 1:
                    change = 0.0
                    for j in range(m):
                        d = abs(hn[j] - hc[j]) / sk[j]
                        if d > change:
                            change = d
                    if change < tol:
                        break
                hc[:] = hn
                evaluations += 1
                hidden_rates(row, hidden, k + 1, hc, xr, x, u, w, ws, hagl, hs, omm, oms, pk,
                             a0_t, gp, mr, work)
            # accept the last evaluated state hc (rates gp, measurement mr)
            gprev[:] = gk
            gk[:] = gp
            for j in range(m):
                hout[kk, k + 1, j] = hc[j]
            mout[kk, k + 1, :] = mr
            if it > worst_it:
                worst_it = it
            if change > worst_change:
                worst_change = change
        stats[kk, 0] = worst_it
        stats[kk, 1] = worst_change
        stats[kk, 2] = evaluations


@_compiled
def windows_pass(row, dims, hidden, nk, idx, x, u, w, ws, hagl, hs, omm, oms, params, ps,
                 h_ref, a_t, a_inv_t, e_t, p1_t, p2_t, newton, zout):
    """Predicted measurement of nk parameter sets over W windows of a flight, the hidden
    states propagated along each window by exponential time differencing in PEC mode (the
    calibration's `airwake.calibrate.hidden.HiddenPropagator`, step for step):

        start   h = h_ref, then `newton` steps h -= A^-1 f_h(h) at the window's first row
        predict h^p = E h + (Phi1 + Phi2/dt) g - (Phi2/dt) g_prev
        evaluate g_new = f_h(h^p) - A h^p and z at the next row
        correct h = h^p + (Phi2/dt) (g_new - 2 g + g_prev)

    idx (W, L) flight rows; x (N, S) with the body states filled; per set k: h_ref[k] (m,)
    and the matrices given transposed (a_t = A^T, ...; (K, m, m)). zout (K, W, L, 6).
    One model call site (the row is inlined there): stage s < newton is a Newton step,
    s = newton the window's first sample, then one stage per sample."""
    m = hidden.shape[0]
    n_win, length = idx.shape
    x, u, w, params = unmanaged(x), unmanaged(u), unmanaged(w), unmanaged(params)
    q, ld, sc, mr, xd = work_arrays(dims)[:5]
    xr = np.empty(dims[0])
    h = np.empty(m)
    hp = np.empty(m)
    g = np.empty(m)
    gprev = np.empty(m)
    gnew = np.empty(m)
    d = np.empty(m)
    for kk in range(nk):
        pk = params[kk * ps]
        at, ait, et, p1, p2 = a_t[kk], a_inv_t[kk], e_t[kk], p1_t[kk], p2_t[kk]
        for wi in range(n_win):
            h[:] = h_ref[kk]
            for s in range(newton + length):
                jj = s - newton  # the window's sample, once past the Newton steps
                if jj <= 0:
                    i = idx[wi, 0]
                    hp[:] = h
                else:  # predict
                    i = idx[wi, jj]
                    hp[:] = 0.0
                    matvec_add(hp, et, h)
                    matvec_add(hp, p1, g)
                    for l in range(m):
                        gl = gprev[l]
                        for j in range(m):
                            hp[j] -= p2[l, j] * gl
                xr[:] = x[i]
                for j in range(m):
                    xr[hidden[j]] = hp[j]
                call_row(row, q, xr, xd, mr, ld, sc, u[i], w[i * ws], hagl[i * hs],
                         omm[i * oms], pk)
                if jj < 0:  # Newton: h -= A^-1 f
                    d[:] = 0.0
                    for j in range(m):
                        gnew[j] = xd[hidden[j]]
                    matvec_add(d, ait, gnew)
                    for j in range(m):
                        h[j] -= d[j]
                    continue
                for j in range(m):  # g = f - A h at the evaluated state
                    gnew[j] = xd[hidden[j]]
                for l in range(m):
                    hl = hp[l]
                    for j in range(m):
                        gnew[j] -= at[l, j] * hl
                zout[kk, wi, max(jj, 0), :] = mr
                if jj == 0:
                    g[:] = gnew
                    gprev[:] = gnew
                    continue
                for j in range(m):  # correct
                    d[j] = gnew[j] - 2.0 * g[j] + gprev[j]
                h[:] = hp
                matvec_add(h, p2, d)
                gprev[:] = g
                g[:] = gnew
