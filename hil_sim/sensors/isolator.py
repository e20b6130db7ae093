"""An IMU on vibration isolators: the second-order mount between airframe and sensor.

Source: the single-degree-of-freedom base-excitation model of a vibration isolator
(Harris & Piersol, *Harris' Shock and Vibration Handbook*, 5th ed., 2002, ch. 30): the
sensor follows the airframe's motion at the mount through

    H(s) = (2 zeta wn s + wn^2) / (s^2 + 2 zeta wn s + wn^2),

unity at low frequency, resonant near wn (transmissibility ~1 / (2 zeta)), falling as
2 zeta wn / w above it. The mount acts on the translational motion (the specific force
the accelerometers read) and, as the box rocks on its mounts, on the rotation (the rates
the gyros read); the angular acceleration is the derivative of the isolated rates.
Discretised with the bilinear transform at the trajectory's (uniform) rate.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.signal

from hil_sim.sensors.config import check_positive
from hil_sim.world.kinematics import Trajectory


@dataclasses.dataclass(frozen=True)
class IsolatorConfig:
    natural_hz: float = 22.0
    damping: float = 0.15

    def __post_init__(self) -> None:
        check_positive("natural_hz", self.natural_hz)
        check_positive("damping", self.damping)


def transmissibility(config: IsolatorConfig, freq_hz: np.ndarray) -> np.ndarray:
    """|H(j 2 pi f)| of the mount."""
    wn = 2.0 * np.pi * config.natural_hz
    s = 2j * np.pi * np.asarray(freq_hz, float)
    h = (2 * config.damping * wn * s + wn**2) / (s**2 + 2 * config.damping * wn * s + wn**2)
    return np.abs(h)


def isolate(traj: Trajectory, config: IsolatorConfig) -> Trajectory:
    """The trajectory of an isolated sensor: specific force and rates through H(s)."""
    dt = np.diff(traj.t_s)
    if dt.size == 0:
        return traj
    step = float(np.median(dt))
    if np.max(np.abs(dt - step)) > 1e-6 * step:
        raise ValueError("isolate: the trajectory must be uniformly sampled")
    fs = 1.0 / step
    if config.natural_hz > 0.25 * fs:
        raise ValueError(f"isolator natural_hz = {config.natural_hz}: needs a trajectory "
                         f"sampled above {4 * config.natural_hz} Hz (it is {fs:.0f} Hz)")
    wn = 2.0 * np.pi * config.natural_hz
    b, a = scipy.signal.bilinear([2 * config.damping * wn, wn**2],
                                 [1.0, 2 * config.damping * wn, wn**2], fs)
    zi = scipy.signal.lfilter_zi(b, a)

    def filt(x):
        return np.column_stack([scipy.signal.lfilter(b, a, x[:, j], zi=zi * x[0, j])[0]
                                for j in range(x.shape[1])])

    rates = filt(traj.rates_body_rad_s)
    return dataclasses.replace(
        traj, specific_force_body_m_s2=filt(traj.specific_force_body_m_s2),
        rates_body_rad_s=rates, ang_acc_body_rad_s2=np.gradient(rates, traj.t_s, axis=0))
