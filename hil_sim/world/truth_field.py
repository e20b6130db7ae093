"""The simulator's truth for scoring airwake maps: the wind field a simulated flight flew
through, rebuilt from its flight table's metadata and evaluated anywhere.

    field = TruthField.from_metadata(flight_metadata)     # scenario_config + seed
    flow = field.relative_flow(t_s, pos_m, euler_rad, frame="ship")   # (N, 6)

The field is the one `run_scenario` built: same wind configuration, same ship, same
random stream for the turbulence (the "wind" child of the seed's SeedSequence), so its
value at a place and time is what the helicopter would have felt there. `relative_flow`
returns the eq 5.3 local wind at hub positions `pos_m` (ship frame: x forward of the
hangar step, y starboard, z down from the deck; or NED for "site") for a rotor at
attitude `euler_rad` (roll, pitch, yaw), turned the way `airwake wind map` turns the
estimates: body -> NED, minus the ship's translational velocity, rotated by the ship's
heading: [u, v, w, w_x, w_y, w_z] relative to the ship.

The analysis never reads this: only the scoring of simulated flights does
(`airwake wind map --score`), through `airwake.estimate.truth`.
"""

from __future__ import annotations

import numpy as np

from hil_sim.world.kinematics import euler_to_dcm, euler_to_quat


class TruthField:
    """A simulated flight's wind field and ship (see module docstring)."""

    def __init__(self, field, ship) -> None:
        self.field = field
        self.ship = ship

    @classmethod
    def from_metadata(cls, metadata: dict) -> TruthField:
        """From a simulated flight table's metadata (keys "scenario_config", "seed")."""
        from hil_sim.sensors.config import config_from_dict
        from hil_sim.world.run import RNG_STREAMS
        from hil_sim.world.ship import Ship, ShipConfig
        from hil_sim.world.wind import build_wind_field

        cfg = metadata.get("scenario_config")
        if not isinstance(cfg, dict) or "seed" not in metadata:
            raise ValueError("not a simulated flight: its metadata has no scenario_config "
                             "and seed")
        children = np.random.SeedSequence(int(metadata["seed"])).spawn(len(RNG_STREAMS))
        rng = np.random.default_rng(children[RNG_STREAMS.index("wind")])
        ship = None
        if cfg.get("ship"):
            ship = Ship(config_from_dict(ShipConfig, dict(cfg["ship"]), "ship"))
        field = build_wind_field(dict(cfg["wind"]), rng=rng, ship=ship)
        return cls(field, ship)

    def relative_flow(self, t_s: np.ndarray, pos_m: np.ndarray, euler_rad: np.ndarray,
                      frame: str = "ship") -> np.ndarray:
        """(N, 6) eq 5.3 wind relative to the ship (or the site) in the map frame."""
        t = np.asarray(t_s, dtype=float)
        pos = np.asarray(pos_m, dtype=float).reshape(-1, 3)
        euler = np.asarray(euler_rad, dtype=float).reshape(-1, 3)
        if frame == "ship":
            if self.ship is None:
                raise ValueError("a ship-frame map of a flight without a ship")
            hub_ned = self.ship.ship_to_ned(t, pos)
        else:
            hub_ned = pos
        local = self.field.local_wind(t, hub_ned, euler_to_quat(euler))
        rot = euler_to_dcm(euler)  # body -> NED
        v_ned = np.einsum("nij,nj->ni", rot, local[:, :3])
        w_ned = np.einsum("nij,nj->ni", rot, local[:, 3:])
        if frame != "ship":
            return np.column_stack([v_ned, w_ned])
        v_ned = v_ned - self.ship.translational_velocity_ned(t)
        heading = self.ship.euler_rad(t)[:, 2]
        c, s = np.cos(heading), np.sin(heading)
        # NED -> ship heading frame: R_z(psi)^T
        def turn(a):
            return np.column_stack([c * a[:, 0] + s * a[:, 1], -s * a[:, 0] + c * a[:, 1],
                                    a[:, 2]])

        return np.column_stack([turn(v_ned), turn(w_ned)])

    def mean_flow_ned(self, pos_ned_m: np.ndarray) -> np.ndarray:
        """(N, 3) the field's time-averaged air velocity (no shedding, no turbulence) at
        site NED positions: what a steady-state map (`airwake windmap`) is scored on."""
        if self.ship is not None:
            raise ValueError("a site-frame mean flow of a flight with a moving ship")
        pos = np.asarray(pos_ned_m, dtype=float).reshape(-1, 3)
        return self.field.mean_velocity_ned(0.0, pos)


def warm(scenarios=("ship_airwake_b0", "fans_indoor")) -> list[str]:
    """Compile (or load from numba's cache) the truth fields' code by evaluating the wind of
    each shipped scenario once (a Dask worker does it when it starts: several workers
    compiling it at once on one machine only multiply the minutes). Returns the scenarios
    it evaluated; one that fails to build is skipped (the task that needs it says why)."""
    from hil_sim.world.scenario import ScenarioError, load_scenario

    done = []
    for name in scenarios:
        try:
            field = TruthField.from_metadata({"scenario_config": load_scenario(name).describe(),
                                              "seed": 0})
        except (ScenarioError, ValueError, KeyError, TypeError):
            continue
        field.relative_flow(np.array([0.0, 0.01]), np.zeros((2, 3)) + [-5.0, 0.0, -2.0],
                            np.zeros((2, 3)), "ship" if field.ship is not None else "site")
        done.append(name)
    return done

