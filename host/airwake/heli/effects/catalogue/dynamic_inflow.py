"""Inflow dynamics: the induced inflow lags the thrust (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, State, register_effect
from airwake.heli.kernel import Q, kernel


@register_effect("dynamic_inflow")
class DynamicInflow(Effect):
    """First-order (Pitt-Peters apparent-mass) lag of the mean induced inflow:

        tau d lambda / dt = lambda_qs - lambda,   tau ~ (apparent mass of the air column
        8 rho R^3 / 3) / (mass flow through the disk) ~ 0.05-0.15 s for this rotor

    lambda_qs is the quasi-static inflow the earlier inflow-stage effects produced; the
    rotor sees the lagged lambda. A collective step meets the old, smaller inflow: thrust
    overshoots, then settles. Signature: az residual proportional to the collective
    (and thrust) *rate*, in phase with d(delta_col)/dt, decaying within tau.
    Off = absent (tau -> 0).
    """

    PARAMETERS = (
        Parameter("tau_s", 0.08, "s", (0.005, 1.0), "fitted", doc="inflow time constant"),
    )
    STATES = (State("lambda_0", "-", "lagged mean inflow (/(Omega R))"),)
    REQUIRES = ("main_rotor", "pitt_peters_inflow")
    SCRATCH = 1  # the quasi-static inflow
    KEEP_LAST = True  # effects added later still feed the lagged (quasi-static) inflow

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        scratch[0] = q[Q.inflow_0]
        q[Q.inflow_0] = s[0]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        ds[0] = (scratch[0] - s[0]) / p.tau_s
