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
/* the material types' shade halves: the spectral factors (kernels/factors.clh;
 * in a program with the trace stage, bsdf.clh has included them already) */
#include "materials.clh"
#include "factors.clh"

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

#ifdef SPM_LIGHT_TRACE
/* One splat sv (SPM_PATH_CH floats) of pixel px into the chunk's list at the
 * next slot of lstat[0] (the pixel in spx, the values in sval); lstat[1]
 * keeps the largest binary exponent of a finite splat's values (frexp's, as
 * host/output/film_splat.c): the fixed-point unit of the chunk. Slots from
 * scap on are counted but not written. */
__attribute__((always_inline)) inline void splat_append(const float *sv, uint px,
                                                       __global uint *spx, __global float *sval,
                                                       __global int *lstat, uint scap)
{
    uint slot = atomic_inc((__global uint *)&lstat[0]);
    int fin = 1, e = -1074;
    for (uint c = 0; c < SPM_PATH_CH; c++) {
        fin &= (as_uint(sv[c]) & 0x7f800000u) != 0x7f800000u;
        int ex;
        if (sv[c] != 0.0f && (frexp(sv[c], &ex), ex > e))
            e = ex;
    }
    if (fin && e > -1074)
        atomic_max(&lstat[1], e);
    if (slot >= scap)
        return;
    spx[slot] = px;
    for (uint c = 0; c < SPM_PATH_CH; c++)
        sval[(size_t)SPM_PATH_CH * slot + c] = sv[c];
}
#endif

#ifdef SPM_WITH_DISPERSION
/* The first vertex of record dx (n vertices) that committed its path to a
 * wavelength: its index (n: none), *b the 1 nm bin, *w 1 / its pdf. */
inline uint disp_commit(__global const spm_vertex_ext *dx, uint npaths, uint n, uint *b, float *w)
{
    for (uint j = 0; j < n; j++) {
        spm_vertex_ext x = dx[(size_t)j * npaths];
        *b = SPM_VX_LAMBDA(x);
        *w = x.light;
        if (*b != SPM_NONE)
            return j;
    }
    return n;
}

/* Radiance dl of 1 nm bin db (times 1 / pdf) into rec: XYZ, then the nspec
 * spectral bins, the one holding db its share of the bin's mean,
 * L / (pdf bin width). */
inline void disp_record(float dl, uint db, __global const float *dcmf, float *rec, uint nspec)
{
    for (int ch = 0; ch < 3; ch++)
        rec[ch] = dl * dcmf[ch * SPM_TRUTH_BINS + db];
    for (uint b = 0; b < nspec; b++)
        rec[3 + b] = 0.0f;
    if (nspec)
        rec[3 + db / (SPM_TRUTH_BINS / nspec)] = dl / (float)(SPM_TRUTH_BINS / nspec);
}

/* A path committed to 1 nm bin b (spm_shared.h SPM_VX_LAMBDA): the record
 * walked as one lane, every colour's value in bin b of the 1 nm rows t
 * (ncolours x SPM_TRUTH_BINS), by vertex_apply at width 1 (fluorescence never
 * meets dispersion, materials.c refuses the pair). Returns L at b. */
#define SB_W 1
#define SB_NV 1
#define SB_VT float
#define SB_UNROLL
#define SB_FMA(a, b, c) ((a) * (b) + (c)) /* uncontracted below */
#define SB_EXP(a) exp(a)
#define SB_LOAD(c, k) t[(size_t)(c) * SPM_TRUTH_BINS]
inline float disp_walk(spm_dev_head h, __global const spm_vertex *vp,
                       __global const spm_vertex_ext *xp, uint npaths, __global const float *t)
{
#pragma OPENCL FP_CONTRACT OFF /* rounds as the CPU reference */
    uint fe = h.colours & 0xFFFFu, nv = h.nvert_end & 0xFFFFu;
    float P[1] = {1.0f};
    float L[1] = {fe != SPM_NONE ? t[(size_t)fe * SPM_TRUTH_BINS] * h.first_emit_c : 0.0f};
    for (uint j = 0; j < nv; j++) {
        spm_vertex v = vp[(size_t)j * npaths];
        spm_vertex_ext x = xp[(size_t)j * npaths];
        if ((v.ids & 0xFFFFu) == SPM_NONE)
            return L[0];
        VERTEX_APPLY(1, SPM_VX_KIND(x), v, x, P, L);
    }
    uint bg = h.colours >> 16;
    if (bg != SPM_NONE)
        FACTOR_EMIT_EYE(P, L, bg, h.bg_c);
    return L[0];
}

#ifdef SPM_LIGHT_TRACE
/* A light subpath committed to 1 nm bin b at vertex jc, its first dispersive
 * one (1 / pdf dw): the walk from the light again in one lane, bin b, as
 * kernels/shade_splats.clh's from the light, its splats from jc on, each
 * times dw (host/cpu/refcpu_shade.c committed_splats); those before jc do not
 * depend on the wavelength and stay the mode's. */
inline void disp_splats(spm_dev_head h, __global const spm_vertex *vp,
                        __global const spm_vertex_ext *xp, __global const uint *pxp, uint npaths,
                        uint jc, uint b, float dw, __global const float *t,
                        __global const float *dcmf, uint nspec, __global uint *spx,
                        __global float *sval, __global int *lstat, uint scap)
{
#pragma OPENCL FP_CONTRACT OFF /* rounds as the CPU reference */
    uint nv = h.nvert_end & 0xFFFFu;
    float P[1] = {1.0f}, L[1];
    for (uint j = 0; j < nv; j++) {
        spm_vertex v = vp[(size_t)j * npaths];
        spm_vertex_ext x = xp[(size_t)j * npaths];
        if ((v.ids & 0xFFFFu) == SPM_NONE)
            return;
        L[0] = 0.0f;
        VERTEX_APPLY(1, SPM_VX_KIND(x), v, x, P, L);
        uint px = pxp[(size_t)(j + 1u) * npaths];
        if (j >= jc && px != SPM_NO_PIXEL) {
            float sv[SPM_PATH_CH];
            disp_record(L[0] * dw, b, dcmf, sv, nspec);
            splat_append(sv, px, spx, sval, lstat, scap);
        }
    }
}
#endif
#undef SB_W
#undef SB_NV
#undef SB_VT
#undef SB_UNROLL
#undef SB_FMA
#undef SB_EXP
#undef SB_LOAD

/* The record of path pi when it committed to a wavelength (SPM_VX_LAMBDA at
 * its first dispersive vertex): one lane at its 1 nm bin, weighed by 1 / its
 * pdf, whatever the mode, into rec (XYZ, then nspec spectral bins). Returns 0
 * when the path did not commit (shade it as the mode does). */
inline int shade_dispersed(spm_dev_head h, __global const spm_vertex *vp,
                           __global const spm_vertex *verts, uint npaths, uint pi,
                           __global const float *dtab, __global const float *dcmf,
                           __global float *rec, uint nspec)
{
    __global const spm_vertex_ext *dx = (__global const spm_vertex_ext *)SPM_VERTEX_EXT(verts, npaths) + pi;
    uint dn = h.nvert_end & 0xFFFFu, db = SPM_NONE;
    float dw = 0.0f, out[SPM_PATH_CH];
    if (disp_commit(dx, npaths, dn, &db, &dw) == dn)
        return 0;
    float dl = disp_walk(h, vp, dx, npaths, dtab + db) * dw;
    disp_record(dl, db, dcmf, out, nspec);
    for (uint c = 0; c < 3 + nspec; c++)
        rec[c] = out[c];
    return 1;
}

#endif

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
/* hero sets up its paths 16 at a time: the draw of a path's wavelengths is
 * scalar integer and table work (key, RNG, 4 bins, 4 densities), as long as
 * the shading itself, and PoCL runs a work-group's work-items one after the
 * other without vectorising across them. So the first HERO_PREP work-items
 * of a group each draw for 16 of its paths in 16-wide vectors, into local
 * memory, and after a barrier every work-item reads its own (8 at a time
 * took 0.07 of ref's shade time more). Only operators take the 16-wide
 * vectors; builtins get their float8 halves (HERO_HALVES), as SB_FMA in
 * shade_body.clh: a 16-wide argument changes the x86 ABI on CPUs without
 * AVX-512, and clang warns of it. */
#define HERO_VW 16
/* A light subpath's key: a chunk starts at any subpath of the pass, so its
 * record pi is subpath first_pixel spp + pofs + pi (kernels/lighttrace.cl). */
#ifdef SPM_LIGHT_TRACE
#define HERO_LT_PARAM , uint pofs
#define HERO_LT_ARG , pofs
#define HERO_LT_OFFSET pi += (uint16)pofs;
#elif defined(SPM_BDPT)
#include "spm_bdpt.h"
/* A connected path's key is its sample's: record pi is sample rsam[pi] of
 * the pass (kernels/bdpt.cl), its hero set the same for every strategy. */
#define HERO_LT_PARAM , __global const uint *rsam
#define HERO_LT_ARG , rsam
#define HERO_LT_OFFSET                                                                  \
    pi = (uint16)(rsam[pi.s0], rsam[pi.s1], rsam[pi.s2], rsam[pi.s3], rsam[pi.s4],     \
                  rsam[pi.s5], rsam[pi.s6], rsam[pi.s7], rsam[pi.s8], rsam[pi.s9],     \
                  rsam[pi.sa], rsam[pi.sb], rsam[pi.sc], rsam[pi.sd], rsam[pi.se], rsam[pi.sf]);
#else
#define HERO_LT_PARAM
#define HERO_LT_ARG
#define HERO_LT_OFFSET
#endif
#define HERO_PREP (SPM_LOCAL_SIZE / HERO_VW)
#define HERO_HALVES(T, f, v) ((T)(f((v).lo), f((v).hi)))

/* t[o + v.sk] for each of the 16 lanes of v */
#define HERO_GATHER16(t, o, v)                                                          \
    ((float16)(t[(o) + (v).s0], t[(o) + (v).s1], t[(o) + (v).s2], t[(o) + (v).s3],      \
               t[(o) + (v).s4], t[(o) + (v).s5], t[(o) + (v).s6], t[(o) + (v).s7],      \
               t[(o) + (v).s8], t[(o) + (v).s9], t[(o) + (v).sa], t[(o) + (v).sb],      \
               t[(o) + (v).sc], t[(o) + (v).sd], t[(o) + (v).se], t[(o) + (v).sf]))

/* The four lanes of the paths of bucket entries e0 .. e0+15 (those before
 * end; host/spectral/tables.c derives the density): the path's uniform u
 * from its key; lane k at x = frac(u + k/4), y = t0 + x dt = tanh(a (l -
 * 538)) at its wavelength l; its 1 nm bin, which the direct index of x's
 * cell gives or puts one before (one comparison with the next bin's edge
 * settles it); and 1 / (density a (1 - y^2) / dt times the lane count).
 * Lane k of the 16 paths goes to bin[k * SPM_LOCAL_SIZE ...], r likewise:
 * vector stores (stored path by path, the scattered stores took 0.14 of
 * ref's shade time). The same float operations as the CPU reference, lane
 * by lane, uncontracted. */
inline void hero_draw16(__global const float *hero, __global const uint *idx, uint e0, uint end,
                        uint seed, spm_divisor spp, uint first_sample, uint first_pixel,
                        __local uint *bin, __local float *r HERO_LT_PARAM)
{
#pragma OPENCL FP_CONTRACT OFF /* rounds as the CPU reference */
    uint part[HERO_VW];
    __global const uint *src = idx + e0;
    if (e0 + HERO_VW > end) {
        for (uint p = 0; p < HERO_VW; p++)
            part[p] = e0 + p < end ? idx[e0 + p] : 0u;
        src = NULL;
    }
    uint16 pi = src ? (uint16)(vload8(0, src), vload8(1, src))
                    : (uint16)(vload8(0, part), vload8(1, part));
    HERO_LT_OFFSET
    uint16 t1 = (uint16)(mul_hi(pi.lo, (uint8)spp.mul), mul_hi(pi.hi, (uint8)spp.mul));
    uint16 q = SPM_DIVISOR_QUOTIENT(pi, t1, spp);
    uint16 h;
    SPM_RNG_HASH_STEPS(h, seed, first_pixel + q, first_sample + (pi - q * spp.d), SPM_DIM_HERO);
    float16 u = HERO_HALVES(float16, convert_float8, h >> 8) * SPM_RNG_UNIT;
    for (uint k = 0; k < SPM_HERO_LANES; k++) {
        float16 x = u + (float)k / (float)SPM_HERO_LANES;
        x = x >= 1.0f ? x - 1.0f : x;
        float16 y = hero[SPM_HERO_T0] + x * hero[SPM_HERO_DT];
        uint16 cell = HERO_HALVES(uint16, convert_uint8, x * (float)SPM_HERO_CELLS);
        uint16 j = HERO_HALVES(uint16, convert_uint8, HERO_GATHER16(hero, SPM_HERO_INDEX, cell));
        /* select on halves: Oclgrind 21.10 gets ?: (or -=) with this
         * uint16 comparison wrong */
        int16 up = y >= HERO_GATHER16(hero, SPM_HERO_EDGE + 1, j);
        j = (uint16)(select(j.lo, j.lo + 1u, up.lo), select(j.hi, j.hi + 1u, up.hi));
        j = j < (uint16)(SPM_TRUTH_BINS - 1u) ? j : (uint16)(SPM_TRUTH_BINS - 1u);
        float16 w = 1.0f / (hero[SPM_HERO_PDFK] * (1.0f - y * y) * (float)SPM_HERO_LANES);
        vstore8(j.lo, 0, bin + k * SPM_LOCAL_SIZE);
        vstore8(j.hi, 1, bin + k * SPM_LOCAL_SIZE);
        vstore8(w.lo, 0, r + k * SPM_LOCAL_SIZE);
        vstore8(w.hi, 1, r + k * SPM_LOCAL_SIZE);
    }
}

/* XYZ of the lanes' radiance L: lane k weighs truth's XYZ weights of its bin
 * by r.sk; summed as the dot product's pairs, (0 + 2) + (1 + 3). */
inline void hero_xyz(__global const float *hero, uint4 b, float4 r, float4 L, float *out)
{
#pragma OPENCL FP_CONTRACT OFF /* rounds as the CPU reference */
    __global const float *cw = hero + SPM_HERO_CMF;
    float4 t0 = L.s0 * (vload4(b.s0, cw) * r.s0), t1 = L.s1 * (vload4(b.s1, cw) * r.s1);
    float4 t2 = L.s2 * (vload4(b.s2, cw) * r.s2), t3 = L.s3 * (vload4(b.s3, cw) * r.s3);
    float4 s = (t0 + t2) + (t1 + t3);
    out[0] = s.x;
    out[1] = s.y;
    out[2] = s.z;
}

#define SB_NAME spm_shade_hero
#define SB_W 4
#define SB_NV 1
#ifdef SPM_BDPT
#define SB_EXTRA_ARGS , SPM_SHADE_PATH_ARGS(SPM_KERNEL_PARAM, SPM_COMMA), \
    SPM_BDPT_SHADE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA)
#else
#define SB_EXTRA_ARGS , SPM_SHADE_PATH_ARGS(SPM_KERNEL_PARAM, SPM_COMMA)
#endif
#define SB_ATTR __attribute__((reqd_work_group_size(SPM_LOCAL_SIZE, 1, 1)))
#define SB_GROUP                                                                       \
    __local uint hbin[SPM_HERO_LANES * SPM_LOCAL_SIZE];                                \
    __local float hr[SPM_HERO_LANES * SPM_LOCAL_SIZE];                                 \
    {                                                                                  \
        uint l = (uint)get_local_id(0);                                                \
        if (l < HERO_PREP)                                                             \
            hero_draw16(extra, idx, i - l + HERO_VW * l, end, seed, spp, first_sample, \
                        first_pixel, hbin + HERO_VW * l, hr + HERO_VW * l HERO_LT_ARG); \
        barrier(CLK_LOCAL_MEM_FENCE);                                                  \
    }
#define HERO_LOCAL4(a, l)                                                              \
    ((a)[l], (a)[(l) + SPM_LOCAL_SIZE], (a)[(l) + 2 * SPM_LOCAL_SIZE], (a)[(l) + 3 * SPM_LOCAL_SIZE])
#define SB_PREPARE                                                                     \
    uint hl = (uint)get_local_id(0);                                                   \
    uint4 hb = (uint4)HERO_LOCAL4(hbin, hl);                                           \
    float4 hw = (float4)HERO_LOCAL4(hr, hl);
/* A colour's values at the four bins. Read through a volatile pointer: four
 * scalar loads, which LLVM would otherwise merge into a gather (vgatherqps),
 * 0.06 of ref's shade time slower here. */
inline float4 hero_load(__global const float *row, uint4 b)
{
    __global const volatile float *v = row;
    return (float4)(v[b.s0], v[b.s1], v[b.s2], v[b.s3]);
}
#define SB_LOAD(c, k) hero_load(tab + (size_t)(c) * SPM_TRUTH_BINS, hb)
#define SB_LOAD_PARAMS , uint4 hb
#define SB_LOAD_ARGS , hb
#define SB_XYZ hero_xyz(extra, hb, hw, L[0], out);
/* for spectral records, the factor that turns a lane's radiance into its
 * share of its 5 nm bin's mean: 1 / (density lanes 5 nm) */
#define HERO_SPEC(k) so[hb.s##k / (SPM_TRUTH_BINS / SPM_NM5_BINS)] +=                    \
    lf[k] * (hw.s##k / (float)(SPM_TRUTH_BINS / SPM_NM5_BINS));
#define SB_SPEC_STORE                                                                  \
    for (uint b = 0; b < SPM_SPEC_BINS; b++)                                           \
        so[b] = 0.0f;                                                                  \
    HERO_SPEC(0) HERO_SPEC(1) HERO_SPEC(2) HERO_SPEC(3)
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
