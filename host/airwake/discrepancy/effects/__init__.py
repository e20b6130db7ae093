"""The discrepancy catalogue: physical effects the baseline model lacks, registered in the
helicopter model's effect registry so specs can name them (`airwake model add NAME`).

    ground_effect        inflow        Cheeseman-Bennett image, faded above ~1 diameter
    imu_lever_arm        measurement   a_IMU = a_CG + w_dot x r + w x (w x r)
    servo_lag            inputs        first-order servos (swashplate, tail)
    rotor_droop          rotor_speed   tachometer rotor speed instead of constant Omega*
    dynamic_inflow       inflow        first-order lag of the mean inflow
    wake_recirculation   inflow        ground-vortex re-ingestion at low height and speed
    accel_bias           measurement   constant accelerometer offsets
    accel_misalignment   measurement   rotated accelerometer triad
    cg_offset            measurement   CG position and mass error
    fuselage_drag_error  forces        extra drag areas at a centre of pressure

Each effect is "off" at its documented parameter values (or when absent); the
diagnosis (`airwake.discrepancy.candidates`) knows how to screen and fit each.
"""

from airwake.discrepancy.effects.accel_bias import AccelBias
from airwake.discrepancy.effects.accel_misalignment import AccelMisalignment
from airwake.discrepancy.effects.cg_offset import CgOffset
from airwake.discrepancy.effects.dynamic_inflow import DynamicInflow
from airwake.discrepancy.effects.fuselage_drag_error import FuselageDragError
from airwake.discrepancy.effects.ground_effect import GroundEffect
from airwake.discrepancy.effects.imu_lever_arm import ImuLeverArm
from airwake.discrepancy.effects.rotor_droop import RotorDroop
from airwake.discrepancy.effects.servo_lag import ServoLag
from airwake.discrepancy.effects.wake_recirculation import WakeRecirculation

CATALOGUE_EFFECTS = (
    GroundEffect, ImuLeverArm, ServoLag, RotorDroop, DynamicInflow, WakeRecirculation,
    AccelBias, AccelMisalignment, CgOffset, FuselageDragError,
)

__all__ = [
    "CATALOGUE_EFFECTS", "AccelBias", "AccelMisalignment", "CgOffset", "DynamicInflow",
    "FuselageDragError", "GroundEffect", "ImuLeverArm", "RotorDroop", "ServoLag",
    "WakeRecirculation",
]
