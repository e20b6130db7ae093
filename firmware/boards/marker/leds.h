/* LED directions of the active marker (reference §3.3.1.4): four IR LEDs on the faces
 * of a PCB tetrahedron, 110 deg viewing angle each, together covering every direction.
 *
 * Marker body frame: x forward, y right, z down (the IMU's axes). The outward face
 * normals (unit vectors) point along cube diagonals:
 *   LED 0 (+1, +1, +1) / sqrt 3     LED 1 (+1, -1, -1) / sqrt 3
 *   LED 2 (-1, +1, -1) / sqrt 3     LED 3 (-1, -1, +1) / sqrt 3
 * Any two normals have dot product -1/3 (a regular tetrahedron). The host's tracker
 * (airwake.tracking.marker) and the simulator's optics use this table; a test keeps the
 * three equal. Change all three if the hardware differs.
 */
#ifndef AW_MARKER_LEDS_H
#define AW_MARKER_LEDS_H

#define MARKER_LEDS 4

extern const float marker_led_dir[MARKER_LEDS][3];

/* The LED whose direction has the largest dot product with v (body frame). */
unsigned marker_led_facing(const float v_body[3]);

#endif
