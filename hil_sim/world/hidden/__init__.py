"""Truth-only ("hidden") effects: physics the host's helicopter model does not contain.

They exist so that the discrepancy workflow has something real to find (MISSION.md §3.6).
Each is implemented here, independently of the host's effect library: own formulas,
own parameters, own files. The model-side ones are `Effect` subclasses plugged into the
truth `HeliModel` pipeline; they are deliberately **not registered** in the host's
effect registry (`register_effect`), so no host tool (catalogue, spec loader, the
discrepancy candidates) can build a model with them by construction.

    ground_effect       GroundEffect          inflow stage   Cheeseman-Bennett
    servo_lag           ServoLag              inputs         first-order servo lag (+ delay in run)
    rotor_droop         RotorGovernor         rotor_speed    finite-gain governor + rotor inertia
    dynamic_inflow      DynamicInflow         inflow         first-order lag of the mean inflow
    wake_recirculation  WakeRecirculation     inflow         ground-vortex inflow increase
    lever_arm           (sensor side)         the IMU sits at r from the CG

Scenario tables (`[hidden.<name>]`) are read into the `*Config` dataclasses of
`hil_sim.world.hidden.config`; `build_hidden_effects` turns them into effect instances
in pipeline order. docs/scenarios.md gives each effect's physics and its signature in
the flight table.
"""

from hil_sim.world.hidden.config import (
    HIDDEN_CONFIGS,
    DynamicInflowConfig,
    GroundEffectConfig,
    HiddenConfig,
    LeverArmConfig,
    RotorDroopConfig,
    ServoLagConfig,
    WakeRecirculationConfig,
    hidden_from_dict,
)
from hil_sim.world.hidden.effects import (
    DynamicInflow,
    GroundEffect,
    RotorGovernor,
    ServoLag,
    WakeRecirculation,
    build_hidden_effects,
)

__all__ = [
    "HIDDEN_CONFIGS", "DynamicInflowConfig", "GroundEffectConfig", "HiddenConfig",
    "LeverArmConfig", "RotorDroopConfig", "ServoLagConfig", "WakeRecirculationConfig",
    "hidden_from_dict", "DynamicInflow", "GroundEffect", "RotorGovernor", "ServoLag",
    "WakeRecirculation", "build_hidden_effects",
]
