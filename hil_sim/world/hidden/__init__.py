"""Truth-only ("hidden") effects: physics the host's helicopter model does not contain.

They exist so that the discrepancy workflow has something real to find (MISSION.md §3.6).
Each is written here from a published formulation *other* than the one the host's
discrepancy catalogue uses for the same phenomenon, with its own parameters and
defaults, so that "adding the catalogue effect fixes the truth" is a test of the
catalogue and not of a copy of it (tests/hil_sim/test_hidden_independence.py keeps
hil_sim from importing the catalogue). The model-side ones are `Effect` subclasses
plugged into the truth `HeliModel` pipeline; they are deliberately **not registered** in
the host's effect registry, so no host tool (catalogue, spec loader, the discrepancy
candidates) can build a model with them.

    [hidden.<name>]          class / where                 physics (source)
    ground_effect            GroundEffect (inflow)         Hayden 1976 power-ratio fit, thrust-
                                                           consistent; wake-footprint fade in
                                                           forward flight; finite deck (run.py)
    servo_lag                SecondOrderServo (inputs)     delay + deadband + 2nd-order servo
                                                           with slew-rate limit (Tischler &
                                                           Remple 2012 actuator form)
    rotor_droop              ElectricDriveGovernor         battery/ESC/brushless motor torque-
                             (rotor_speed)                 speed line + PI governor, throttle
                                                           ceiling, back-calculation anti-windup
    dynamic_inflow           PittPetersDynamicInflow       3-state Pitt & Peters 1981 / Peters &
                             (inflow, last)                HaQuang 1988 (M, L(chi), load feedback)
    wake_recirculation       GroundVortexRecirculation     line ground vortex + image below the
                             (inflow)                      disk (Curtiss et al. 1984 picture)
    lever_arm                sensor side (run.py)          the IMU at r from the CG
    vibration_rectification  sensor side (sensor_side.py)  accelerometer K2 rectification,
                                                           b (Omega/Omega_ref)^n (IEEE 1293)
    input_time_skew          sensor side (sensor_side.py)  pilot-input stream skewed vs the INS

Scenario tables (`[hidden.<name>]`) are read into the `*Config` dataclasses of
`hil_sim.world.hidden.config`; `build_hidden_effects` turns the model-side ones into
effect instances in pipeline order. docs/scenarios.md gives each effect's physics,
source, parameters and its signature in the flight table.
"""

from hil_sim.world.hidden.config import (
    HIDDEN_CONFIGS,
    DynamicInflowConfig,
    GroundEffectConfig,
    HiddenConfig,
    InputTimeSkewConfig,
    LeverArmConfig,
    RotorDroopConfig,
    ServoLagConfig,
    VibrationRectificationConfig,
    WakeRecirculationConfig,
    hidden_from_dict,
)
from hil_sim.world.hidden.dynamic_inflow import PittPetersDynamicInflow
from hil_sim.world.hidden.effects import (
    HEIGHT_EFFECTS,
    HIDDEN_EFFECT_CLASSES,
    build_hidden_effects,
)
from hil_sim.world.hidden.electric_drive import ElectricDriveGovernor
from hil_sim.world.hidden.ground_effect import GroundEffect
from hil_sim.world.hidden.ground_vortex import GroundVortexRecirculation
from hil_sim.world.hidden.servo import SecondOrderServo

__all__ = [
    "HEIGHT_EFFECTS", "HIDDEN_CONFIGS", "HIDDEN_EFFECT_CLASSES", "DynamicInflowConfig",
    "ElectricDriveGovernor", "GroundEffect", "GroundEffectConfig",
    "GroundVortexRecirculation", "HiddenConfig", "InputTimeSkewConfig", "LeverArmConfig",
    "PittPetersDynamicInflow", "RotorDroopConfig", "SecondOrderServo", "ServoLagConfig",
    "VibrationRectificationConfig", "WakeRecirculationConfig", "build_hidden_effects",
    "hidden_from_dict",
]
