/* Three-component float vector helpers for the geometry and the CPU reference.
 * Each is one plain expression so the operation order is the obvious one. */
#ifndef SPM_GEOMETRY_VEC3_H
#define SPM_GEOMETRY_VEC3_H
#include <math.h>

static inline void v3_sub(float o[3], const float a[3], const float b[3])
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

static inline void v3_cross(float o[3], const float a[3], const float b[3])
{
    float x = a[1] * b[2] - a[2] * b[1];
    float y = a[2] * b[0] - a[0] * b[2];
    float z = a[0] * b[1] - a[1] * b[0];
    o[0] = x;
    o[1] = y;
    o[2] = z;
}

static inline float v3_dot(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* o = a + b * s */
static inline void v3_madd(float o[3], const float a[3], const float b[3], float s)
{
    o[0] = a[0] + b[0] * s;
    o[1] = a[1] + b[1] * s;
    o[2] = a[2] + b[2] * s;
}

/* MiniLight's "unitized": v times the reciprocal length (zero stays zero). */
static inline void v3_normalise(float o[3], const float v[3])
{
    float len = sqrtf(v3_dot(v, v));
    float inv = len != 0.0f ? 1.0f / len : 0.0f;
    o[0] = v[0] * inv;
    o[1] = v[1] * inv;
    o[2] = v[2] * inv;
}
#endif
