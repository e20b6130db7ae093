/* Quaternion maths (eq 3.9 integration, rotations). */
#include <math.h>

#include "quat.h"
#include "test_algos.h"

#define PI_F 3.14159265f

/* A constant rate about z for 1 s must give exactly that rotation angle. */
static void test_quat_integrate_constant_rate_gives_exact_angle(void)
{
    quat_t q = quat_identity();
    const float w[3] = {0.0f, 0.0f, 1.2f};
    for (int i = 0; i < 450; i++) {
        q = quat_integrate(q, w, 1.0f / 450.0f);
    }
    CHECK_NEAR(q.w, cos(0.6), 2e-5);
    CHECK_NEAR(q.z, sin(0.6), 2e-5);
    CHECK_NEAR(q.x, 0.0, 1e-7);
}

/* Long runs must not drift off the unit sphere (the sqrt-free renormalisation). */
static void test_quat_norm_stays_one_over_a_million_steps(void)
{
    quat_t q = quat_identity();
    const float w[3] = {3.0f, -2.0f, 5.0f};
    for (int i = 0; i < 1000000; i++) {
        q = quat_integrate(q, w, 1.0f / 450.0f);
    }
    const double n = sqrt((double)q.w * q.w + (double)q.x * q.x + (double)q.y * q.y + (double)q.z * q.z);
    CHECK_NEAR(n, 1.0, 1e-5);
}

/* Body rates: rotating about body x then body y must compose as q = qx (x) qy. */
static void test_quat_body_rates_compose_on_the_right(void)
{
    quat_t q = quat_identity();
    const float wx[3] = {PI_F / 2.0f, 0.0f, 0.0f};
    const float wy[3] = {0.0f, PI_F / 2.0f, 0.0f};
    for (int i = 0; i < 100; i++) {
        q = quat_integrate(q, wx, 0.01f);
    }
    for (int i = 0; i < 100; i++) {
        q = quat_integrate(q, wy, 0.01f);
    }
    /* body x-axis after: rotate (1,0,0) by q */
    const float ex[3] = {1.0f, 0.0f, 0.0f};
    float r[3];
    quat_rotate(q, ex, r);
    /* Rx(90) Ry(90) ex = Rx(90) (0,0,-1) = (0,1,0) */
    CHECK_NEAR(r[0], 0.0, 1e-4);
    CHECK_NEAR(r[1], 1.0, 1e-4);
    CHECK_NEAR(r[2], 0.0, 1e-4);
}

/* rotate_inv must undo rotate (body <-> reference). */
static void test_quat_rotate_inv_undoes_rotate(void)
{
    const quat_t q = quat_normalize((quat_t){0.3f, -0.5f, 0.7f, 0.1f});
    const float v[3] = {1.5f, -2.0f, 0.25f};
    float a[3], b[3];
    quat_rotate(q, v, a);
    quat_rotate_inv(q, a, b);
    for (int i = 0; i < 3; i++) {
        CHECK_NEAR(b[i], v[i], 1e-5);
    }
    CHECK_NEAR(sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), 1e-5);
}

/* A zero quaternion must not become NaN when normalised. */
static void test_quat_normalize_zero_gives_identity(void)
{
    const quat_t q = quat_normalize((quat_t){0.0f, 0.0f, 0.0f, 0.0f});
    CHECK(q.w == 1.0f && q.x == 0.0f && q.y == 0.0f && q.z == 0.0f);
}

int main(void)
{
    RUN(test_quat_integrate_constant_rate_gives_exact_angle);
    RUN(test_quat_norm_stays_one_over_a_million_steps);
    RUN(test_quat_body_rates_compose_on_the_right);
    RUN(test_quat_rotate_inv_undoes_rotate);
    RUN(test_quat_normalize_zero_gives_identity);
    return ALGO_TEST_EXIT();
}
