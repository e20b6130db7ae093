"""The active marker's LED geometry (§3.3.1.4): four LEDs on the faces of a PCB
tetrahedron, axes = outward face normals in the marker (IMU) frame, LED centres
`LED_RADIUS_M` from the marker centre along them. The simulator's optics use the same
numbers (`hil_sim.sensors.losa.MARKER_LED_DIRECTIONS`, `LosaConfig.led_radius_m`; a test
keeps them equal)."""

from __future__ import annotations

import numpy as np

LED_DIRECTIONS_BODY = np.array(
    [[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]
) / np.sqrt(3.0)
LED_RADIUS_M = 0.02
NO_LED = 255  # `marker_attitude.active_led` when none is lit


def led_lever_arms_body_m(active_led: np.ndarray) -> np.ndarray:
    """(N, 3) lit-LED positions from the marker centre in body axes; NaN where none."""
    led = np.asarray(active_led).astype(int)
    lit = (led >= 0) & (led < len(LED_DIRECTIONS_BODY))
    arms = np.full((led.size, 3), np.nan)
    arms[lit] = LED_RADIUS_M * LED_DIRECTIONS_BODY[led[lit]]
    return arms
