"""Atmosphere: air density."""

from __future__ import annotations

from airwake.heli.effects.base import Effect, Parameter, register_effect
from airwake.heli.kernel import Q, kernel


@register_effect("atmosphere")
class Atmosphere(Effect):
    """Air density used by every aerodynamic effect (Pitt-Peters normalisation, tail
    rotor, fuselage, empennage)."""

    PARAMETERS = (
        Parameter("air_density_kg_m3", 1.225, "kg/m^3", (0.5, 1.5), "Table 5.1 (rho)", fixed=True),
    )

    @kernel
    def environment(q, p, s, ds, load, scratch):
        q[Q.air_density_kg_m3] = p.air_density_kg_m3
