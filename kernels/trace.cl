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

/* a.x*b.x + a.y*b.y + a.z*b.z, left to right (as v3_dot) */
inline float dot3(float3 a, float3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

inline float3 cross3(float3 a, float3 b)
{
    return (float3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

/* MiniLight's unitized: times the reciprocal length, zero stays zero */
inline float3 unit3(float3 v)
{
    float len = sqrt(dot3(v, v));
    float inv = len != 0.0f ? 1.0f / len : 0.0f;
    return v * inv;
}

inline float3 ld3(__global const float *p)
{
    return (float3)(p[0], p[1], p[2]);
}

/* MiniLight's triangle test (Moller-Trumbore, |det| >= epsilon, t >= 0). */
inline int tri_hit(__global const spm_tri *tr, float3 o, float3 d, float *t_out)
{
    float3 e1 = ld3(tr->e1), e2 = ld3(tr->e2);
    float3 pvec = cross3(d, e2);
    float det = dot3(e1, pvec);
    if (!((det <= -SPM_RAY_EPSILON) | (det >= SPM_RAY_EPSILON)))
        return 0;
    float inv = 1.0f / det;
    float3 tvec = o - ld3(tr->v0);
    float u = dot3(tvec, pvec) * inv;
    if (!((u >= 0.0f) && (u <= 1.0f)))
        return 0;
    float3 q = cross3(tvec, e1);
    float v = dot3(d, q) * inv;
    if (!((v >= 0.0f) && (u + v <= 1.0f)))
        return 0;
    float t = dot3(e2, q) * inv;
    *t_out = t;
    return t >= 0.0f;
}

/* Slab test: entry distance, or INFINITY when the box is missed or lies
 * beyond tmax. The exit is widened by a few ulps so a flat box (a wall)
 * whose faces the ray touches is not lost to rounding. No operand is NaN
 * (finite boxes and origins, finite reciprocals), so plain compares give
 * fmin/fmax's values without their NaN handling. */
inline float min2(float a, float b)
{
    return b < a ? b : a;
}

inline float max2(float a, float b)
{
    return b > a ? b : a;
}

inline float box_entry(__global const spm_bvh_node *nd, float3 o, float3 inv, float tmax)
{
    float3 t0 = (ld3(nd->bmin) - o) * inv;
    float3 t1 = (ld3(nd->bmax) - o) * inv;
    float3 lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
    float enter = max2(max2(lo.x, lo.y), max2(lo.z, 0.0f));
    float leave = min2(min2(hi.x, hi.y), hi.z) * 1.0000005f;
    return (enter <= leave && enter <= tmax) ? enter : INFINITY;
}

/* Traversal keeping the closest hit other than triangle `skip`, starting
 * from the hit (hit, best): an exact tie goes to the lower index, so the
 * visiting order does not matter. Returns the final hit's index (`hit` when
 * nothing beats it; -1 for none). With `any`, returns at the first
 * triangle that beats the start: the caller only needs to know whether one
 * exists (a shadow ray), and the result is then some such triangle. */
int traverse(__global const spm_bvh_node *nodes, __global const spm_tri *tris, float3 o, float3 d,
             uint skip, float best, int hit, int any, float *t_out, __global uint *counters)
{
    /* a zero component gets a huge reciprocal, not infinity (no 0 * inf NaN) */
    float3 inv = (float3)(1.0f / (d.x != 0.0f ? d.x : 1e-30f), 1.0f / (d.y != 0.0f ? d.y : 1e-30f),
                          1.0f / (d.z != 0.0f ? d.z : 1e-30f));
    uint st_node[SPM_BVH_STACK];
    float st_t[SPM_BVH_STACK];
    int sp = 0;
    int start = hit;
    uint node = 0;
    *t_out = best;
    if (box_entry(&nodes[0], o, inv, best) == INFINITY)
        return hit;
    for (;;) {
        uint count = nodes[node].count, first = nodes[node].first;
        if (count > 0) {
            for (uint i = first; i < first + count; i++) {
                float t;
                if (i != skip && tri_hit(&tris[i], o, d, &t) &&
                    (t < best || (t == best && (int)i < hit))) {
                    best = t;
                    hit = (int)i;
                }
            }
            if (any && hit != start)
                return hit;
        } else {
            float ta = box_entry(&nodes[first], o, inv, best);
            float tb = box_entry(&nodes[first + 1], o, inv, best);
            uint na = first, nb = first + 1;
            if (tb < ta) {
                float tt = ta;
                ta = tb;
                tb = tt;
                na = first + 1;
                nb = first;
            }
            if (ta != INFINITY) {
                if (tb != INFINITY) {
                    if (sp < SPM_BVH_STACK) {
                        st_node[sp] = nb;
                        st_t[sp++] = tb;
                    } else {
                        atomic_inc(&counters[SPM_COUNTER_STACK]); /* BVH deeper than the stack: reported */
                    }
                }
                node = na;
                continue;
            }
        }
        /* pop the next subtree still closer than the best hit */
        for (;;) {
            if (sp == 0) {
                *t_out = best;
                return hit;
            }
            --sp;
            if (st_t[sp] <= best)
                break;
        }
        node = st_node[sp];
    }
}

/* Closest hit ignoring triangle `skip`: index or -1. */
inline int intersect(__global const spm_bvh_node *nodes, __global const spm_tri *tris, float3 o,
                     float3 d, uint skip, float *t_out, __global uint *counters)
{
    return traverse(nodes, tris, o, d, skip, INFINITY, -1, 0, t_out, counters);
}

/* The shadow test "the closest hit other than `skip` is emitter triangle ei,
 * or nothing": returns what intersect() would, or another occluder. When ei
 * itself is hit at te, the closest hit is ei exactly when no other triangle
 * hits at t < te or at t == te with a lower index, which is the traversal's
 * rule started from (te, ei); when ei is not hit, any hit at all occludes. */
inline int shadow_hit(__global const spm_bvh_node *nodes, __global const spm_tri *tris, float3 o,
                      float3 d, uint skip, uint ei, __global uint *counters)
{
    float te, t;
    if (ei != skip && tri_hit(&tris[ei], o, d, &te))
        return traverse(nodes, tris, o, d, skip, te, (int)ei, 1, &t, counters);
    return traverse(nodes, tris, o, d, skip, INFINITY, -1, 1, &t, counters);
}

/* Level feeler: one colour met; lvlk[c * KMAX + min(k, KMAX) - 1] (k = occurrence count). */
inline void feel(__global const uchar *lvlk, uint c, uint k, uint by, uint *level, uint *setby)
{
    uint l = lvlk[c * SPM_PRETEST_KMAX + min(k, (uint)SPM_PRETEST_KMAX) - 1u];
    if (l < *level) {
        *level = l;
        *setby = by;
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

        /* local emission, first vertex only, front face */
        if (j == 0 && m.emit != SPM_NONE && dot3(back, n) > 0.0f) {
            hd.first_emit = m.emit;
            hd.first_emit_c = 1.0f;
            feel(lvlk, m.emit, 1u, SPM_SETBY_EMITTER, &level, &setby);
        }

        /* next-event estimation: one emitter triangle, one point on it */
        uint eid = SPM_NONE;
        float c = 0.0f;
        if (p.nemitters > 0) {
            uint k = (uint)(spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_EMITTER) * ne);
            uint ei = emitters[min(k, p.nemitters - 1u)];
            __global const spm_tri *et = &tris[ei];
            float sqr1 = sqrt(spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_EPOINT_A));
            float r2 = spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_EPOINT_B);
            float a = 1.0f - sqr1, b = (1.0f - r2) * sqr1;
            float3 ep = ld3(et->v0) + ld3(et->e1) * a + ld3(et->e2) * b;
            float3 ev = ep - pos;
            float3 ed = unit3(ev);
            int sh = shadow_hit(nodes, tris, pos, ed, (uint)hit, ei, counters);
            float cos_e = -dot3(ed, ld3(et->n));
            float cos_i = dot3(ed, n), cos_o = dot3(back, n);
            /* unoccluded, front face, light and viewer on the same side */
            if ((sh < 0 || (uint)sh == ei) && cos_e > 0.0f && (cos_i < 0.0f) == (cos_o < 0.0f)) {
                float d2 = dot3(ev, ev);
                float wgt = ne * cos_e * et->area / fmax(d2, SPM_D2_MIN) * fabs(cos_i) / SPM_PI_F;
                if (wgt > 0.0f) {
                    eid = mats[et->material].emit;
                    c = wgt * rrw;
                }
            }
        }

        /* the vertex; its reflectance counted per occurrence */
        uint refl = m.refl;
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

        /* Russian roulette on the mean reflectance (the same at every level) */
        if (!(spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_RR) < m.mean)) {
            hd.end = SPM_END_ABSORBED;
            j++;
            break;
        }
        rrw *= m.inv_mean;

        /* cosine-weighted direction about the normal on the incoming side */
        float u = spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_DIR_A);
        float v = spm_rng(seed, pixel, sample, SPM_DIM_VERTEX(j) + SPM_DIM_DIR_B);
        float phi = 2.0f * SPM_PI_F * u, sr = sqrt(v);
        float x = cos(phi) * sr, y = sin(phi) * sr, z = sqrt(1.0f - v);
        float3 nn = dot3(n, back) < 0.0f ? -n : n;
        float3 tg = ld3(tr->t);
        d = tg * x + cross3(nn, tg) * y + nn * z;
        o = pos;
        skip = (uint)hit;
    }
    hd.nvert = j;
    if (hd.end == SPM_END_TRUNCATED)
        atomic_inc(&counters[SPM_COUNTER_TRUNCATED]);
    heads[gid] = spm_dev_head_pack(&hd);
    levels[gid] = (uchar)(level | (setby << SPM_SETBY_SHIFT));
}
