"""Servo lag between the recorded commands and the blade pitch (catalogue effect)."""

from __future__ import annotations

import numpy as np

from airwake.discrepancy.effects._util import fetch, stash
from airwake.heli.effects.base import Effect, Parameter, State, register_effect


@register_effect("servo_lag")
class ServoLag(Effect):
    """First-order servo dynamics: a flight table records the pilot's *commands* (RC PWM
    mapped to blade pitch); the blades reach them through servos with a finite speed,

        d theta_j / dt = (delta_j - theta_j) / tau_j

    tau_swash for the three swashplate servos (collective, lateral, longitudinal) and
    tau_tail for the tail servo. The model downstream sees theta. For slow inputs
    theta ~ delta - tau d delta/dt: the residual is proportional to the input *rates*
    (it leads the inputs by 90 degrees at low frequency) and grows with input frequency.
    """

    PARAMETERS = (
        Parameter("tau_swash_s", 0.05, "s", (0.002, 0.5), "fitted",
                  doc="swashplate servo time constant"),
        Parameter("tau_tail_s", 0.05, "s", (0.002, 0.5), "fitted",
                  doc="tail servo time constant"),
    )
    STATES = (
        State("col_rad", "rad", "collective blade pitch reached"),
        State("lat_rad", "rad", "lateral cyclic reached"),
        State("lon_rad", "rad", "longitudinal cyclic reached"),
        State("ped_rad", "rad", "tail blade pitch reached"),
    )

    def inputs(self, ctx, p) -> None:
        st = ctx.state(self.name)
        cmd = np.column_stack([np.broadcast_to(np.asarray(v, float), (ctx.n,)) for v in (
            ctx.delta_col_rad, ctx.delta_lat_rad, ctx.delta_lon_rad, ctx.delta_ped_rad)])
        stash(ctx, "servo_lag.command", cmd)  # read back in state_rates
        ctx.delta_col_rad = st[:, 0].copy()
        ctx.delta_lat_rad = st[:, 1].copy()
        ctx.delta_lon_rad = st[:, 2].copy()
        ctx.delta_ped_rad = st[:, 3].copy()

    def state_rates(self, ctx, p) -> None:
        st = ctx.state(self.name)
        swash = np.asarray(p.tau_swash_s, float)
        tail = np.asarray(p.tau_tail_s, float)
        tau = np.stack(np.broadcast_arrays(swash, swash, swash, tail), -1)
        ctx.set_rates(self.name, (fetch(ctx, "servo_lag.command") - st) / tau)
