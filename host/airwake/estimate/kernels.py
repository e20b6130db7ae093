"""Compiled per-particle arithmetic of the wind model (numba): the work around the one
batched helicopter-model evaluation of each sample, fused into two passes over the
particles instead of ~30 numpy passes (the numpy version cost as much as the model).

`transition_rows` : wind random walk (noise drawn by the caller's Generator) with the
                    box, the rotor-state predictor, and the model's input rows.
`observe_rows`    : rotor-state remainder g, corrector, and the eq 5.17 log-likelihood.
The maths is the one written in `airwake.calibrate.hidden` and `wind_model`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, fastmath=True)
def transition_rows(wind, noise, step, bounds, hidden, g, g_prev, e_t, p1_t, p2_t, started,
                    x_body, hid, x_out, h_pred):
    """In place: wind += noise * step (clipped to +-bounds); h_pred = hidden @ e_t +
    g @ p1_t - g_prev @ p2_t (or hidden when not started); x_out rows = x_body with the
    rotor states h_pred at columns `hid`."""
    n, m = hidden.shape
    s = x_body.shape[0]
    acc = np.empty(m)
    for i in range(n):
        for c in range(6):
            v = wind[i, c] + noise[i, c] * step[c]
            wind[i, c] = min(max(v, -bounds[c]), bounds[c])
        for j in range(s):
            x_out[i, j] = x_body[j]
        if started:
            acc[:] = 0.0
            for b in range(m):  # i-b-a order: the inner loop runs along matrix rows
                hb, gb, pb = hidden[i, b], g[i, b], g_prev[i, b]
                for a in range(m):
                    acc[a] += hb * e_t[b, a] + gb * p1_t[b, a] - pb * p2_t[b, a]
        else:
            for a in range(m):
                acc[a] = hidden[i, a]
        for a in range(m):
            h_pred[i, a] = acc[a]
            x_out[i, hid[a]] = acc[a]


@njit(cache=True)
def observe_rows(xd, z, h_pred, hidden, g, g_prev, a_t, p2_t, started, hid, h_ref, z_meas,
                 inv_scale, inv_sigma, log_lik):
    """In place: g_new = xd[:, hid] - h_pred @ a_t; hidden = h_pred + (g_new - 2 g +
    g_prev) @ p2_t (corrector; = h_pred when not started); g_prev, g = g, g_new;
    log_lik = -||(z_meas - z) * inv_scale|| * inv_sigma (-inf when not finite). A row
    whose rotor state is not finite restarts at h_ref with zero remainders."""
    n, m = hidden.shape
    gn = np.empty(m)
    d = np.empty(m)
    hn = np.empty(m)
    for i in range(n):
        for a in range(m):
            gn[a] = xd[i, hid[a]]
        for b in range(m):
            hb = h_pred[i, b]
            for a in range(m):
                gn[a] -= hb * a_t[b, a]
        ok = True
        if started:
            for a in range(m):
                d[a] = gn[a] - 2.0 * g[i, a] + g_prev[i, a]
                hn[a] = h_pred[i, a]
            for b in range(m):
                db = d[b]
                for a in range(m):
                    hn[a] += db * p2_t[b, a]
            for a in range(m):
                hidden[i, a] = hn[a]
                g_prev[i, a] = g[i, a]
                g[i, a] = gn[a]
                if not (math.isfinite(hn[a]) and math.isfinite(gn[a])):
                    ok = False
        else:
            for a in range(m):
                hidden[i, a] = h_pred[i, a]
                g[i, a] = gn[a]
                g_prev[i, a] = gn[a]
                if not (math.isfinite(h_pred[i, a]) and math.isfinite(gn[a])):
                    ok = False
        if not ok:
            for a in range(m):
                hidden[i, a] = h_ref[a]
                g[i, a] = 0.0
                g_prev[i, a] = 0.0
        ss = 0.0
        for c in range(6):
            e = (z_meas[c] - z[i, c]) * inv_scale[c]
            ss += e * e
        ll = -math.sqrt(ss) * inv_sigma
        log_lik[i] = ll if math.isfinite(ll) else -np.inf
