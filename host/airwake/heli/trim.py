"""Trim (steady flight) and linearisation of a `HeliModel`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from airwake.errors import AirwakeError
from airwake.heli.model import BODY_EFFECT

_VEL = slice(3, 6)
_RATES = slice(9, 12)


class TrimError(AirwakeError):
    """The trim iteration did not converge."""


@dataclass
class Trim:
    x: np.ndarray  # (S,) trimmed state
    u: np.ndarray  # (4,) trimmed inputs
    residual: float  # max |d/dt| of the trimmed quantities
    iterations: int


def _jacobian(fun, z: np.ndarray, eps: np.ndarray) -> np.ndarray:
    """Central differences of a batched function fun((K,n)) -> (K,m), one call."""
    n = z.size
    pts = np.concatenate([z[None], z + np.diag(eps), z - np.diag(eps)])
    out = fun(pts)
    return (out[1 : n + 1] - out[n + 1 :]).T / (2.0 * eps)


def trim(
    model,
    vel_b_m_s=(0.0, 0.0, 0.0),
    yaw_rad: float = 0.0,
    wind=None,
    env=None,
    params=None,
    tol: float = 1e-10,
    max_iter: int = 30,
) -> Trim:
    """Steady flight at a body velocity (hover by default): solves for the four inputs,
    roll and pitch and every non-body state so that the body accelerations, angular
    accelerations and all hidden-state rates vanish (Newton, batched finite differences)."""
    s = model.n_states
    body = model.state_slice(BODY_EFFECT)
    hidden = [i for i in range(s) if not (body.start <= i < body.stop)]
    x0 = np.zeros(s)
    x0[body.start + 3 : body.start + 6] = vel_b_m_s
    x0[body.start + 8] = yaw_rad
    z = np.zeros(6 + len(hidden))
    z[0] = 0.09  # collective near hover

    def unpack(zz):
        k = zz.shape[0]
        x = np.repeat(x0[None], k, 0)
        x[:, body.start + 6] = zz[:, 4]
        x[:, body.start + 7] = zz[:, 5]
        x[:, hidden] = zz[:, 6:]
        return x, zz[:, :4]

    def resid(zz):
        x, u = unpack(zz)
        xd = model.derivatives(x, u, wind, env, params)
        return np.concatenate(
            [xd[:, body.start + 3 : body.start + 6], xd[:, body.start + 9 : body.start + 12],
             xd[:, hidden]], axis=1
        )

    scale = np.ones(z.size)
    for it in range(1, max_iter + 1):
        r = resid(z[None])[0]
        err = np.max(np.abs(r))
        if err < tol:
            x, u = unpack(z[None])
            return Trim(x[0], u[0], float(err), it)
        jac = _jacobian(resid, z, 1e-6 * scale)
        step = np.linalg.lstsq(jac, -r, rcond=None)[0]
        # damp large steps (first iterations from a cold start)
        big = np.max(np.abs(step[:6]))
        z = z + (step * min(1.0, 0.2 / big) if big > 0.2 else step)
    x, u = unpack(z[None])
    err = float(np.max(np.abs(resid(z[None])[0])))
    if err > 1e-6:
        raise TrimError(
            f"trim did not converge: max residual {err:.3g} after {max_iter} iterations"
        )
    return Trim(x[0], u[0], err, max_iter)


def trim_hover(model, **kw) -> Trim:
    return trim(model, (0.0, 0.0, 0.0), **kw)


def linearize(model, x, u, w=None, env=None, params=None, eps: float = 1e-6):
    """A = d xdot/dx (S,S), B = d xdot/du (S,4) by central differences (one batched call)."""
    x = np.asarray(x, dtype=float)
    u = np.asarray(u, dtype=float)
    s = x.size
    z = np.concatenate([x, u])
    n = z.size
    pts = np.concatenate([z[None], z + eps * np.eye(n), z - eps * np.eye(n)])
    xd = model.derivatives(pts[:, :s], pts[:, s:], w, env, params)
    jac = (xd[1 : n + 1] - xd[n + 1 :]).T / (2 * eps)
    return jac[:, :s], jac[:, s:]
