/* The trace stage: one work-item per path of a pass. MiniLight's transport
 * (docs/METHODS.md "Paths"), written as path records (spm_shared.h, in the
 * device layout: header array and vertex-major vertex slabs) plus the
 * per-path level byte (the level feeler). Colour never enters here.
 *
 * The loop names no material type: each vertex asks its type through the
 * contract of kernels/bsdf.clh (one switch per call, generated from
 * include/spm_types.h), and the MIS weights are computed here, once.
 *
 * Floating point: contraction is off in this file, and vector helpers spell
 * out the same operation order as the CPU reference (host/geometry/geometry_vec3.h),
 * so the ray arithmetic rounds identically; only cos/sin (OpenCL allows 4 ulp)
 * and the BVH traversal order (ties at shared edges) can make a rare path
 * differ from the reference. */
#pragma OPENCL FP_CONTRACT OFF
#include "spm_shared.h"
#include "spm_rng.h"
#include "spm_kernel_args.h"
#include "traverse.clh"
#include "bsdf.clh"
#include "lights.clh"
#include "camera.clh"
#include "texture.clh"
#include "metalrough.clh"
#ifdef SPM_WITH_SMOOTH
#include "shading.clh"
#endif

/* Level feeler: one colour met; lvlk[c * KMAX + min(k, KMAX) - 1] (k = occurrence count). */
inline void feel(__global const uchar *lvlk, uint c, uint k, uint by, uint *level, uint *setby)
{
    uint l = lvlk[c * SPM_PRETEST_KMAX + min(k, (uint)SPM_PRETEST_KMAX) - 1u];
    if (l < *level) {
        *level = l;
        *setby = by;
    }
}

/* The material and emitter types (spm_shared.h SPM_MAT_*, SPM_EMIT_*), one
 * switch each: a type's case is compiled in only when the scene uses it, by
 * the define its descriptor gives (host/scene/materials.c). A tag this
 * program was not built for is black and dark (the host never sends one). */

/* The occurrences of colour c among vertices 0..j, c being vertex j's */
SPM_ALWAYS_INLINE uint occurrences(const ushort *seen, uint j, uint c)
{
    uint k = 1;
    for (uint i = 0; i < j; i++)
        k += seen[i] == c;
    return k;
}

/* The camera ray through a jittered point of pixel k.pixel (camera.clh);
 * a thin lens draws its disk point from dimensions of its own. */
SPM_ALWAYS_INLINE void camera_key_ray(const spm_camera *cam, spm_key k, float3 *o, float3 *d)
{
    uint px = k.pixel % (uint)cam->width, py = k.pixel / (uint)cam->width;
    float w = (float)cam->width, h = (float)cam->height;
    float cx = 2.0f * ((float)px + key_rng(k, SPM_DIM_CAM_X)) / w - 1.0f;
    float cy = 1.0f - 2.0f * ((float)py + key_rng(k, SPM_DIM_CAM_Y)) / h;
    float lu = 0.5f, lv = 0.5f;
#ifdef SPM_WITH_LENS
    if (cam->lens_radius > 0.0f)
        lu = key_rng(k, SPM_DIM_LENS_A), lv = key_rng(k, SPM_DIM_LENS_B);
#endif
    camera_ray(cam, cx, cy, lu, lv, o, d);
}

/* The hit's shading frame *fr, the one place a type finds it: the shading
 * normal (on the viewer's side) and tangent every type shades with; gn, the
 * geometric normal on the viewer's side, decides which side a direction is
 * on (kernels/shading.clh). A flat triangle's is gn and its own tangent;
 * a normal map (triangle `hit`'s material's, tex and uvs) bends either.
 * Written through a pointer, not returned: a returned struct is a noalias
 * (sret) argument, whose inlining leaves an llvm.experimental.noalias.scope.decl
 * when the frame stays in memory (shading_frame takes its fields' addresses),
 * an intrinsic Oclgrind 21.10 cannot run. */
SPM_ALWAYS_INLINE void hit_frame(__global const spm_tri *tr, __global const float *vnormals,
                                 __global const uint *tex, __global const float *uvs, uint hit,
                                 float3 o, float3 d, spm_frame *fr)
{
    fr->ng = ld3(tr->n);
    fr->back = -d;
    fr->gn = dot3(fr->ng, fr->back) < 0.0f ? -fr->ng : fr->ng;
    fr->n = fr->gn;
    fr->t = ld3(tr->t);
    fr->smooth = 0;
#ifdef SPM_WITH_SMOOTH
    fr->smooth = tr->vn != 0u;
    int mapped = 0;
#ifdef SPM_WITH_NMAP
    mapped = nmap_frame(tex, uvs, hit, tr, vnormals, o, d, fr->back, fr->gn, &fr->n, &fr->t);
    fr->smooth |= mapped;
#endif
    if (fr->smooth && !mapped)
        shading_frame(tr, vnormals + 9u * (tr->vn - 1u), o, d, fr->back, fr->gn, &fr->n, &fr->t);
#endif
    fr->b = cross3(fr->n, fr->t);
    fr->wo = frame_local(fr, fr->back);
}

/* Next-event estimation's weight, the light sample ls's at a vertex of
 * material m (BSDF b, frame fr) with the path's throughput rrw:
 *   g f |cos_i| w_mis rrw,
 * f |cos_i| the type's, w_mis the power heuristic against the type's density
 * of sampling the same direction when its sampled rays count emission too
 * and the light is not a delta. Returns the emission's colour (SPM_NONE:
 * nothing) and *c its weight; *cos_light the type's spectral argument. */
SPM_ALWAYS_INLINE uint light_weight(spm_material m, const spm_bsdf *b, const spm_frame *fr,
                         const spm_light_sample *ls, float rrw, float *c, float *cos_light)
{
    spm_eval e = bsdf_eval(m, b, fr, ls->wi, SPM_RADIANCE);
    *cos_light = e.cos_light;
    float wm = 1.0f;
    if (!(e.pdf < 0.0f) && !ls->delta)
        wm = mis_power(ls->pdf, e.pdf);
    float wgt = ls->g * (e.k * (e.f * wm) / e.div) / e.post;
    if (!(wgt > 0.0f))
        return SPM_NONE;
    *c = wgt * ls->scale * rrw;
    return ls->colour;
}

/* The emission a sampled ray from o (on triangle from) hit at distance t on
 * triangle hit (colour memit, factor escale, face cosine ecos), counted at
 * the vertex that sampled it (record x) with the throughput rrw and the
 * power heuristic of its density cpdf against the light sample's
 * (light_pdf_hit, the selection's pmf from o); cpdf 0 (a delta) weighs 1. */
SPM_ALWAYS_INLINE void count_hit(const spm_trace_params *p, __global const spm_emitter *emitters,
                                 __global const float *light_pdf, __global const spm_tri *tris,
                                 float3 o, uint from, uint hit, float t, float ecos, float cpdf,
                                 float rrw, uint memit, float escale, __global spm_vertex_ext *x)
{
    float wm = 1.0f;
    if (cpdf > 0.0f)
        wm = mis_power(cpdf, light_pdf_hit(p, emitters, light_pdf, tris, o, from, hit, t, ecos));
    x->ids = (x->ids & 0xFFFFu) | SPM_VX_HIT_BITS(memit);
    x->hit_c = rrw * wm * escale;
}

/* The ray of direction d leaving the scene after vertex j - 1 (whose sampled
 * ray had density cpdf; throughput rrw): what it meets, into the header. The
 * map, which light_sample reaches too (density lpdf), takes the power
 * heuristic; 1 after a delta (cpdf 0) and for the camera's ray, 0 when the
 * vertex's sampled rays count no emission (cpdf < 0: its light sample
 * weighed 1). The two-colour background weighs 1. */
SPM_ALWAYS_INLINE void escape(const spm_trace_params *p, __global const spm_emitter *emitters,
                              __global const float *light_pdf, __global const float *envmap,
                              float3 d, spm_key key, uint j, float cpdf, float rrw,
                              spm_path_head *hd)
{
    float scale, lpdf;
    hd->end = SPM_END_ESCAPED;
    hd->bg = light_escape(p, emitters, light_pdf, envmap, d, key, j, &scale, &lpdf);
#if SPM_ON_LIGHT_ENVMAP
    if (lpdf > 0.0f && j > 0u)
        scale *= cpdf < 0.0f ? 0.0f : cpdf > 0.0f ? mis_power(cpdf, lpdf) : 1.0f;
    if (!(scale > 0.0f))
        hd->bg = SPM_NONE;
#endif
    hd->bg_c = hd->bg != SPM_NONE ? rrw * scale : 0.0f;
}

#ifndef SPM_LIGHT_TRACE /* the light integrator's program: kernels/lighttrace.cl */
/* One batch of a pass; parameters: spm_kernel_args.h SPM_TRACE_ARGS. */
__kernel void spm_trace(SPM_TRACE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint gid = get_global_id(0);
    if (gid >= npaths)
        return;
    spm_key key = {p.seed, first_pixel + gid / p.spp_per_pass, p.first_sample + gid % p.spp_per_pass};
    spm_walk walk = {disp, p.disperse, SPM_NONE};
    __global spm_vertex *vrec = &verts[gid]; /* vertex j at vrec[j * npaths] (spm_shared.h) */
#ifdef SPM_WITH_VEXT
    /* the types' vertex words, slabs after the vertices' (SPM_VERTEX_EXT) */
    __global spm_vertex_ext *xrec = (__global spm_vertex_ext *)SPM_VERTEX_EXT(verts, npaths) + gid;
#endif
    float cpdf = -1.0f; /* the last vertex's density of its sampled ray, for MIS at the
                           emission it hits: < 0 not counted, 0 a delta */
    int seg = 0;        /* the last vertex records the length of its ray's segment */
    spm_camera cam = p.cam;
    float3 o, d;
    camera_key_ray(&cam, key, &o, &d);

    spm_path_head hd = {0u, SPM_END_TRUNCATED, SPM_NONE, 0.0f, SPM_NONE, 0.0f, 0u, 0u};
    uint level = init_level, setby = SPM_SETBY_NONE;
    ushort seen[SPM_MAX_DEPTH]; /* reflectance ids so far: occurrence counts */
    float rrw = 1.0f;           /* product of the weights over earlier vertices */
    uint skip = 0xFFFFFFFFu;
    TEXTURE_CONE(cam); /* a textured scene's ray cone (texture.clh) */
    uint j = 0;
    for (; j < SPM_MAX_DEPTH; j++) {
        float t;
        int hit = intersect(nodes, tris, o, d, skip, &t, counters SPM_ALPHA_ARGS);
        if (hit < 0) { /* the background: MiniLight's sky for an upward ray, or the map */
            escape(&p, emitters, light_pdf, envmap, d, key, j, cpdf, rrw, &hd);
            if (hd.bg != SPM_NONE)
                feel(lvlk, hd.bg, 1u, SPM_SETBY_EMITTER, &level, &setby);
            break;
        }
        __global const spm_tri *tr = &tris[hit];
        float3 pos = o + d * t;
        SPM_MATERIAL_AT(m, mi, mats, tex, uvs, tr, (uint)hit, pos, key, j); /* metalrough.clh */
        spm_frame fr;
        hit_frame(tr, vnormals, tex, uvs, (uint)hit, o, d, &fr);

        /* local emission, first vertex only, front face (either face when twosided) */
        float ecos = dot3(fr.back, fr.ng), escale;
        if (m.type & SPM_EMIT_TWOSIDED)
            ecos = fabs(ecos);
        uint memit = light_eval_at(m, ecos, &escale, tex, uvs, (uint)hit, tr, pos, key, j, 0u);
        if (j == 0 && memit != SPM_NONE && (ecos > 0.0f || (m.type & SPM_EMIT_TWOSIDED))) {
            hd.first_emit = memit;
            hd.first_emit_c = escale;
            feel(lvlk, memit, 1u, SPM_SETBY_EMITTER, &level, &setby);
        }
#ifdef SPM_WITH_VEXT
        if (seg) /* the segment's length: a medium's absorption, in the shade stage */
            xrec[(size_t)(j - 1u) * npaths].lobe = t;
        /* emission the last vertex's sampled ray hit, counted there */
        if (cpdf >= 0.0f && memit != SPM_NONE && ecos > 0.0f) {
            count_hit(&p, emitters, light_pdf, tris, o, skip, (uint)hit, t, ecos, cpdf, rrw, memit,
                      escale, &xrec[(size_t)(j - 1u) * npaths]);
            feel(lvlk, memit, 1u, SPM_SETBY_EMITTER, &level, &setby);
        }
#endif
        spm_bsdf b;
        bsdf_begin(m, &fr, key, j, &walk, &b);
        spm_vertex_ext xe = {0u, 0.0f, 0.0f, 0.0f};
        uint eid = SPM_NONE;
        float c = 0.0f, mmean, minv;
        spm_light_sample ls;
        if (p.nemitters > 0 && b.nee && /* next-event estimation */
            light_sample(SPM_TRACE_ARGS(SPM_KERNEL_ARG, SPM_COMMA), key, j, pos, hit, &fr, &ls))
            eid = light_weight(m, &b, &fr, &ls, rrw, &c, &xe.light);

        /* the vertex; its reflectance counted per occurrence */
        uint refl = bsdf_lobe(m, &b, &mmean, &minv);
        TEXTURE_PICK(t, refl, m.refl, mi, (uint)hit, tr, pos, d, key, j, mmean, minv);
        if (refl != SPM_NONE)
            feel(lvlk, refl, occurrences(seen, j, refl), SPM_SETBY_REFLECTOR, &level, &setby);
        if (eid != SPM_NONE)
            feel(lvlk, eid, 1u, SPM_SETBY_EMITTER, &level, &setby);
        seen[j] = (ushort)refl;
        __global spm_vertex *vx = &vrec[(size_t)j * npaths];
        vx->ids = (refl & 0xFFFFu) | (eid << 16);
        vx->c = c;
        uint col2 = bsdf_record(m, &b, &walk, &xe);
        if (col2 != SPM_NONE)
            feel(lvlk, col2, 1u, SPM_SETBY_REFLECTOR, &level, &setby);
#ifdef SPM_WITH_VEXT
        xrec[(size_t)j * npaths] = xe; /* every vertex: a zero record is a plain one */
#endif

        /* Russian roulette on the mean reflectance (the same at every level) */
        spm_bsample s;
        if (!(key_rng(key, SPM_DIM_VERTEX(j) + SPM_DIM_RR) < mmean) ||
            !bsdf_sample(m, &b, &fr, key, j, SPM_RADIANCE, &s) ||
            /* a direction on the other side of the geometric surface than of the
             * shading one (a reflection under it, a refraction over it): ends */
            (fr.smooth && (s.refract ? !(dot3(s.wi, fr.gn) < 0.0f) : !(dot3(s.wi, fr.gn) > 0.0f)))) {
            hd.end = SPM_END_ABSORBED;
            j++;
            break;
        }
        rrw *= minv;
        rrw *= s.wt;
        rrw *= s.w;
        TEXTURE_BOUNCE(tr, vnormals, fr, b, s, d); /* the ray cone's spread (texture.clh) */
        cpdf = s.pdf; /* for the next hit */
        seg = s.inside;
#ifdef SPM_WITH_VEXT
        if (s.cos_lobe != 0.0f) /* the record holds 0 already */
            xrec[(size_t)j * npaths].lobe = s.cos_lobe;
#endif
        d = s.wi;
        o = pos;
        skip = (uint)hit;
    }
    hd.nvert = j;
    if (hd.end == SPM_END_TRUNCATED)
        atomic_inc(&counters[SPM_COUNTER_TRUNCATED]);
    heads[gid] = spm_dev_head_pack(&hd);
    levels[gid] = (uchar)(level | (setby << SPM_SETBY_SHIFT));
}
#endif
