"""One made-up effect written twice, as a numpy plugin and as a compiled kernel plugin.

It touches every kind of pipeline hook a plugin can use (inflow modification, a load, an
own state with private scratch, a measurement transform), so a test can check that the
two styles give the same model, and that numpy stages interleave correctly with the
compiled segments around them.

    inflow:       lambda_0 <- lambda_0 (1 + k_inflow)
    forces:       side drag at the tail boom r = (-0.8, 0, 0): F_y = rho/2 cd v_y |v_y|
    state_rates:  d v_f/dt = (v_y - v_f) / tau       (v_y kept from the forces stage)
    measurement:  acc_x += bias_gain v_f
"""

import numpy as np
from airwake.heli import Effect, Parameter, State, register_effect
from airwake.heli.context import cross
from airwake.heli.kernel import Q, add_load, air_velocity_at, kernel
from airwake.heli.kernel import cross as kcross

BOOM = (-0.8, 0.0, 0.0)
PARAMETERS = (
    Parameter("k_inflow", 0.1, "-", (0.0, 1.0), "test"),
    Parameter("cd_m2", 0.02, "m^2", (0.0, 1.0), "test"),
    Parameter("tau_s", 0.05, "s", (0.001, 1.0), "test"),
    Parameter("bias_gain", 0.01, "1/s", (-1.0, 1.0), "test"),
)
STATES = (State("v_f_m_s", "m/s", "filtered side flow at the boom"),)


@register_effect("test_probe_numpy")
class ProbeNumpy(Effect):
    """Test probe, numpy style."""

    PARAMETERS = PARAMETERS
    STATES = STATES
    REQUIRES = ("main_rotor",)

    def inflow(self, ctx, p):
        ctx.inflow_0 = ctx.inflow_0 * (1.0 + p.k_inflow)

    def forces(self, ctx, p):
        vy = ctx.air_velocity_at(np.array(BOOM))[:, 1]
        f = np.zeros((ctx.n, 3))
        f[:, 1] = 0.5 * ctx.air_density_kg_m3 * p.cd_m2 * vy * np.abs(vy)
        ctx.add_load(self.name, f, cross(np.array(BOOM), f))
        ctx.probe_vy = vy

    def state_rates(self, ctx, p):
        vf = ctx.state(self.name)[:, 0]
        ctx.set_rates(self.name, ((ctx.probe_vy - vf) / p.tau_s)[:, None])

    def measurement(self, ctx, p):
        ctx.meas[:, 0] += p.bias_gain * ctx.state(self.name)[:, 0]


@register_effect("test_probe_kernel")
class ProbeKernel(Effect):
    """Test probe, kernel style."""

    PARAMETERS = PARAMETERS
    STATES = STATES
    REQUIRES = ("main_rotor",)
    SCRATCH = 1  # v_y from forces to state_rates

    @kernel
    def inflow(q, p, s, ds, load, scratch):
        q[Q.inflow_0] = q[Q.inflow_0] * (1.0 + p.k_inflow)

    @kernel
    def forces(q, p, s, ds, load, scratch):
        vy = air_velocity_at(q, -0.8, 0.0, 0.0)[1]
        fy = 0.5 * q[Q.air_density_kg_m3] * p.cd_m2 * vy * abs(vy)
        mx, my, mz = kcross(-0.8, 0.0, 0.0, 0.0, fy, 0.0)
        add_load(load, 0.0, fy, 0.0, mx, my, mz)
        scratch[0] = vy

    @kernel
    def state_rates(q, p, s, ds, load, scratch):
        ds[0] = (scratch[0] - s[0]) / p.tau_s

    @kernel
    def measurement(q, p, s, ds, load, scratch):
        q[Q.meas] += p.bias_gain * s[0]
