"""Inflow dynamics: the induced inflow lags the thrust (catalogue effect)."""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.effects._util import fetch, stash
from airwake.heli.effects.base import Effect, Parameter, State, register_effect


@register_effect("dynamic_inflow")
class DynamicInflow(Effect):
    """First-order (Pitt-Peters apparent-mass) lag of the mean induced inflow:

        tau d lambda / dt = lambda_qs - lambda,   tau ~ 0.85 R / (v_i) (apparent mass of
        the air column, 8 rho R^3/3 pi, over the mass flow; ~0.05-0.15 s here)

    lambda_qs is the quasi-static inflow the earlier inflow-stage effects produced; the
    rotor sees the lagged lambda. A collective step meets the old, smaller inflow: thrust
    overshoots, then settles. Signature: az residual proportional to the collective
    (and thrust) *rate*, in phase with d(delta_col)/dt, decaying within tau.
    """

    PARAMETERS = (
        Parameter("tau_s", 0.08, "s", (0.005, 1.0), "fitted", doc="inflow time constant"),
    )
    STATES = (State("lambda_0", "-", "lagged mean inflow (/(Omega R))"),)
    REQUIRES = ("main_rotor", "pitt_peters_inflow")

    def inflow(self, ctx, p) -> None:
        stash(ctx, "dynamic_inflow.qs", np.array(ctx.inflow_0, dtype=float))
        ctx.inflow_0 = ctx.state(self.name)[:, 0].copy()

    def state_rates(self, ctx, p) -> None:
        lam = ctx.state(self.name)[:, 0]
        rate = (fetch(ctx, "dynamic_inflow.qs") - lam) / np.asarray(p.tau_s, float)
        ctx.set_rates(self.name, rate[:, None])
