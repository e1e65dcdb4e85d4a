/* The trace stage: one work-item per path of a pass. MiniLight's transport
 * (docs/METHODS.md "Paths"), written as path records (spm_shared.h, in the
 * device layout: header array and vertex-major vertex slabs) plus the
 * per-path level byte (the level feeler). Colour never enters here.
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
/* the types with vertex words (spm_vertex_ext): the conductor, the
 * dielectric and the coated type (the last two use the conductor's GGX) */
#if defined(SPM_WITH_CONDUCTOR) || defined(SPM_WITH_DIELECTRIC) || defined(SPM_WITH_COATED)
#define SPM_WITH_VEXT
#define COND_TRACE
#include "conductor.clh"
#endif
#ifdef SPM_WITH_DIELECTRIC
#include "dielectric.clh"
#endif
#ifdef SPM_WITH_COATED
#include "coated.clh"
#endif
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

/* The vertex's reflection: the colour it records, its Russian-roulette
 * survival (mean) and weight (inv_mean). Its own random numbers, if any, are
 * SPM_DIM_TYPE(j, k) (spm_rng.h). */
inline uint vertex_lobe(spm_material m, uint seed, uint pixel, uint sample, uint j, float *mean,
                        float *inv_mean)
{
    switch (SPM_MAT_TAG(m)) {
#ifdef SPM_WITH_LAMBERT
    case SPM_MAT_LAMBERT:
        *mean = m.mean;
        *inv_mean = m.inv_mean;
        return m.refl;
#endif
#ifdef SPM_WITH_CONDUCTOR
    case SPM_MAT_CONDUCTOR: /* eta recorded as the colour, k in the vertex's own words */
        *mean = m.mean;
        *inv_mean = m.inv_mean;
        return m.refl;
#endif
#ifdef SPM_WITH_DIELECTRIC
    case SPM_MAT_DIELECTRIC: /* its absorption colour; R + T = 1: always survives */
        *mean = m.mean;
        *inv_mean = m.inv_mean;
        return m.refl;
#endif
#ifdef SPM_WITH_COATED
    case SPM_MAT_COATED: /* its lobe's colour and survival: the trace loop's (coated.clh) */
        *mean = m.mean;
        *inv_mean = m.inv_mean;
        return m.refl;
#endif
#ifdef SPM_WITH_FLUOR
    case SPM_MAT_FLUOR:
    case SPM_MAT_DONALDSON: /* diffuse: its diagonal colour marks it for the shade stage */
        *mean = m.mean;
        *inv_mean = m.inv_mean;
        return m.refl;
#endif
    default:
        *mean = 0.0f;
        *inv_mean = 0.0f;
        return SPM_NONE;
    }
}

/* The emission of an emitter's material towards a direction at cosine
 * cos_e > 0 to its emitting face's normal (next-event estimation, a first
 * hit, a lobe's hit): its colour, and *scale, the factor its radiance there
 * takes (its emission profile; 1 for every direction of a uniform one). */
inline uint vertex_emission(spm_material m, float cos_e, float *scale)
{
    (void)cos_e;
    switch (SPM_EMIT_TAG(m)) {
#ifdef SPM_WITH_AREA
    case SPM_EMIT_AREA:
        *scale = 1.0f;
        return m.emit;
#endif
    default:
        *scale = 0.0f;
        return SPM_NONE;
    }
}

/* One batch of a pass; parameters: spm_kernel_args.h SPM_TRACE_ARGS. */
__kernel void spm_trace(SPM_TRACE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint gid = get_global_id(0);
    if (gid >= npaths)
        return;
    uint pixel = first_pixel + gid / p.spp_per_pass; /* the batch starts at first_pixel */
    uint sample = p.first_sample + gid % p.spp_per_pass;
    uint seed = p.seed;
    __global spm_vertex *vrec = &verts[gid]; /* vertex j at vrec[j * npaths] (spm_shared.h) */
#ifdef SPM_WITH_VEXT
    /* the types' vertex words, slabs after the vertices' (SPM_VERTEX_EXT) */
    __global spm_vertex_ext *xrec = (__global spm_vertex_ext *)SPM_VERTEX_EXT(verts, npaths) + gid;
    float cpdf = -1.0f; /* the last vertex's lobe density: < 0 none (not a conductor's,
                           a dielectric's or a coating's specular lobe), 0 a delta (or a
                           glass's refraction), else the rough lobe's, for MIS */
#endif
#ifdef SPM_WITH_DIELECTRIC
    int din = 0; /* the last vertex's sampled ray runs inside its glass */
#endif
#ifdef SPM_WITH_DISPERSION
    uint lam = SPM_NONE; /* the 1 nm bin the path committed to (none yet) */
#endif

    /* camera ray (spm_shared.h: spm_camera) */
    uint px = pixel % (uint)p.cam.width, py = pixel / (uint)p.cam.width;
    float w = (float)p.cam.width, h = (float)p.cam.height;
    float cx = 2.0f * ((float)px + spm_rng(seed, pixel, sample, SPM_DIM_CAM_X)) / w - 1.0f;
    float cy = 1.0f - 2.0f * ((float)py + spm_rng(seed, pixel, sample, SPM_DIM_CAM_Y)) / h;
    float3 right = (float3)(p.cam.right[0], p.cam.right[1], p.cam.right[2]);
    float3 up = (float3)(p.cam.up[0], p.cam.up[1], p.cam.up[2]);
    float3 cdir = (float3)(p.cam.dir[0], p.cam.dir[1], p.cam.dir[2]);
    float3 o = (float3)(p.cam.eye[0], p.cam.eye[1], p.cam.eye[2]);
    float sy = cy * h / w;
    float3 d = unit3(cdir + p.cam.tan_half * (right * cx + up * sy));

    spm_path_head hd;
    hd.nvert = 0;
    hd.end = SPM_END_TRUNCATED;
    hd.first_emit = SPM_NONE;
    hd.first_emit_c = 0.0f;
    hd.bg = SPM_NONE;
    hd.bg_c = 0.0f;
    hd.pad0 = 0;
    hd.pad1 = 0;
    uint level = init_level, setby = SPM_SETBY_NONE;
    ushort seen[SPM_MAX_DEPTH]; /* reflectance ids so far: occurrence counts */
    float rrw = 1.0f;           /* product of 1/mean over earlier vertices */
    uint skip = 0xFFFFFFFFu;
    float ne = (float)p.nemitters;

    uint j = 0;
    for (; j < SPM_MAX_DEPTH; j++) {
        float t;
        int hit = intersect(nodes, tris, o, d, skip, &t, counters);
        if (hit < 0) {
            hd.end = SPM_END_ESCAPED;
            hd.bg = d.y > 0.0f ? p.bg_up : p.bg_down;
            if (hd.bg != SPM_NONE) {
                hd.bg_c = rrw;
                feel(lvlk, hd.bg, 1u, SPM_SETBY_EMITTER, &level, &setby);
            }
            break;
        }
        __global const spm_tri *tr = &tris[hit];
        spm_material m = mats[tr->material];
        float3 pos = o + d * t;
        float3 n = ld3(tr->n);
        float3 back = -d;
#ifdef SPM_WITH_SMOOTH
        /* The hit's shading frame, the one place a type finds it: the shading
         * normal sn (on the viewer's side) and tangent stg every type shades
         * with; gn, the geometric normal on the viewer's side, decides which
         * side a direction is on (kernels/shading.clh). A flat triangle's is
         * gn and its own tangent, as without smooth shading. */
        float3 gn = dot3(n, back) < 0.0f ? -n : n;
        int smooth = tr->vn != 0u;
        float3 sn = gn, stg = ld3(tr->t);
        if (smooth)
            shading_frame(tr, vnormals + 9u * (tr->vn - 1u), o, d, back, gn, &sn, &stg);
#endif

        /* local emission, first vertex only, front face (either face when twosided) */
        float ecos = dot3(back, n), escale;
        if (m.type & SPM_EMIT_TWOSIDED)
            ecos = fabs(ecos);
        uint memit = vertex_emission(m, ecos, &escale);
        if (j == 0 && memit != SPM_NONE && (dot3(back, n) > 0.0f || (m.type & SPM_EMIT_TWOSIDED))) {
            hd.first_emit = memit;
            hd.first_emit_c = escale;
            feel(lvlk, memit, 1u, SPM_SETBY_EMITTER, &level, &setby);
        }

#ifdef SPM_WITH_DIELECTRIC
        if (din) /* the segment's length inside: its absorption, in the shade stage */
            xrec[(size_t)(j - 1u) * npaths].cos_lobe = t;
#endif
#ifdef SPM_WITH_VEXT
        /* emission the last vertex's conductor, glass or coating lobe hit: counted there, with
         * its MIS weight against the light sample (smooth: 1) */
        if (cpdf >= 0.0f && memit != SPM_NONE) {
            float ce = ecos;
            if (ce > 0.0f) {
                float wm = 1.0f;
                if (cpdf > 0.0f) {
                    float pl = light_pdf[hit] * fmax(t * t, SPM_D2_MIN_REL * tr->area) / (tr->area * ce);
                    wm = cond_power(cpdf, pl);
                }
                __global spm_vertex_ext *px = &xrec[(size_t)(j - 1u) * npaths];
                px->ids = (px->ids & 0xFFFFu) | SPM_EXT_IDS(SPM_NONE, memit);
                px->hit_c = rrw * wm * escale;
                feel(lvlk, memit, 1u, SPM_SETBY_EMITTER, &level, &setby);
            }
        }
        int cond = SPM_MAT_TAG(m) == SPM_MAT_CONDUCTOR;
        float calpha = cond ? m.p[SPM_COND_P_ALPHA] : 0.0f;
#ifdef SPM_WITH_DIELECTRIC
        int diel = SPM_MAT_TAG(m) == SPM_MAT_DIELECTRIC;
        float dalpha = diel ? m.p[SPM_DIEL_P_ALPHA] : 0.0f;
#ifdef SPM_WITH_DISPERSION
        /* a dispersive glass: n of the path's committed bin, the first such vertex
         * drawing it (rgb: n_d, p.disperse 0) */
        float dior = m.p[SPM_DIEL_P_IOR];
        uint drow = diel && p.disperse ? (uint)m.p[SPM_DIEL_P_DISP] : 0u;
        int dcommit = 0;
        if (drow) {
            if (lam == SPM_NONE) {
                lam = disp_bin(spm_rng_stratified_u32(seed, pixel, sample, SPM_DIM_TYPE(0u, SPM_DIM_DIEL_LAMBDA)));
                dcommit = 1;
            }
            dior = disp[(drow - 1u) * SPM_TRUTH_BINS + lam];
        }
        float deta = !diel ? 1.0f : dot3(back, n) > 0.0f ? dior : 1.0f / dior;
#else
        /* the relative index eta_t / eta_i: eta entering through the front face, 1 / eta leaving */
        float deta = !diel ? 1.0f : dot3(back, n) > 0.0f ? m.p[SPM_DIEL_P_IOR] : 1.0f / m.p[SPM_DIEL_P_IOR];
#endif
#endif
#ifdef SPM_WITH_SMOOTH
        float3 cn = sn, ctg = stg, cbt = cross3(cn, ctg); /* the shading frame */
#else
        float3 cn = dot3(n, back) < 0.0f ? -n : n; /* the normal on the incoming side */
        float3 ctg = ld3(tr->t), cbt = cross3(cn, ctg);
#endif
        float3 wl = (float3)(dot3(back, ctg), dot3(back, cbt), dot3(back, cn)); /* wo in the frame */
        spm_vertex_ext xe = {0u, 0.0f, 0.0f, 0.0f};
        /* no light sample on a delta lobe */
#ifdef SPM_WITH_DIELECTRIC
        int nee = p.nemitters > 0 && !(cond && calpha == 0.0f) && !(diel && dalpha == 0.0f);
#else
        int nee = p.nemitters > 0 && !(cond && calpha == 0.0f);
#endif
#else
        int nee = p.nemitters > 0;
#endif
#ifdef SPM_WITH_COATED
        /* a coated vertex (coated.clh): the lobe first, from its own dimension; the
         * specular lobe's direction, weight cw and density; the diffuse lobe's weight
         * without 1 - F(cos_i), its direction the cosine-weighted bounce's */
        int coat = SPM_MAT_TAG(m) == SPM_MAT_COATED, cspec = 0;
        float ceta = m.p[SPM_COAT_P_ETA], kalpha = m.p[SPM_COAT_P_ALPHA];
        float cps = 1.0f, cw = 0.0f, kpdf = 0.0f;
        float3 kdir = (float3)(0.0f, 0.0f, 0.0f);
        if (coat) {
            float fo = coat_fresnel(ceta, wl.z);
            cps = coat_spec_prob(fo, m.p[SPM_COAT_P_SPEC]);
            cspec = spm_rng(seed, pixel, sample, SPM_DIM_TYPE(j, SPM_DIM_COAT_LOBE)) < cps;
            if (!cspec) {
                cw = (1.0f - fo) * m.p[SPM_COAT_P_KD] / (1.0f - cps);
            } else if (kalpha == 0.0f) {
                cw = fo / cps;
                kdir = cn * (2.0f * wl.z) - back;
            } else {
                float3 mh = cond_vndf(wl, kalpha,
                                      spm_rng(seed, pixel, sample, SPM_DIM_TYPE(j, SPM_DIM_COAT_M_A)),
                                      spm_rng(seed, pixel, sample, SPM_DIM_TYPE(j, SPM_DIM_COAT_M_B)));
                float cl = dot3(wl, mh);
                float3 il = mh * (2.0f * cl) - wl;
                if (il.z > 0.0f && cl > 0.0f) { /* else below the surface: weight 0 */
                    float lo = cond_lambda(kalpha, wl.z), li = cond_lambda(kalpha, il.z);
                    cw = coat_fresnel(ceta, cl) * ((1.0f + lo) / (1.0f + lo + li)) / cps;
                    kpdf = cond_d(kalpha, mh.z) / ((1.0f + lo) * 4.0f * wl.z);
                    kdir = ctg * il.x + cbt * il.y + cn * il.z;
                }
            }
            nee = nee && !(cspec && kalpha == 0.0f); /* no light sample on a delta lobe */
        }
#endif

        /* next-event estimation: one emitter triangle, one point on it */
        uint eid = SPM_NONE;
        float c = 0.0f;
        if (nee) {
            /* by power through the table, or uniformly when the powers are equal (spm_emitter) */
            uint k;
            if (p.emit_power)
                k = spm_emitter_search(emitters, p.nemitters,
                                       spm_rng_u32(seed, pixel, sample,
                                                   SPM_DIM_VERTEX(j) + SPM_DIM_EMITTER) >> 8);
            else
                k = min((uint)(spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_EMITTER) * ne),
                        p.nemitters - 1u);
            uint ei = emitters[k].tri;
            __global const spm_tri *et = &tris[ei];
            float sqr1 = sqrt(spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_EPOINT_A));
            float r2 = spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_EPOINT_B);
            float a = 1.0f - sqr1, b = (1.0f - r2) * sqr1;
            float3 ev0 = ld3(et->v0);
            float3 ep = ev0 + (ld3(et->v1) - ev0) * a + (ld3(et->v2) - ev0) * b;
            float3 ev = ep - pos;
            float3 ed = unit3(ev);
            int sh = shadow_hit(nodes, tris, pos, ed, (uint)hit, ei, counters);
            float cos_e = -dot3(ed, ld3(et->n));
            spm_material em = mats[et->material];
            if (em.type & SPM_EMIT_TWOSIDED)
                cos_e = fabs(cos_e); /* the back face emits too */
            float cos_i = dot3(ed, n), cos_o = dot3(back, n);
            /* unoccluded, a face that emits, light and viewer on the same side */
            if ((sh < 0 || (uint)sh == ei) && cos_e > 0.0f && (cos_i < 0.0f) == (cos_o < 0.0f)) {
                float d2 = dot3(ev, ev);
                float wgt;
#ifdef SPM_WITH_CONDUCTOR
                if (cond) {
                    /* the rough lobe: BRDF cos_i without F, D G2 / (4 wo_z), times the power
                     * heuristic against the lobe's density (solid angle: the pick's pdf
                     * times d^2 / (area cos_e)); Fresnel at wo.h in the shade stage */
                    float3 il = (float3)(dot3(ed, ctg), dot3(ed, cbt), dot3(ed, cn));
                    float pb, ch;
                    float f = cond_eval(calpha, wl, il, &pb, &ch);
                    float d2c = fmax(d2, SPM_D2_MIN_REL * et->area);
                    float pl = emitters[k].pdf * d2c / (et->area * cos_e);
                    wgt = emitters[k].inv_pdf * cos_e * et->area / d2c * (f * cond_power(pl, pb));
                    xe.cos_light = ch;
#ifdef SPM_WITH_SMOOTH
                    if (!(il.z > 0.0f)) /* below the shading horizon: nothing */
                        wgt = 0.0f;
#endif
                } else
#endif
#ifdef SPM_WITH_DIELECTRIC
                if (diel) {
                    /* the rough lobe's reflection, F D G2 / (4 wo_z), times the power
                     * heuristic against the lobe's density of reflecting there */
                    float3 il = (float3)(dot3(ed, ctg), dot3(ed, cbt), dot3(ed, cn));
                    float pb;
                    float f = diel_eval(dalpha, deta, wl, il, &pb);
                    float d2c = fmax(d2, SPM_D2_MIN_REL * et->area);
                    float pl = emitters[k].pdf * d2c / (et->area * cos_e);
                    wgt = emitters[k].inv_pdf * cos_e * et->area / d2c * (f * cond_power(pl, pb));
#ifdef SPM_WITH_SMOOTH
                    if (!(il.z > 0.0f)) /* below the shading horizon: nothing */
                        wgt = 0.0f;
#endif
                } else
#endif
#ifdef SPM_WITH_COATED
                if (coat) {
                    float d2c = fmax(d2, SPM_D2_MIN_REL * et->area);
                    float lw;
                    if (cspec) { /* rough: F(wo.h) D G2 / (4 wo_z) / ps, the power heuristic */
                        float3 il = (float3)(dot3(ed, ctg), dot3(ed, cbt), dot3(ed, cn));
                        float pb, ch;
                        float f = cond_eval(kalpha, wl, il, &pb, &ch);
                        float pl = emitters[k].pdf * d2c / (et->area * cos_e);
                        lw = coat_fresnel(ceta, ch) * (f * cond_power(pl, pb)) / cps;
#ifdef SPM_WITH_SMOOTH
                        if (!(il.z > 0.0f)) /* below the shading horizon: nothing */
                            lw = 0.0f;
#endif
                    } else { /* diffuse: |cos_i| / pi (1 - F(|cos_i|)) times its weight */
#ifdef SPM_WITH_SMOOTH
                        float ci = fmax(dot3(ed, sn), 0.0f); /* the cosine to sn (flat: |cos_i|) */
#else
                        float ci = fabs(cos_i);
#endif
                        lw = ci / SPM_PI_F * (1.0f - coat_fresnel(ceta, ci)) * cw;
                    }
                    wgt = emitters[k].inv_pdf * cos_e * et->area / d2c * lw;
                } else
#endif
#ifdef SPM_WITH_SMOOTH
                /* the cosine to the shading normal (flat: |cos_i|), none below its horizon */
                wgt = emitters[k].inv_pdf * cos_e * et->area / fmax(d2, SPM_D2_MIN_REL * et->area) *
                      fmax(dot3(ed, sn), 0.0f) / SPM_PI_F;
#else
                wgt = emitters[k].inv_pdf * cos_e * et->area / fmax(d2, SPM_D2_MIN_REL * et->area) *
                      fabs(cos_i) / SPM_PI_F;
#endif
                if (wgt > 0.0f) {
                    float es;
                    eid = vertex_emission(em, cos_e, &es);
                    c = wgt * es * rrw;
                }
            }
        }

        /* the vertex; its reflectance counted per occurrence */
        float mmean, minv;
        uint refl = vertex_lobe(m, seed, pixel, sample, j, &mmean, &minv);
#ifdef SPM_WITH_COATED
        if (coat) { /* the lobe's colour; survival min(1, cw mean) and weight cw / q */
            float q = fmin(1.0f, cw * (cspec ? 1.0f : m.mean));
            refl = cspec ? m.col2 : m.refl;
            mmean = q;
            minv = q > 0.0f ? cw / q : 0.0f;
        }
#endif
        if (refl != SPM_NONE) {
            uint k = 1;
            for (uint i = 0; i < j; i++)
                k += seen[i] == refl;
            feel(lvlk, refl, k, SPM_SETBY_REFLECTOR, &level, &setby);
        }
        if (eid != SPM_NONE)
            feel(lvlk, eid, 1u, SPM_SETBY_EMITTER, &level, &setby);
        seen[j] = (ushort)refl;
        __global spm_vertex *vx = &vrec[(size_t)j * npaths];
        vx->ids = (refl & 0xFFFFu) | (eid << 16);
        vx->c = c;
#ifdef SPM_WITH_VEXT
        cpdf = -1.0f;
        if (cond) {
            xe.ids = SPM_EXT_IDS(m.col2, SPM_NONE);
            if (m.col2 != SPM_NONE)
                feel(lvlk, m.col2, 1u, SPM_SETBY_REFLECTOR, &level, &setby);
        }
#ifdef SPM_WITH_DIELECTRIC
        din = 0;
        if (diel)
            xe.ids = SPM_EXT_KIND; /* no hit yet; the length inside comes with the next hit */
#ifdef SPM_WITH_DISPERSION
        if (dcommit) { /* the committed bin and 1 / its pdf (spm_shared.h SPM_EXT_LAMBDA) */
            xe.ids |= lam + 1u;
            xe.cos_light = (float)SPM_TRUTH_BINS;
        }
#endif
#endif
        xrec[(size_t)j * npaths] = xe; /* every vertex: a zero record is a plain one */
#endif

        /* Russian roulette on the mean reflectance (the same at every level) */
        if (!(spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_RR) < mmean)) {
            hd.end = SPM_END_ABSORBED;
            j++;
            break;
        }
        rrw *= minv;
#ifdef SPM_WITH_DIELECTRIC
        if (diel) {
            /* the normal m: the surface's (smooth) or a visible normal (rough); reflect
             * with probability F(wo.m), else refract. The weight f |cos_i| / pdf is 1
             * for the smooth lobe, G2 / G1(wo) for the rough one, each times 1 / e^2
             * when refracting (radiance is compressed into the denser medium) */
            float3 mh = (float3)(0.0f, 0.0f, 1.0f);
            float cm = wl.z;
            if (dalpha > 0.0f) {
                mh = cond_vndf(wl, dalpha,
                               spm_rng(seed, pixel, sample, SPM_DIM_TYPE(j, SPM_DIM_DIEL_M_A)),
                               spm_rng(seed, pixel, sample, SPM_DIM_TYPE(j, SPM_DIM_DIEL_M_B)));
                cm = dot3(wl, mh);
            }
            if (!(cm > 0.0f)) { /* a normal facing away: the path ends */
                hd.end = SPM_END_ABSORBED;
                j++;
                break;
            }
            float ct;
            float f = diel_fresnel(cm, deta, &ct);
            int rf = spm_rng(seed, pixel, sample, SPM_DIM_TYPE(j, SPM_DIM_DIEL_CHOICE)) < f;
            float3 il = rf ? mh * (2.0f * cm) - wl : diel_refract(wl, mh, cm, deta, ct);
            if (rf ? !(il.z > 0.0f) : !(il.z < 0.0f)) { /* the wrong side: the path ends */
                hd.end = SPM_END_ABSORBED;
                j++;
                break;
            }
            if (!rf)
                rrw *= 1.0f / (deta * deta);
            cpdf = 0.0f;
            if (dalpha > 0.0f) {
                float lo = cond_lambda(dalpha, wl.z), li = cond_lambda(dalpha, fabs(il.z));
                rrw *= (1.0f + lo) / (1.0f + lo + li);
                if (rf)
                    cpdf = f * cond_d(dalpha, mh.z) / ((1.0f + lo) * 4.0f * wl.z);
            }
            d = ctg * il.x + cbt * il.y + cn * il.z;
#ifdef SPM_WITH_SMOOTH
            /* a reflection on the viewer's side of the geometric surface, a
             * refraction on the other, or the path ends */
            if (smooth && (rf ? !(dot3(d, gn) > 0.0f) : !(dot3(d, gn) < 0.0f))) {
                hd.end = SPM_END_ABSORBED;
                j++;
                break;
            }
#endif
            din = dot3(d, n) < 0.0f; /* into the back face's side: inside */
            o = pos;
            skip = (uint)hit;
            continue;
        }
#endif
#ifdef SPM_WITH_CONDUCTOR
        if (cond) {
            /* the lobe: the mirror direction, or about a visible normal m; its weight
             * f cos_i / pdf without F is 1 (smooth) or G2 / G1(wo); F at wo.m */
            float cl;
            if (calpha == 0.0f) {
                cl = wl.z;
                d = cn * (2.0f * wl.z) - back;
                cpdf = 0.0f;
            } else {
                float3 mh = cond_vndf(wl, calpha,
                                      spm_rng(seed, pixel, sample, SPM_DIM_TYPE(j, SPM_DIM_COND_M_A)),
                                      spm_rng(seed, pixel, sample, SPM_DIM_TYPE(j, SPM_DIM_COND_M_B)));
                cl = dot3(wl, mh);
                float3 il = mh * (2.0f * cl) - wl;
                if (!(il.z > 0.0f) || !(cl > 0.0f)) { /* below the surface: the path ends */
                    hd.end = SPM_END_ABSORBED;
                    j++;
                    break;
                }
                float lo = cond_lambda(calpha, wl.z), li = cond_lambda(calpha, il.z);
                rrw *= (1.0f + lo) / (1.0f + lo + li);
                cpdf = cond_d(calpha, mh.z) / ((1.0f + lo) * 4.0f * wl.z);
                d = ctg * il.x + cbt * il.y + cn * il.z;
            }
#ifdef SPM_WITH_SMOOTH
            if (smooth && !(dot3(d, gn) > 0.0f)) { /* under the geometric surface: ends */
                hd.end = SPM_END_ABSORBED;
                j++;
                break;
            }
#endif
            xrec[(size_t)j * npaths].cos_lobe = cl;
            o = pos;
            skip = (uint)hit;
            continue;
        }
#endif
#ifdef SPM_WITH_COATED
        if (coat && cspec) { /* the specular lobe's direction; its hit counted at the next vertex */
            cpdf = kpdf;
            d = kdir;
#ifdef SPM_WITH_SMOOTH
            if (smooth && !(dot3(d, gn) > 0.0f)) { /* under the geometric surface: ends */
                hd.end = SPM_END_ABSORBED;
                j++;
                break;
            }
#endif
            o = pos;
            skip = (uint)hit;
            continue;
        }
#endif

        /* cosine-weighted direction about the normal on the incoming side */
        float u = spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_DIR_A);
        float v = spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_DIR_B);
        float phi = 2.0f * SPM_PI_F * u, sr = sqrt(v);
        float x = cos(phi) * sr, y = sin(phi) * sr, z = sqrt(1.0f - v);
#ifdef SPM_WITH_COATED
        if (coat) /* the diffuse lobe's transmission out through the coating */
            rrw *= 1.0f - coat_fresnel(ceta, z);
#endif
#ifdef SPM_WITH_SMOOTH
        float3 nn = sn, tg = stg;
#else
        float3 nn = dot3(n, back) < 0.0f ? -n : n;
        float3 tg = ld3(tr->t);
#endif
        d = tg * x + cross3(nn, tg) * y + nn * z;
#ifdef SPM_WITH_SMOOTH
        if (smooth && !(dot3(d, gn) > 0.0f)) { /* under the geometric surface: ends */
            hd.end = SPM_END_ABSORBED;
            j++;
            break;
        }
#endif
        o = pos;
        skip = (uint)hit;
    }
    hd.nvert = j;
    if (hd.end == SPM_END_TRUNCATED)
        atomic_inc(&counters[SPM_COUNTER_TRUNCATED]);
    heads[gid] = spm_dev_head_pack(&hd);
    levels[gid] = (uchar)(level | (setby << SPM_SETBY_SHIFT));
}
