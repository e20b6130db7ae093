/* Quaternion maths, see quat.h. */
#include "quat.h"

#include <math.h>

quat_t quat_identity(void)
{
    const quat_t q = {1.0f, 0.0f, 0.0f, 0.0f};
    return q;
}

quat_t quat_mul(quat_t a, quat_t b)
{
    const quat_t r = {
        a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
        a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
        a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
        a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
    };
    return r;
}

quat_t quat_conj(quat_t q)
{
    const quat_t r = {q.w, -q.x, -q.y, -q.z};
    return r;
}

quat_t quat_normalize(quat_t q)
{
    const float n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
    if (!(n2 > 0.0f)) {
        return quat_identity();
    }
    const float k = 1.0f / sqrtf(n2);
    const quat_t r = {q.w * k, q.x * k, q.y * k, q.z * k};
    return r;
}

quat_t quat_renormalize(quat_t q)
{
    /* 1/sqrt(n2) ~ (3 - n2) / 2 near n2 = 1 */
    const float n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
    const float k = 0.5f * (3.0f - n2);
    const quat_t r = {q.w * k, q.x * k, q.y * k, q.z * k};
    return r;
}

void quat_rotate(quat_t q, const float v[3], float out[3])
{
    /* v' = v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z) */
    const float tx = 2.0f * (q.y * v[2] - q.z * v[1]);
    const float ty = 2.0f * (q.z * v[0] - q.x * v[2]);
    const float tz = 2.0f * (q.x * v[1] - q.y * v[0]);
    const float r0 = v[0] + q.w * tx + (q.y * tz - q.z * ty);
    const float r1 = v[1] + q.w * ty + (q.z * tx - q.x * tz);
    const float r2 = v[2] + q.w * tz + (q.x * ty - q.y * tx);
    out[0] = r0;
    out[1] = r1;
    out[2] = r2;
}

void quat_rotate_inv(quat_t q, const float v[3], float out[3])
{
    quat_rotate(quat_conj(q), v, out);
}

quat_t quat_integrate(quat_t q, const float omega_rad_s[3], float dt_s)
{
    const float hx = omega_rad_s[0] * dt_s;
    const float hy = omega_rad_s[1] * dt_s;
    const float hz = omega_rad_s[2] * dt_s;
    const float t2 = hx * hx + hy * hy + hz * hz; /* theta^2 */
    /* cos(theta/2) and sin(theta/2)/theta by their series */
    const float c = 1.0f - t2 * (1.0f / 8.0f) + t2 * t2 * (1.0f / 384.0f);
    const float s = 0.5f - t2 * (1.0f / 48.0f) + t2 * t2 * (1.0f / 3840.0f);
    const quat_t dq = {c, s * hx, s * hy, s * hz};
    return quat_renormalize(quat_mul(q, dq));
}
