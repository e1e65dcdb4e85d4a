/* The shade stage: one kernel per spectral method, each over a list of path
 * indices (a level's bucket, or all paths), writing XYZ per path. Every kernel
 * is the one body in shade_body.clh at a fixed vector width; the host compiles
 * only what the scene and mode use (-D below, as the mode descriptors in
 * host/spectral/modes.c ask for them; n: vectors per colour of its shade table):
 *   SPM_SHADE_L<l>_NV=n  level l (spm_shared.h): level 0 the 400 1 nm bins as
 *                        float16 (n = 25: truth, and ml's finest level),
 *                        level l > 0 80>>(l-1) bins as 5 vectors of
 *                        16, 8, 4, 2 floats (n = 5); mlc: the spike lanes
 *                        as more vectors
 *   SPM_SHADE_RGB        3 components in a float4, XYZ by the sRGB matrix
 *   SPM_SHADE_HERO       4 wavelengths in a float4, gathered from the 1 nm rows
 * Contraction is left on: fma() is what the body asks for anyway. */
#include "spm_shared.h"
#include "spm_rng.h"
#include "spm_kernel_args.h"

/* Floats of a path's record and of a pass pixel: XYZ, then with
 * -DSPM_SPEC_BINS=n the n spectral bins (the host sets both). */
#ifndef SPM_PATH_CH
#define SPM_PATH_CH 3
#endif

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define HSUM2(v) ((v).x + (v).y)
#define HSUM4(v) HSUM2((v).lo + (v).hi)
#define HSUM8(v) HSUM4((v).lo + (v).hi)
#define HSUM16(v) HSUM8((v).lo + (v).hi)

#ifdef SPM_SHADE_L0_NV
#define SB_NAME spm_shade_l0
#define SB_W 16
#define SB_NV SPM_SHADE_L0_NV
#include "shade_body.clh"
#endif
#ifdef SPM_SHADE_L1_NV
#define SB_NAME spm_shade_l1
#define SB_W 16
#define SB_NV SPM_SHADE_L1_NV
#include "shade_body.clh"
#endif
#ifdef SPM_SHADE_L2_NV
#define SB_NAME spm_shade_l2
#define SB_W 8
#define SB_NV SPM_SHADE_L2_NV
#include "shade_body.clh"
#endif
#ifdef SPM_SHADE_L3_NV
#define SB_NAME spm_shade_l3
#define SB_W 4
#define SB_NV SPM_SHADE_L3_NV
#include "shade_body.clh"
#endif
#ifdef SPM_SHADE_L4_NV
#define SB_NAME spm_shade_l4
#define SB_W 2
#define SB_NV SPM_SHADE_L4_NV
#include "shade_body.clh"
#endif

#ifdef SPM_SHADE_RGB
#define SB_NAME spm_shade_rgb
#define SB_W 4
#define SB_NV 1
#include "shade_body.clh"
#endif

#ifdef SPM_SHADE_HERO
/* The 1 nm bin holding y = t0 + x dt: the direct index of x's cell is that
 * bin or the one before it (host/spectral/tables.c), so one comparison with
 * the next bin's edge settles it. */
inline uint hero_bin(__global const float *hero, float x, float y)
{
    uint j = (uint)hero[SPM_HERO_INDEX + (uint)(x * (float)SPM_HERO_CELLS)];
    j += y >= hero[SPM_HERO_EDGE + j + 1] ? 1u : 0u;
    return min(j, (uint)SPM_TRUTH_BINS - 1u);
}

/* A path's four lanes from its uniform u (host/spectral/tables.c derives the
 * density): x = frac(u + i/4), y = t0 + x dt = tanh(a (l - 538)) at the
 * lane's wavelength l, its 1 nm bin, and the lane's XYZ weights: truth's
 * weights of the bin over the density a (1 - y^2) / dt and the lane count;
 * for spectral records, the factor that turns a lane's radiance into its
 * share of its 5 nm bin's mean: 1 / (density lanes 5 nm). */
inline void hero_lanes(__global const float *hero, float u, uint4 *bin, float4 *w, float4 *sfw)
{
#pragma OPENCL FP_CONTRACT OFF /* rounds as the CPU reference */
    float4 x = u + (float4)(0.0f, 0.25f, 0.5f, 0.75f);
    x = select(x, x - 1.0f, x >= 1.0f);
    float4 y = hero[SPM_HERO_T0] + x * hero[SPM_HERO_DT];
    uint4 b = (uint4)(hero_bin(hero, x.s0, y.s0), hero_bin(hero, x.s1, y.s1),
                      hero_bin(hero, x.s2, y.s2), hero_bin(hero, x.s3, y.s3));
    float4 r = 1.0f / (hero[SPM_HERO_PDFK] * (1.0f - y * y) * (float)SPM_HERO_LANES);
    __global const float *cw = hero + SPM_HERO_CMF;
    float4 c0 = vload4(b.s0, cw) * r.s0, c1 = vload4(b.s1, cw) * r.s1;
    float4 c2 = vload4(b.s2, cw) * r.s2, c3 = vload4(b.s3, cw) * r.s3;
    w[0] = (float4)(c0.x, c1.x, c2.x, c3.x);
    w[1] = (float4)(c0.y, c1.y, c2.y, c3.y);
    w[2] = (float4)(c0.z, c1.z, c2.z, c3.z);
    *bin = b;
    *sfw = r / (float)(SPM_TRUTH_BINS / SPM_NM5_BINS);
}

#define SB_NAME spm_shade_hero
#define SB_W 4
#define SB_NV 1
#define SB_EXTRA_ARGS , SPM_SHADE_PATH_ARGS(SPM_KERNEL_PARAM, SPM_COMMA)
#define SB_PREPARE                                                                     \
    uint4 hb;                                                                          \
    float4 hcmf[3], hs;                                                                \
    hero_lanes(extra, spm_rng(seed, first_pixel + pi / spp, first_sample + pi % spp, SPM_DIM_HERO), \
               &hb, hcmf, &hs);
#define SB_LOAD(c, k)                                                                  \
    ((float4)(tab[(size_t)(c) * SPM_TRUTH_BINS + hb.s0], tab[(size_t)(c) * SPM_TRUTH_BINS + hb.s1], \
              tab[(size_t)(c) * SPM_TRUTH_BINS + hb.s2], tab[(size_t)(c) * SPM_TRUTH_BINS + hb.s3]))
#define SB_CMF(ch, k) hcmf[ch]
#define SB_SPEC_STORE                                                                  \
    for (uint b = 0; b < SPM_SPEC_BINS; b++)                                           \
        so[b] = 0.0f;                                                                  \
    so[hb.s0 / (SPM_TRUTH_BINS / SPM_NM5_BINS)] += lf[0] * hs.s0;                        \
    so[hb.s1 / (SPM_TRUTH_BINS / SPM_NM5_BINS)] += lf[1] * hs.s1;                        \
    so[hb.s2 / (SPM_TRUTH_BINS / SPM_NM5_BINS)] += lf[2] * hs.s2;                        \
    so[hb.s3 / (SPM_TRUTH_BINS / SPM_NM5_BINS)] += lf[3] * hs.s3;
#include "shade_body.clh"
#endif

/* A sample counts unless a component is NaN or infinite; tested on the bits
 * so that no build option can fold the test away. */
inline int finite_bits(float x)
{
    return (as_uint(x) & 0x7f800000u) != 0x7f800000u;
}

/* One work-item per pixel: its spp samples (contiguous) summed in sample
 * order, so the pass image is the same however the work was scheduled.
 * Parameters: spm_kernel_args.h SPM_ACCUM_ARGS. */
__kernel void spm_accumulate(SPM_ACCUM_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint p = get_global_id(0);
    if (p >= npix)
        return;
    float sx = 0.0f, sy = 0.0f, sz = 0.0f;
    uint bad = 0;
    for (uint k = 0; k < spp; k++) {
        __global const float *s = &xyz[SPM_PATH_CH * ((size_t)p * spp + k)];
        float x = s[0], y = s[1], z = s[2];
        if (finite_bits(x) && finite_bits(y) && finite_bits(z)) {
            sx += x;
            sy += y;
            sz += z;
        } else {
            bad++;
        }
    }
    __global float *out = &pass_xyz[SPM_PATH_CH * (size_t)p];
    out[0] = sx;
    out[1] = sy;
    out[2] = sz;
#if SPM_PATH_CH > 3
    /* the bins of the same samples, in the same order */
    for (uint c = 3; c < SPM_PATH_CH; c++) {
        float a = 0.0f;
        for (uint k = 0; k < spp; k++) {
            __global const float *s = &xyz[SPM_PATH_CH * ((size_t)p * spp + k)];
            if (finite_bits(s[0]) && finite_bits(s[1]) && finite_bits(s[2]))
                a += s[c];
        }
        out[c] = a;
    }
#endif
    if (bad)
        atomic_add(&counters[SPM_COUNTER_NONFINITE], bad);
}
