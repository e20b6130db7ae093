/* Quaternion maths for the marker attitude (reference eq 3.9), single precision.
 *
 * Convention: Hamilton product, scalar first q = (w, x, y, z). A quaternion q maps
 * body-frame vectors to the reference frame: v_ref = q (x) v_body (x) q*. With body
 * angular rates omega the kinematics are (eq 3.9)
 *     dq/dt = 1/2 q (x) (0, omega)
 * The reference prints the same 4x4 matrix with the scalar as its last component.
 */
#ifndef AW_QUAT_H
#define AW_QUAT_H

typedef struct {
    float w, x, y, z;
} quat_t;

quat_t quat_identity(void);
quat_t quat_mul(quat_t a, quat_t b);
quat_t quat_conj(quat_t q);
/* Exact normalisation (one sqrtf). */
quat_t quat_normalize(quat_t q);
/* One Newton step towards unit norm, no sqrt: for |q| within ~1e-3 of 1 (after an
 * integration step) it leaves an error of the order of the square of the input's. */
quat_t quat_renormalize(quat_t q);
/* v_ref = q v_body q*; out may alias v. */
void quat_rotate(quat_t q, const float v[3], float out[3]);
/* v_body = q* v_ref q; out may alias v. */
void quat_rotate_inv(quat_t q, const float v[3], float out[3]);
/* Integrate eq 3.9 over dt with constant body rates: q (x) exp(omega dt / 2), the
 * exponential by its series to 4th order in |omega dt| (error < 2e-9 for
 * |omega dt| < 0.2 rad, i.e. 90 rad/s at 450 Hz), then renormalised. */
quat_t quat_integrate(quat_t q, const float omega_rad_s[3], float dt_s);

#endif
