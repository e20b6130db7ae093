"""Simulated instruments: each turns truth kinematics into what the real device emits.

Every sensor takes a config dataclass (defaults from datasheets, see docs/sensors.md)
and `rng=np.random.Generator`, and gives (1) measured values at its own sample
instants as numpy arrays (`measure(...)`, the flight-table fast path) and (2) the
time-stamped byte or edge stream the real device emits (`stream(...)`), for the
native boards:

- `vn200.Vn200`              VN200 INS, binary output packets (rover and base)
- `rtk.RtkReceiver`          Piksi RTK baseline, SBP frames (`sbp` package)
- `rc.RcReceiver`            5 RC channels, PWM widths and edges; `pwm_to_blade_pitch`
- `rc.TailServoPwm`          heading-hold gyro -> tail servo PWM (rover)
- `rotor.RotorTachometer`    IR blade-passage pulses -> rotor speed
- `losa.LosaOptics`          marker LED through three slots onto 4 x 128 pixels
- `marker_imu.MarkerImu`     MPU-9250 gyro/accel/mag, register blocks
- `anemometer.Anemometer`    Young 81000 class, motion-affected, ASCII/analog

Shared: `imu` (IMU error model with rotor vibration), `noise`, `streams`, `geodesy`,
`config` (config dataclasses from scenario tables).
"""
