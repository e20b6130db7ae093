"""Servo lag between the recorded commands and the blade pitch (catalogue effect)."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, State, register_effect
from airwake.heli.kernel import Q, kernel


@register_effect("servo_lag")
class ServoLag(Effect):
    """First-order servo dynamics: a flight table records the pilot's *commands* (RC PWM
    mapped to blade pitch); the blades reach them through servos with a finite speed,

        d theta_j / dt = (delta_j - theta_j) / tau_j

    tau_swash for the three swashplate servos (collective, lateral, longitudinal) and
    tau_tail for the tail servo. The model downstream sees theta. For slow inputs
    theta ~ delta - tau d delta/dt: the residual is proportional to the input *rates*
    (it leads the inputs by 90 degrees at low frequency) and grows with input frequency.
    Off = absent (tau -> 0).
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
    SCRATCH = 4  # the commands, kept from the inputs stage for state_rates

    @kernel
    def inputs(q, p, s, ds, load, scratch):
        scratch[0] = q[Q.delta_col_rad]
        scratch[1] = q[Q.delta_lat_rad]
        scratch[2] = q[Q.delta_lon_rad]
        scratch[3] = q[Q.delta_ped_rad]
        q[Q.delta_col_rad] = s[0]
        q[Q.delta_lat_rad] = s[1]
        q[Q.delta_lon_rad] = s[2]
        q[Q.delta_ped_rad] = s[3]

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        for j in range(3):
            ds[j] = (scratch[j] - s[j]) / p.tau_swash_s
        ds[3] = (scratch[3] - s[3]) / p.tau_tail_s
