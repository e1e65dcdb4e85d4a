/* The material contract's pieces the tests of types share: a flat hit and
 * a light sample's value (host/cpu/refcpu_bsdf.h). */
#ifndef SPM_BSDF_TESTLIB_H
#define SPM_BSDF_TESTLIB_H
#include "refcpu_bsdf.h"

/* a flat hit, normal +z, viewed from wo */
static inline spm_ref_hit bt_hit_from(const float wo[3])
{
    spm_ref_hit h = {{0, 0, 1}, {1, 0, 0}, {-wo[0], -wo[1], -wo[2]}, {0, 0, 1}, {0, 0, 1}, 0};
    return h;
}

/* f |cos_i| of an eval, in its own rounding order */
static inline float bt_value(spm_ref_eval e)
{
    return e.k * e.f / e.div / e.post;
}
#endif
