"""A truth-only effect *outside* the discrepancy catalogue (for its out-of-catalogue test).

Tail-rotor thrust error growing with airspeed: in forward and sideward flight the tail
rotor works in the main rotor's swept wake and the fin's blockage changes with the
sideslip flow, so its thrust departs from the hover-calibrated blade-element value the
host model uses. Written here, truth side only, as an extra tail-rotor side force
proportional to the in-plane airspeed squared (a dynamic-pressure scaling):

    dY = -k_T (V / V_ref)^2 T_tail,  at the tail rotor r_T = (-l_T, 0, -h_T)
    V = |(u_air, v_air)| at the CG (still air: the body's horizontal speed)

k_T = relative thrust change at V_ref (0.25 at 5 m/s: the tail works 25 % harder). The
force acts along the tail thrust (-y for positive thrust), so it yaws the nose right and
pushes the body left: rdot and ay residuals that grow as V^2 with the tail thrust.
Neither the catalogue nor the host model has such a term. Not registered in the host's
effect registry (like the other hidden effects); the discrepancy tests append it to the
truth model (`with_tail_thrust_error`).
"""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter
from airwake.heli.kernel import Q, add_load, cross, kernel


class TailThrustAirspeedError(Effect):
    """Tail thrust error proportional to the airspeed squared (module docstring)."""

    name = "hil_tail_thrust_airspeed"
    PARAMETERS = (
        Parameter("relative_change", 0.25, "-", (-1.0, 2.0), "k_T at V_ref"),
        Parameter("reference_airspeed_m_s", 5.0, "m/s", (0.5, 30.0), "V_ref", fixed=True),
        Parameter("arm_m", 0.7978, "m", (0.1, 3.0), "truth tail arm l_T", fixed=True),
        Parameter("height_m", 0.012, "m", (-0.5, 0.5), "truth tail height h_T", fixed=True),
    )

    def rest_state(self, u, ctx):
        """No states: the truth's trim has nothing to start for this effect."""
        import numpy as np

        return np.zeros(0)

    def linear_values(self) -> dict:
        """Smooth already: nothing to switch off for the trim."""
        return {}

    @kernel
    def forces(q, p, s, ds, load, scratch):
        ux = q[Q.wind_v_m_s] - q[Q.vel_b_m_s]
        uy = q[Q.wind_v_m_s + 1] - q[Q.vel_b_m_s + 1]
        v2 = (ux * ux + uy * uy) / (p.reference_airspeed_m_s * p.reference_airspeed_m_s)
        fy = -p.relative_change * v2 * q[Q.tail_thrust_n]
        mx, my, mz = cross(-p.arm_m, 0.0, -p.height_m, 0.0, fy, 0.0)
        add_load(load, 0.0, fy, 0.0, mx, my, mz)


def with_tail_thrust_error(truth, relative_change: float = 0.25):
    """A `TruthModel` with the tail-thrust error appended to its model (the effect runs
    after the tail rotor's forces, in the forces stage)."""
    import dataclasses

    from airwake.heli import HeliModel

    tail = truth.host_model["tail_rotor"].parameters()
    eff = TailThrustAirspeedError(relative_change=relative_change, arm_m=tail["arm_m"],
                                  height_m=tail["height_m"])
    return dataclasses.replace(truth, model=HeliModel(list(truth.model.effects) + [eff]))
