/* LED directions of the active marker (reference §3.3.1.4): four IR LEDs on the faces
 * of a PCB tetrahedron, 110 deg viewing angle each, together covering every direction.
 *
 * Marker body frame: x forward, y right, z down (the IMU's axes). The tetrahedron
 * stands on its base; the outward face normals (unit vectors) are
 *   LED 0: straight up                          ( 0,      0,     -1  )
 *   LED k = 1..3: azimuth 120 (k-1) deg from +x, 19.47 deg below the horizon
 *          (cos az * 2 sqrt(2)/3, sin az * 2 sqrt(2)/3, +1/3)
 * Any two normals have dot product -1/3 (a regular tetrahedron). Change this table
 * (one place) if the hardware differs.
 */
#ifndef AW_MARKER_LEDS_H
#define AW_MARKER_LEDS_H

#define MARKER_LEDS 4

extern const float marker_led_dir[MARKER_LEDS][3];

/* The LED whose direction has the largest dot product with v (body frame). */
unsigned marker_led_facing(const float v_body[3]);

#endif
