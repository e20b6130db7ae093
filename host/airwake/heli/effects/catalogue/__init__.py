"""The catalogue: physical effects the baseline model (Table 5.1/5.2) lacks. They are
registered with the package's own effects when `airwake.heli.effects` is imported, so a
spec can name them and `airwake model add NAME` can fit them.

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
    advance_cyclic       blade_pitch   cyclic trim linear in the in-plane advance ratio
    advance_torque       forces        rotor torque in the advance ratio squared (a yaw couple)
    yaw_gyro             inputs        the gyro's share of the yaw damping on the inertial rate

Each effect is "off" at its documented parameter values (or when absent); the
discrepancy workflow (`airwake model diagnose`) knows how to screen and fit each.
"""

from airwake.heli.effects.catalogue.accel_bias import AccelBias
from airwake.heli.effects.catalogue.accel_misalignment import AccelMisalignment
from airwake.heli.effects.catalogue.advance_cyclic import AdvanceCyclic
from airwake.heli.effects.catalogue.advance_torque import AdvanceTorque
from airwake.heli.effects.catalogue.cg_offset import CgOffset
from airwake.heli.effects.catalogue.dynamic_inflow import DynamicInflow
from airwake.heli.effects.catalogue.fuselage_drag_error import FuselageDragError
from airwake.heli.effects.catalogue.ground_effect import GroundEffect
from airwake.heli.effects.catalogue.imu_lever_arm import ImuLeverArm
from airwake.heli.effects.catalogue.rotor_droop import RotorDroop
from airwake.heli.effects.catalogue.servo_lag import ServoLag
from airwake.heli.effects.catalogue.wake_recirculation import WakeRecirculation
from airwake.heli.effects.catalogue.yaw_gyro import YawGyro

CATALOGUE_EFFECTS = (
    GroundEffect, ImuLeverArm, ServoLag, RotorDroop, DynamicInflow, WakeRecirculation,
    AccelBias, AccelMisalignment, CgOffset, FuselageDragError, AdvanceCyclic,
    AdvanceTorque, YawGyro,
)

__all__ = [
    "CATALOGUE_EFFECTS", "AccelBias", "AccelMisalignment", "AdvanceCyclic", "AdvanceTorque",
    "CgOffset",
    "DynamicInflow", "FuselageDragError", "GroundEffect", "ImuLeverArm", "RotorDroop", "ServoLag",
    "WakeRecirculation", "YawGyro",
]
