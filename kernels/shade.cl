/* The shade stage: one kernel per spectral method, each over a list of path
 * indices (a level's bucket, or all paths), writing XYZ per path. Every kernel
 * is the one body in shade_body.clh at a fixed vector width; the host compiles
 * only what the scene and mode use (-D below, as the mode descriptors in
 * host/spectral/modes.c ask for them; n: vectors per colour of its shade table):
 *   SPM_SHADE_L<l>_NV=n  level l: 80>>l bins as 5 vectors of 16>>l floats
 *                        (n = 5; mlc: 5 + the spike lanes as more vectors)
 *   SPM_SHADE_TRUTH_NV=n 400 1 nm bins = 25 x float16
 *   SPM_SHADE_RGB        3 components in a float4, XYZ by the sRGB matrix
 *   SPM_SHADE_HERO       4 wavelengths in a float4, gathered from level 0
 * Contraction is left on: fma() is what the body asks for anyway. */
#include "spm_shared.h"
#include "spm_rng.h"
#include "spm_kernel_args.h"

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
#define SB_W 8
#define SB_NV SPM_SHADE_L1_NV
#include "shade_body.clh"
#endif
#ifdef SPM_SHADE_L2_NV
#define SB_NAME spm_shade_l2
#define SB_W 4
#define SB_NV SPM_SHADE_L2_NV
#include "shade_body.clh"
#endif
#ifdef SPM_SHADE_L3_NV
#define SB_NAME spm_shade_l3
#define SB_W 2
#define SB_NV SPM_SHADE_L3_NV
#include "shade_body.clh"
#endif

#ifdef SPM_SHADE_TRUTH_NV
#define SB_NAME spm_shade_truth
#define SB_W 16
#define SB_NV SPM_SHADE_TRUTH_NV
#include "shade_body.clh"
#endif

#ifdef SPM_SHADE_RGB
#define SB_NAME spm_shade_rgb
#define SB_W 4
#define SB_NV 1
#include "shade_body.clh"
#endif

#ifdef SPM_SHADE_HERO
/* Lane wavelength from a uniform x: the 1 nm bin j with cdf[j] <= x < cdf[j+1],
 * the offset f in it (the CDF is linear inside), the level-0 bin j/5, and the
 * lane's XYZ weight: CMF(380+j+f) / pdf / lanes (spectra piecewise constant). */
inline void hero_lane(__global const float *hero, float x, uint *bin, float4 *w)
{
#pragma OPENCL FP_CONTRACT OFF /* rounds as the CPU reference's lerp */
    __global const float *cdf = hero + SPM_HERO_CDF;
    uint lo = 0, hi = SPM_TRUTH_BINS;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) >> 1;
        if (cdf[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    float width = cdf[lo + 1] - cdf[lo];
    float f = width > 0.0f ? clamp((x - cdf[lo]) / width, 0.0f, 1.0f) : 0.0f;
    float pdf = hero[SPM_HERO_PDF + lo];
    float wt[3];
    for (int ch = 0; ch < 3; ch++) {
        __global const float *cp = hero + SPM_HERO_CMF + ch * (SPM_TRUTH_BINS + 1);
        float cmf = cp[lo] + (cp[lo + 1] - cp[lo]) * f;
        wt[ch] = pdf > 0.0f ? cmf / pdf / (float)SPM_HERO_LANES : 0.0f;
    }
    *bin = lo / (SPM_TRUTH_BINS / SPM_L0_BINS);
    *w = (float4)(wt[0], wt[1], wt[2], 0.0f);
}

#define SB_NAME spm_shade_hero
#define SB_W 4
#define SB_NV 1
#define SB_EXTRA_ARGS , SPM_SHADE_PATH_ARGS(SPM_KERNEL_PARAM, SPM_COMMA)
#define SB_PREPARE                                                                     \
    uint hb[4];                                                                        \
    float4 hw[4];                                                                      \
    {                                                                                  \
        float u = spm_rng(seed, first_pixel + pi / spp, first_sample + pi % spp, SPM_DIM_HERO); \
        for (int l = 0; l < SPM_HERO_LANES; l++) {                                     \
            float x = u + (float)l / (float)SPM_HERO_LANES;                                   \
            hero_lane(extra, x >= 1.0f ? x - 1.0f : x, &hb[l], &hw[l]);                 \
        }                                                                              \
    }                                                                                  \
    float4 hcmf[3] = {(float4)(hw[0].x, hw[1].x, hw[2].x, hw[3].x),                     \
                      (float4)(hw[0].y, hw[1].y, hw[2].y, hw[3].y),                     \
                      (float4)(hw[0].z, hw[1].z, hw[2].z, hw[3].z)};
#define SB_LOAD(c, k)                                                                  \
    ((float4)(tab[(size_t)(c) * SPM_L0_BINS + hb[0]], tab[(size_t)(c) * SPM_L0_BINS + hb[1]], \
              tab[(size_t)(c) * SPM_L0_BINS + hb[2]], tab[(size_t)(c) * SPM_L0_BINS + hb[3]]))
#define SB_CMF(ch, k) hcmf[ch]
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
        __global const float *s = &xyz[3 * ((size_t)p * spp + k)];
        float x = s[0], y = s[1], z = s[2];
        if (finite_bits(x) && finite_bits(y) && finite_bits(z)) {
            sx += x;
            sy += y;
            sz += z;
        } else {
            bad++;
        }
    }
    pass_xyz[3 * p + 0] = sx;
    pass_xyz[3 * p + 1] = sy;
    pass_xyz[3 * p + 2] = sz;
    if (bad)
        atomic_add(&counters[SPM_COUNTER_NONFINITE], bad);
}
