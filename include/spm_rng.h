/* Counter-based random numbers keyed by (seed, pixel, sample, dimension).
 * Integer-only, so the OpenCL kernels and the CPU reference produce the same
 * bits; the float conversion is exact (24 random bits times 2^-24). */
#ifndef SPM_RNG_H
#define SPM_RNG_H
#include "spm_shared.h"

/* Dimensions: 0, 1 camera jitter; each vertex j uses SPM_DIM_VERTEX(j) + 0..5
 * (MiniLight's transport: the same for every type); types draw from their own
 * range (SPM_DIM_TYPE below). */
#define SPM_DIM_CAM_X 0u
#define SPM_DIM_CAM_Y 1u
#define SPM_DIMS_PER_VERTEX 6u
#define SPM_DIM_VERTEX(j) (2u + SPM_DIMS_PER_VERTEX * (spm_u32)(j))
#define SPM_DIM_EMITTER 0u      /* which emitter */
#define SPM_DIM_EPOINT_A 1u     /* point on it */
#define SPM_DIM_EPOINT_B 2u
#define SPM_DIM_RR 3u           /* Russian roulette */
#define SPM_DIM_DIR_A 4u        /* cosine-weighted direction */
#define SPM_DIM_DIR_B 5u
#define SPM_DIM_HERO 0x7fffff00u
/* A light subpath (--integrator light): the light by vertex 0's
 * SPM_DIM_EMITTER, its ray's four numbers and the lens point of the light's
 * own vertex from the vertex slot after the last (no path reaches it); a
 * surface vertex j's lens point from its SPM_DIM_EPOINT_A/B (it takes no
 * light sample), its bounce and roulette from its own as on a camera path. */
#define SPM_DIM_LT_EMIT SPM_DIM_VERTEX(SPM_MAX_DEPTH)
#define SPM_DIM_LT_LENS (SPM_DIM_VERTEX(SPM_MAX_DEPTH) + 4u)  /* hero wavelength offset, shade stage only */
/* a thin lens's point on its disk: dimensions of their own, far above the
 * vertices' and the types', so a pinhole camera's paths draw what they drew */
#define SPM_DIM_LENS_A 0x7ffffe00u
#define SPM_DIM_LENS_B 0x7ffffe01u

/* Dimensions of material and emitter types (host/scene/materials.c), in their
 * own range, so that a type's draws never shift the ones above: every
 * Lambertian path keeps the numbers it has always drawn. Vertex j has
 * SPM_TYPE_DIMS_PER_VERTEX of them, split in two: the material type met at
 * the vertex draws SPM_DIM_TYPE(j, k), k < SPM_TYPE_MAT_DIMS, and the emitter
 * type sampled for the vertex's light (usually another material's) draws
 * SPM_DIM_EMIT_TYPE(j, k), k < SPM_TYPE_EMIT_DIMS, so the two never share a
 * number. A type claims k = 0 .. n-1 by giving n as its descriptor's rng_dims
 * (at most its half: test_material_types checks) and naming its offsets
 * SPM_DIM_<TYPE>_<WHAT> = 0, 1, ... beside its code. One material is met at a
 * vertex, so material types share their half (likewise emitter types); a
 * type that needs more raises SPM_TYPE_DIMS_PER_VERTEX, which moves no
 * existing dimension. The range starts far above the vertices' and far below
 * hero's: SPM_DIM_VERTEX(SPM_MAX_DEPTH) = 386 <= 2^30, and
 * 2^30 + SPM_MAX_DEPTH * SPM_TYPE_DIMS_PER_VERTEX < SPM_DIM_HERO. */
#define SPM_DIM_TYPE_BASE 0x40000000u
#define SPM_TYPE_DIMS_PER_VERTEX 8u
#define SPM_TYPE_MAT_DIMS 4u
#define SPM_TYPE_EMIT_DIMS (SPM_TYPE_DIMS_PER_VERTEX - SPM_TYPE_MAT_DIMS)
#define SPM_DIM_TYPE(j, k) (SPM_DIM_TYPE_BASE + SPM_TYPE_DIMS_PER_VERTEX * (spm_u32)(j) + (spm_u32)(k))
#define SPM_DIM_EMIT_TYPE(j, k) SPM_DIM_TYPE(j, SPM_TYPE_MAT_DIMS + (spm_u32)(k))
/* the conductor's (host/scene/materials.c): its rough lobe's visible normal */
#define SPM_DIM_COND_M_A 0u
#define SPM_DIM_COND_M_B 1u
/* the coated type's (kernels/coated.clh): its lobe choice, its rough
 * coating's visible normal */
#define SPM_DIM_COAT_LOBE 0u
#define SPM_DIM_COAT_M_A 1u
#define SPM_DIM_COAT_M_B 2u
/* the dielectric's: its rough lobe's visible normal, then the choice
 * between reflection and refraction (by the Fresnel reflectance); at a
 * path's first dispersive vertex, the wavelength it commits to (the
 * pixel's rotation drawn at vertex 0's: spm_rng_stratified_u32) */
#define SPM_DIM_DIEL_M_A 0u
#define SPM_DIM_DIEL_M_B 1u
#define SPM_DIM_DIEL_CHOICE 2u
#define SPM_DIM_DIEL_LAMBDA 3u
/* A texture lookup's range (spm_shared.h SPM_TEX_GRID): vertex j draws
 * SPM_DIM_TEX(j, 0 .. 3), the level, the texel along x and along y, the grid
 * corner; above every type's range (2^30 + SPM_MAX_DEPTH * 8) and below the
 * lens's and hero's. */
#define SPM_DIM_TEX_BASE 0x60000000u
#define SPM_DIM_TEX(j, k) (SPM_DIM_TEX_BASE + 4u * (spm_u32)(j) + (spm_u32)(k))
/* The metallic-roughness mix's choice at vertex j (spm_shared.h SPM_MIX_*):
 * its own dimension, between the textures' and the environment map's. */
#define SPM_DIM_MIX(j) (0x68000000u + (spm_u32)(j))
/* The environment map's lookup (kernels/light_envmap.clh): the texel drawn
 * along u and along v, SPM_DIM_ENV(j, 0 .. 1), and the node of the texel's
 * palette cell, SPM_DIM_ENV(j, 2), by the light sample at vertex j or by the
 * ray escaping in vertex j's place (the two never meet at one j); above the
 * textures' range, below the lens's. */
#define SPM_DIM_ENV_BASE 0x70000000u
#define SPM_DIM_ENV(j, k) (SPM_DIM_ENV_BASE + 3u * (spm_u32)(j) + (spm_u32)(k))
#define SPM_DIM_ENV_NODE 2u
/* A textured emitter's lookup (kernels/light_area.clh emit_texture): the texel
 * along x and along y and the grid corner, SPM_DIM_ETEX(j, 0 .. 2) where the
 * ray of vertex j - 1 (or the camera's, j = 0) hits it, SPM_DIM_ETEX(j, 3 .. 5)
 * at the point vertex j's light sample draws on it (a vertex can be both),
 * j = SPM_MAX_DEPTH at a light subpath's start; between the textures' range
 * and the map's. */
#define SPM_DIM_ETEX_BASE 0x68000000u
#define SPM_DIM_ETEX(j, k) (SPM_DIM_ETEX_BASE + 8u * (spm_u32)(j) + (spm_u32)(k))
#define SPM_DIM_ETEX_NEE 3u

/* "lowbias32" integer mixer (Wellons): full avalanche, cheap. Its steps on x
 * of any unsigned 32-bit integer type (the kernels also mix 16 keys at once). */
#define SPM_MIX32_STEPS(x)   \
    do {                     \
        (x) ^= (x) >> 16;    \
        (x) *= 0x7feb352dU;  \
        (x) ^= (x) >> 15;    \
        (x) *= 0x846ca68bU;  \
        (x) ^= (x) >> 16;    \
    } while (0)

SPM_INLINE spm_u32 spm_mix32(spm_u32 x)
{
    SPM_MIX32_STEPS(x);
    return x;
}

/* The key's hash into h: pixel, sample and dim (and h) may be vectors, which
 * the kernels mix without a call (a 16-wide argument changes the x86 ABI on
 * CPUs without AVX-512). */
#define SPM_RNG_HASH_STEPS(h, seed, pixel, sample, dim)  \
    do {                                                 \
        (h) = spm_mix32((seed) ^ 0x9e3779b9U) ^ (pixel); \
        SPM_MIX32_STEPS(h);                              \
        (h) ^= (sample) * 0x85ebca6bU;                   \
        SPM_MIX32_STEPS(h);                              \
        (h) ^= (dim) * 0xc2b2ae35U;                      \
        SPM_MIX32_STEPS(h);                              \
    } while (0)
/* The 24 random bits of a hash to a float in [0, 1) (exact). */
#define SPM_RNG_UNIT (1.0f / 16777216.0f)

SPM_INLINE spm_u32 spm_rng_u32(spm_u32 seed, spm_u32 pixel, spm_u32 sample, spm_u32 dim)
{
    spm_u32 h;
    SPM_RNG_HASH_STEPS(h, seed, pixel, sample, dim);
    return h;
}

/* The stochastic opacity's number for triangle tri met by the ray of origin
 * o and direction d (their floats' bits): the same on both backends for the
 * same ray, whatever the traversal's order (spm_shared.h SPM_ALPHA_BLEND).
 * In the kernels of scenes with opacity only. */
#if !defined(__OPENCL_VERSION__) || defined(SPM_WITH_ALPHA)
SPM_INLINE spm_u32 spm_alpha_hash(spm_u32 tri, spm_u32 ox, spm_u32 oy, spm_u32 oz, spm_u32 dx,
                                  spm_u32 dy, spm_u32 dz)
{
    spm_u32 h = spm_mix32(tri ^ 0x9e3779b9U);
    h = spm_mix32(h ^ ox) ^ oy;
    h = spm_mix32(h) ^ oz;
    h = spm_mix32(h) ^ dx;
    h = spm_mix32(h) ^ dy;
    h = spm_mix32(h) ^ dz;
    return spm_mix32(h);
}
#endif

/* Uniform in [0, 1). */
SPM_INLINE float spm_rng(spm_u32 seed, spm_u32 pixel, spm_u32 sample, spm_u32 dim)
{
    return (float)(spm_rng_u32(seed, pixel, sample, dim) >> 8) * SPM_RNG_UNIT;
}
/* A committed wavelength, stratified over a pixel's samples: a rotated
 * radical inverse (Cranley-Patterson), h = r + reverse(sample) mod 2^32, r
 * one random rotation per pixel (the sample key SPM_RNG_PIXEL_KEY, which no
 * sample reaches). The first 2^k samples of a pixel fall one in each of 2^k
 * equal strata of [0, 2^32); each sample alone is uniform and independent
 * of its path's other numbers (r is), so the estimate stays unbiased with
 * the uniform pdf. The sample index is the pixel's own, so the strata do not
 * depend on how passes, devices or ranks share the samples. The rotation is
 * drawn at vertex 0's dimension whatever vertex commits: the pixel's
 * samples share one sequence. */
#define SPM_RNG_PIXEL_KEY 0xffffffffu
/* The bits of x reversed, a byte at a time by multiplies (each product mod
 * 2^32 keeps the bits 16-23 read): the shift-and-mask form is recognised by
 * LLVM and becomes its bitreverse intrinsic, which Oclgrind cannot run. */
SPM_INLINE spm_u32 spm_bit_reverse8(spm_u32 b)
{
    return ((((b * 0x0802u) & 0x22110u) | ((b * 0x8020u) & 0x88440u)) * 0x10101u >> 16) & 0xffu;
}
SPM_INLINE spm_u32 spm_bit_reverse32(spm_u32 x)
{
    return spm_bit_reverse8(x & 0xffu) << 24 | spm_bit_reverse8((x >> 8) & 0xffu) << 16 |
           spm_bit_reverse8((x >> 16) & 0xffu) << 8 | spm_bit_reverse8(x >> 24);
}

SPM_INLINE spm_u32 spm_rng_stratified_u32(spm_u32 seed, spm_u32 pixel, spm_u32 sample, spm_u32 dim)
{
    return spm_rng_u32(seed, pixel, SPM_RNG_PIXEL_KEY, dim) + spm_bit_reverse32(sample);
}
#endif
