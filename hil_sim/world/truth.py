"""The truth helicopter: the host's effect-based model with "true" parameters + hidden effects.

    truth = build_truth_model(spec="truth", overrides={"main_rotor.lock_number": 3.4},
                              hidden=HiddenConfig(ground_effect=GroundEffectConfig()))
    truth.model            # HeliModel: host effects (spec) + hidden effects (appended)
    truth.trim(vel_ned_m_s, yaw_rad, wind)  -> Trim at hover / steady flight

`spec` is "truth" (`hil_sim/world/truth_helicopter.toml`: reference Table 5.2 with a
plausible profile drag, see docs/scenarios.md), a shipped host spec name ("table52",
"table51") or a path to a TOML model spec. `overrides` are {"effect.param": value} on the
host effects. Hidden effects come from `hil_sim.world.hidden` (not from the host
registry): the host can load the same spec but never the hidden part.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from airwake.heli import HeliModel, load_spec
from airwake.heli.trim import Trim, TrimError, trim

from hil_sim.world.hidden import HiddenConfig, build_hidden_effects

TRUTH_SPEC_PATH = Path(__file__).resolve().parent / "truth_helicopter.toml"
BODY = "rigid_body"


def resolve_spec(spec: str | Path) -> Path | str:
    """'truth' -> the shipped truth spec; other names/paths go to the host's load_spec."""
    return TRUTH_SPEC_PATH if str(spec) == "truth" else spec


@dataclass
class TruthModel:
    """The truth `HeliModel`, its host-only part, and what built it."""

    model: HeliModel
    host_model: HeliModel  # the same helicopter without hidden effects (= "truth parameters")
    hidden: HiddenConfig
    spec: str
    overrides: dict = field(default_factory=dict)

    @property
    def rotor_radius_m(self) -> float:
        return float(self.model["main_rotor"].parameters()["radius_m"])

    @property
    def nominal_rotor_speed_rad_s(self) -> float:
        return float(self.model["main_rotor"].parameters()["nominal_speed_rad_s"])

    @property
    def hub_offset_body_m(self) -> np.ndarray:
        """Main-rotor hub relative to the CG, body axes (the hub sits h_R above the CG)."""
        return np.array([0.0, 0.0, -self.model["main_rotor"].parameters()["hub_height_m"]])

    def state_index(self, name: str) -> int:
        return self.model.state_index(name)

    def linear_model(self) -> HeliModel:
        """The truth model with its hidden effects' non-smooth parts switched off (the
        servo deadband): what the trim solves and the pilot's linear design sees. At a
        trim (servos at the command) it agrees with `model` exactly."""
        values = {}
        for e in self.model.effects[len(self.host_model.effects):]:
            values.update({f"{e.name}.{k}": v for k, v in e.linear_values().items()})
        return self.model.with_parameters(values) if values else self.model

    def trim(self, vel_body_m_s=(0.0, 0.0, 0.0), yaw_rad: float = 0.0, wind=None,
             height_agl_m: float = np.inf) -> Trim:
        """Steady flight of the truth model, hidden states included.

        The host's `trim` solves the host part from a cold start; the hidden states then
        start from their physical steady values (each effect's `rest_state`: servos at
        the command, rotor at the governor's set point, inflow at its quasi-static
        value) and Newton refines everything on the `linear_model`."""
        env = {"height_agl_m": np.array([float(height_agl_m)])}
        base = trim(self.host_model, vel_body_m_s, yaw_rad=yaw_rad, wind=wind)
        if len(self.model.effects) == len(self.host_model.effects):
            return base
        x0 = np.zeros(self.model.n_states)
        for i, name in enumerate(self.host_model.state_names):
            x0[self.model.state_names.index(name)] = base.x[i]
        ctx = self.host_model.evaluate(base.x[None], base.u[None], wind)
        for e in self.model.effects[len(self.host_model.effects):]:
            x0[self.model.state_slice(e.name)] = e.rest_state(base.u, ctx)
        return refine_trim(self.linear_model(), x0, base.u, wind=wind, env=env)


def refine_trim(model: HeliModel, x0: np.ndarray, u0: np.ndarray, wind=None, env=None,
                tol: float = 1e-10, max_iter: int = 30) -> Trim:
    """Newton on inputs, roll, pitch and every non-body state from an initial guess, so
    that body accelerations and all other state rates vanish (velocity, yaw and
    position are held)."""
    body = model.state_slice(BODY)
    free = [body.start + 6, body.start + 7] + [
        i for i in range(model.n_states) if not (body.start <= i < body.stop)]
    checked = list(range(body.start + 3, body.start + 6)) + list(
        range(body.start + 9, body.start + 12)) + free[2:]

    def unpack(z):
        x = np.repeat(x0[None], z.shape[0], 0)
        x[:, free] = z[:, 4:]
        return x, z[:, :4]

    def resid(z):
        x, u = unpack(z)
        return model.derivatives(x, u, wind, env)[:, checked]

    z = np.concatenate([u0, x0[free]])
    scale = np.maximum(np.abs(z), 1e-3)
    err = np.inf
    for it in range(1, max_iter + 1):
        r = resid(z[None])[0]
        err = float(np.max(np.abs(r)))
        if err < tol:
            x, u = unpack(z[None])
            return Trim(x[0], u[0], err, it)
        eps = 1e-7 * scale
        pts = np.concatenate([z + np.diag(eps), z - np.diag(eps)])
        out = resid(pts)
        jac = (out[: z.size] - out[z.size:]).T / (2.0 * eps)
        step = np.linalg.lstsq(jac, -r, rcond=None)[0]
        big = np.max(np.abs(step[:6]))
        z = z + (step * min(1.0, 0.2 / big) if big > 0.2 else step)
    if err > 1e-6:
        raise TrimError(f"truth trim did not converge: max residual {err:.3g}")
    x, u = unpack(z[None])
    return Trim(x[0], u[0], err, max_iter)


def build_truth_model(spec: str | Path = "truth", overrides: dict | None = None,
                      hidden: HiddenConfig | None = None) -> TruthModel:
    """Host model from `spec` (+ overrides) with the enabled hidden effects appended."""
    hidden = hidden or HiddenConfig()
    host = load_spec(resolve_spec(spec))
    if overrides:
        host = host.with_parameters(dict(overrides))
    rotor = host["main_rotor"].parameters()
    extra = build_hidden_effects(hidden, rotor_radius_m=rotor["radius_m"],
                                 nominal_speed_rad_s=rotor["nominal_speed_rad_s"])
    model = HeliModel(list(host.effects) + extra)
    return TruthModel(model=model, host_model=host, hidden=hidden, spec=str(spec),
                      overrides=dict(overrides or {}))
