/* The bidirectional integrator's trace kernel (--integrator bdpt), compiled
 * only into a program built with -DSPM_BDPT after kernels/trace.cl,
 * kernels/shade.cl and kernels/lighttrace.cl (docs/ARCHITECTURE.md
 * "Connected paths"). host/cpu/refcpu_bdpt.c is its reference, operation for
 * operation and with the same random numbers: per sample the camera subpath
 * z (key k) and the light subpath y (key k with SPM_BDPT_LIGHT_SEED), each
 * vertex with its densities per unit area both ways (pbrt-v4's pdfFwd,
 * pdfRev); then every strategy (s, t), t >= 1, but (1, 1), joined, weighed
 * by pbrt-v4's MISWeight with remap0, and written as a camera path's record
 * (camera vertices, then the light's reversed, the light's emission at the
 * last) with its weight folded into the emission's, into the next free
 * record slot. The mode's shade kernels shade the records; each record's
 * value becomes a splat of its pixel (kernels/lighttrace.cl's fixed-point
 * sums). Subpath vertices keep what MIS and the joins need; a joined
 * vertex's frame and BSDF are made again from its ray and key, as the walk
 * made them. Like the path loop it names no material type and no light
 * kind. Parameters: SPM_TRACE_ARGS, SPM_BDPT_TRACE_ARGS. */
#pragma OPENCL FP_CONTRACT OFF
#include "spm_bdpt.h"
#ifdef SPM_WITH_ALPHA /* the traversal's opacity test reads the texture words */
#define BD_ALPHA , sc->tex, sc->uvs
#else
#define BD_ALPHA
#endif

/* A subpath vertex: v[0] the endpoint (the lens or the light), v[1..] the
 * surface vertices. d the ray that reached it; n its triangle's normal (0
 * off a surface); beta the subpath's throughput arriving there; fwd, rev
 * its densities per unit area; emit, escale: a camera vertex on an emitter,
 * its emission toward the vertex before; disp: its index is the sample's
 * committed bin's (dispersive glass). */
typedef struct {
    float3 p, d, n;
    uint tri, refl, col2, emit;
    float beta, escale, fwd, rev;
    int delta, disp;
    spm_vertex_ext x;
} bd_vertex;

typedef struct {
    bd_vertex v[SPM_BDPT_SUBPATH + 1];
    int n;
    uint e, colour; /* the light subpath's light and its emission's colour */
    float ts;       /* a textured emission's factor at the light's point */
} bd_subpath;

/* What the kernel reads of the scene, as one argument to its helpers. */
typedef struct {
    __global const spm_tri *tris;
    __global const spm_bvh4_node *nodes;
    __global const spm_emitter *emitters;
    __global const spm_material *mats;
    __global const float *light_pdf, *vnormals, *disp, *uvs;
    __global const uint *tex;
    __global uint *counters;
    spm_camera cam;
    uint disperse, lam; /* lam: the sample's committed bin, once both subpaths are walked */
} bd_scene;

/* What strategy (s, t) found (refcpu_bdpt.c bd_join): its weight without
 * MIS, the pixel, the spectral arguments of the two joined vertices, and the
 * densities the connected path gives the joined vertices and their
 * neighbours (pbrt-v4's a1 .. a4). */
typedef struct {
    float c, arg_pt, arg_qs;
    uint px;
    float pt_rev, ptm_rev, qs_rev, qsm_rev;
} bd_join;

SPM_ALWAYS_INLINE float remap0(float f)
{
    return f != 0.0f ? f : 1.0f;
}

/* a solid-angle density at `from` toward `to` per unit area at `to`:
 * pdf |cos at to| / d^2 (no cosine off a surface) */
SPM_ALWAYS_INLINE float to_area(float pdf, float3 from, float3 to, float3 n)
{
    float3 d = to - from;
    float d2 = dot3(d, d);
    if (!(d2 > 0.0f))
        return 0.0f;
    float c = dot3(n, n) > 0.0f ? fabs(dot3(n, d)) / sqrt(d2) : 1.0f;
    return pdf * c / d2;
}

/* unit direction from a to b, and the distance */
SPM_ALWAYS_INLINE float toward(float3 a, float3 b, float3 *w)
{
    float3 d = b - a;
    float l = sqrt(dot3(d, d));
    *w = l > 0.0f ? d / l : (float3)(0.0f);
    return l;
}

/* the segment from a along w to dist is clear (a's triangle skipped) */
SPM_ALWAYS_INLINE int bd_visible(const bd_scene *sc, float3 a, uint skip, float3 w, float dist)
{
    float ts;
    return !(intersect(sc->nodes, sc->tris, a, w, skip, &ts, sc->counters BD_ALPHA) >= 0 &&
             ts < dist * (1.0f - 1e-4f));
}

/* the segment from a to b is clear both ways, a's and b's triangles skipped
 * (bt: none off a surface). The test from a passes a face within dist 1e-4
 * of b: at an edge of a closed box of metal, a light vertex on one face
 * sees out through the next. A face other than b's met in that last piece
 * is judged from b, where it lies at the start of the ray; b's own face
 * first clears the segment with one ray. */
SPM_ALWAYS_INLINE int bd_visible_join(const bd_scene *sc, float3 a, uint at, float3 b, uint bt,
                                      float3 w, float dist)
{
    float ts;
    int hit = intersect(sc->nodes, sc->tris, a, w, at, &ts, sc->counters BD_ALPHA);
    if (hit < 0 || (uint)hit == bt)
        return 1;
    return ts >= dist * (1.0f - 1e-4f) && bd_visible(sc, b, bt, -w, dist);
}

/* Surface vertex i of subpath sp (key k) as its walk made it: the material,
 * frame and BSDF instance. */
SPM_ALWAYS_INLINE void vertex_state(const bd_scene *sc, const bd_subpath *sp, int i, spm_key k,
                                    spm_material *m, spm_frame *fr, spm_bsdf *b)
{
    const bd_vertex *v = &sp->v[i];
    __global const spm_tri *tr = &sc->tris[v->tri];
    *m = sc->mats[tr->material];
#ifdef SPM_WITH_TEXTURE /* the metallic-roughness mix's pick, again */
    mix_pick(sc->tex, sc->uvs, sc->mats, tr, v->tri, v->p, k, (uint)(i - 1), m);
#endif
    hit_frame(tr, sc->vnormals, sc->tex, sc->uvs, v->tri, sp->v[i - 1].p, v->d, fr);
    spm_walk w = {sc->disp, sc->disperse, sc->lam};
    bsdf_begin(*m, fr, k, (uint)(i - 1), &w, b);
}

/* the type's density at a vertex of sampling wi seen from wo (0 at a
 * delta), in solid angle */
SPM_ALWAYS_INLINE float lobe_pdf(int delta, spm_material m, const spm_frame *fr,
                                 const spm_bsdf *b, float3 wo, float3 wi, int mode)
{
    if (delta)
        return 0.0f;
    return bsdf_pdf(m, b, frame_local(fr, wo), frame_local(fr, wi), mode);
}

/* The walk from the subpath's last vertex along o + t d (pdf_dir the
 * density of d there, in solid angle) in mode, until roulette, a miss or
 * the cap ends it. rw is the sample's, shared by both subpaths: the first
 * dispersive vertex either meets commits the bin, every later one takes it. */
SPM_ALWAYS_INLINE void bd_walk(const bd_scene *sc, spm_key k, int mode, spm_walk *rw, float3 o,
                               float3 d, uint skip, float beta, float pdf_dir, bd_subpath *sp)
{
    int seg = 0;
    while (sp->n <= SPM_BDPT_SUBPATH) {
        uint j = (uint)(sp->n - 1);
        float t;
        bd_vertex *v = &sp->v[sp->n], *prev = &sp->v[sp->n - 1];
        int hit = intersect(sc->nodes, sc->tris, o, d, skip, &t, sc->counters BD_ALPHA);
        if (hit < 0)
            return;
        __global const spm_tri *tr = &sc->tris[hit];
        v->p = o + d * t;
        SPM_MATERIAL_AT(m, mi, sc->mats, sc->tex, sc->uvs, tr, (uint)hit, v->p, k, j);
        spm_frame fr;
        v->d = d;
        v->n = ld3(tr->n);
        v->tri = (uint)hit;
        hit_frame(tr, sc->vnormals, sc->tex, sc->uvs, (uint)hit, o, d, &fr);
        v->beta = beta;
        v->fwd = to_area(pdf_dir, prev->p, v->p, v->n);
        v->rev = 0.0f;
        if (seg) /* the segment's length inside: the medium's absorption */
            prev->x.lobe = t;
        v->emit = SPM_NONE;
        float ecos = -dot3(d, v->n);
        if (m.type & SPM_EMIT_TWOSIDED)
            ecos = fabs(ecos); /* the back face emits too (refcpu_bdpt.c vertex_emission) */
        if (mode == SPM_RADIANCE && ecos > 0.0f)
            v->emit = light_eval_at(m, ecos, &v->escale, sc->tex, sc->uvs, (uint)hit, tr, v->p,
                                    k, j, 0u);
        spm_bsdf b;
        b.commit = 0; /* only the types whose index a bin sets write it */
        bsdf_begin(m, &fr, k, j, rw, &b);
        v->disp = b.commit != 0;
        float mmean, minv;
        v->refl = bsdf_lobe(m, &b, &mmean, &minv);
        v->refl = texture_seen(sc->tex, sc->uvs, mi, (uint)hit, tr, v->p, &sc->cam, k, j, v->refl,
                               m.refl, &mmean, &minv);
        v->x = (spm_vertex_ext){0u, 0.0f, 0.0f, 0.0f};
        v->col2 = bsdf_record(m, &b, rw, &v->x);
        v->delta = !b.nee;
        sp->n++;
        spm_bsample s;
        if (v->refl == SPM_NONE || !(key_rng(k, SPM_DIM_VERTEX(j) + SPM_DIM_RR) < mmean) ||
            sp->n > SPM_BDPT_SUBPATH || !bsdf_sample(m, &b, &fr, k, j, mode, &s) ||
            (fr.smooth && (s.refract ? !(dot3(s.wi, fr.gn) < 0.0f) : !(dot3(s.wi, fr.gn) > 0.0f))))
            return;
        beta *= minv;
        beta *= s.wt;
        beta *= s.w;
        if (mode == SPM_IMPORTANCE)
            beta *= adjoint_ns(&fr, -d, s.wi);
        pdf_dir = lobe_pdf(v->delta, m, &fr, &b, -d, s.wi, mode);
        prev->rev = to_area(lobe_pdf(v->delta, m, &fr, &b, s.wi, -d, mode), v->p, prev->p, prev->n);
        seg = s.inside;
        v->x.lobe = s.cos_lobe;
        o = v->p;
        d = s.wi;
        skip = (uint)hit;
    }
}

/* The camera subpath of key k: the lens vertex, then the walk. */
SPM_ALWAYS_INLINE void camera_subpath(const bd_scene *sc, spm_key k, spm_walk *rw, bd_subpath *z)
{
    float3 o, d;
    float pp, pd;
    camera_key_ray(&sc->cam, k, &o, &d);
    camera_pdf_We(&sc->cam, o, d, &pp, &pd);
    bd_vertex *v = &z->v[0];
    *v = (bd_vertex){0};
    v->p = o;
    v->beta = 1.0f;
    v->fwd = pp;
    z->n = 1;
    if (pd > 0.0f)
        bd_walk(sc, k, SPM_RADIANCE, rw, o, d, 0xFFFFFFFFu, 1.0f, pd, z);
}

/* The light subpath of key k (the light tracer's start): the light by the
 * selection, its ray, beta = Le |cos_o| / (pmf pdf_pos pdf_dir); the walk. */
SPM_ALWAYS_INLINE void light_subpath(const bd_scene *sc, const spm_trace_params *p, spm_key k,
                                     spm_walk *rw, bd_subpath *y)
{
    uint ei = light_pick(p, sc->emitters, k, SPM_DIM_VERTEX(0));
    __global const spm_emitter *e = &sc->emitters[ei];
    float3 o, d;
    float pp, pd, scale, cos_o;
    bd_vertex *v = &y->v[0];
    *v = (bd_vertex){0};
    y->n = 0;
    y->e = ei;
    light_sample_emission(sc->tris, sc->emitters, ei, key_rng(k, SPM_DIM_LT_EMIT),
                          key_rng(k, SPM_DIM_LT_EMIT + 1u), key_rng(k, SPM_DIM_LT_EMIT + 2u),
                          key_rng(k, SPM_DIM_LT_EMIT + 3u), &o, &d, &pp, &pd);
    if (!(pp > 0.0f && pd > 0.0f))
        return;
    y->colour = lt_emission(sc->tris, sc->mats, e, d, &scale, &cos_o);
    y->ts = 1.0f; /* a textured emission, looked up once as the light tracer's start does */
    if (e->kind == SPM_LIGHT_AREA)
        y->colour = emit_texture(sc->tex, sc->uvs, e->tri, &sc->tris[e->tri], o, k, SPM_MAX_DEPTH,
                                 0u, y->colour, &y->ts);
    v->p = o;
    if (e->kind == SPM_LIGHT_AREA)
        v->n = ld3(sc->tris[e->tri].n);
    v->fwd = e->pdf * pp;
    y->n = 1;
    if (y->colour == SPM_NONE)
        return;
    uint skip = e->kind == SPM_LIGHT_AREA ? e->tri : 0xFFFFFFFFu;
    v->d = d; /* its ray's direction: a light at infinity's, for s = 1 */
    bd_walk(sc, k, SPM_IMPORTANCE, rw, o, d, skip, scale * y->ts * cos_o / (e->pdf * pp * pd),
            pd, y);
    if (y->n > 1 && light_at_infinity(e)) /* y[1] by the disc: pdf_pos |cos| */
        y->v[1].fwd = pp * fabs(dot3(y->v[1].n, d));
}

/* One end of a join lies in the other's face plane, within the rounding of
 * the hit points (refcpu_bdpt.c in_plane: 16 ulps of the largest
 * coordinate): its cosine there is noise of either sign, which would join
 * the two faces of one wall through it. n = 0: an end off a surface. */
SPM_ALWAYS_INLINE int bd_in_plane(float3 a, float3 na, float3 b, float3 nb)
{
    float3 d = b - a, m3 = fmax(fabs(a), fabs(b));
    float tau = 16.0f * FLT_EPSILON * fmax(m3.x, fmax(m3.y, m3.z));
    return (dot3(na, na) > 0.0f && fabs(dot3(d, na)) <= tau) ||
           (dot3(nb, nb) > 0.0f && fabs(dot3(d, nb)) <= tau);
}

/* ---- the joins ----------------------------------------------------------- */

/* s = 0: camera vertex pt = z[t-1] on an emitter, Le toward z[t-2]; the
 * light's densities of pt (pmf / area) and of its ray to z[t-2] (the face's
 * cosine lobe, either face's of a two-sided light). */
SPM_ALWAYS_INLINE int join_emitter(const bd_scene *sc, const bd_subpath *z, int t, bd_join *J)
{
    const bd_vertex *pt = &z->v[t - 1], *pm = &z->v[t - 2];
    if (pt->emit == SPM_NONE)
        return 0;
    J->c = pt->beta * pt->escale;
    __global const spm_tri *tr = &sc->tris[pt->tri];
    float3 w;
    toward(pt->p, pm->p, &w);
    J->pt_rev = sc->light_pdf[pt->tri] / tr->area;
    int two = (sc->mats[tr->material].type & SPM_EMIT_TWOSIDED) != 0;
    J->ptm_rev = to_area(light_area_pdf_dir(two, ld3(tr->n), w), pt->p, pm->p, pm->n);
    return J->c > 0.0f;
}

/* t = 1, s >= 2: light vertex qs = y[s-1] seen from the camera (a lens
 * point of its own), splatted where it lands: beta f |cos| We / pdf_Wi. */
SPM_ALWAYS_INLINE int join_camera(const bd_scene *sc, spm_key ky, const bd_subpath *y, int s,
                                  bd_join *J)
{
    const bd_vertex *qs = &y->v[s - 1];
    if (qs->delta)
        return 0;
    float3 wi;
    float dist, pdf, pp, pd;
    float2 film;
    uint dim = SPM_DIM_VERTEX(s - 2) + SPM_DIM_EPOINT_A;
    float we = camera_sample_Wi(&sc->cam, qs->p, key_rng(ky, dim), key_rng(ky, dim + 1u), &wi,
                                &dist, &pdf, &film);
    if (!(we > 0.0f) || !(pdf > 0.0f) || !bd_visible(sc, qs->p, qs->tri, wi, dist))
        return 0;
    J->px = film_pixel(&sc->cam, film);
    spm_material m;
    spm_frame fr;
    spm_bsdf b;
    vertex_state(sc, y, s - 1, ky, &m, &fr, &b);
    spm_eval e = bsdf_eval(m, &b, &fr, wi, SPM_IMPORTANCE | SPM_JOIN);
    float f = qs->beta * (e.k * e.f / e.div) / e.post * adjoint_ns(&fr, fr.back, wi);
    J->arg_qs = e.cos_light;
    J->c = f * we / pdf;
    float3 lens = qs->p + wi * dist;
    camera_pdf_We(&sc->cam, lens, -wi, &pp, &pd);
    J->qs_rev = to_area(pd, lens, qs->p, qs->n);
    J->qsm_rev = to_area(lobe_pdf(0, m, &fr, &b, wi, fr.back, SPM_IMPORTANCE), qs->p,
                         y->v[s - 2].p, y->v[s - 2].n);
    return J->c > 0.0f;
}

/* light vertex qs = y[s-1] toward `back` (s >= 2): *fy its beta f |cos|,
 * *py its density of that ray; qs- 's density through it (J->qsm_rev) */
SPM_ALWAYS_INLINE void light_side(const bd_scene *sc, spm_key ky, const bd_subpath *y, int s,
                                  float3 back, float *fy, float *py, bd_join *J)
{
    const bd_vertex *qs = &y->v[s - 1];
    spm_material m;
    spm_frame fr;
    spm_bsdf b;
    vertex_state(sc, y, s - 1, ky, &m, &fr, &b);
    spm_eval ey = bsdf_eval(m, &b, &fr, back, SPM_IMPORTANCE | SPM_JOIN);
    *fy = qs->beta * (ey.k * ey.f / ey.div) / ey.post * adjoint_ns(&fr, fr.back, back);
    J->arg_qs = ey.cos_light;
    *py = lobe_pdf(0, m, &fr, &b, fr.back, back, SPM_IMPORTANCE);
    J->qsm_rev = to_area(lobe_pdf(0, m, &fr, &b, back, fr.back, SPM_IMPORTANCE), qs->p,
                         y->v[s - 2].p, y->v[s - 2].n);
}

/* A camera vertex's argument for its join along w (dist long), arg its
 * eval's: an absorbing vertex's (the ABSORB kind: glass) is the medium's
 * length when the join runs into its back face's side, inside (a sampled
 * ray's `inside`), else none (refcpu_bdpt.c join_arg). */
SPM_ALWAYS_INLINE float join_arg(const bd_vertex *v, const spm_frame *fr, float3 w, float dist,
                                 float arg)
{
    if (SPM_VX_KIND(v->x) != SPM_FK_ABSORB)
        return arg;
    return dot3(w, fr->ng) < 0.0f ? dist : 0.0f;
}

/* s >= 1, t >= 2: z[t-1] joined to y[s-1] (s = 1: the light's point):
 *   beta_z f_z |cos| f_y |cos| beta_y / d^2, f_y |cos| the light's
 *   Le |cos_o| / (pmf pdf_pos) at s = 1. */
SPM_ALWAYS_INLINE int join_inner(const bd_scene *sc, spm_key k, spm_key ky, const bd_subpath *z,
                                 int t, const bd_subpath *y, int s, bd_join *J)
{
    const bd_vertex *pt = &z->v[t - 1], *qs = &y->v[s - 1], *pm = &z->v[t - 2];
    if (pt->delta || (s > 1 && qs->delta))
        return 0;
    if (bd_in_plane(pt->p, pt->n, qs->p, qs->n))
        return 0;
    float3 w;
    float fy, py;
    float dist = toward(pt->p, qs->p, &w);
    float3 back = -w;
    spm_material m;
    spm_frame fr;
    spm_bsdf b;
    vertex_state(sc, z, t - 1, k, &m, &fr, &b);
    spm_eval ez = bsdf_eval(m, &b, &fr, w, SPM_RADIANCE | SPM_JOIN);
    float fz = (ez.k * ez.f / ez.div) / ez.post;
    J->arg_pt = join_arg(pt, &fr, w, dist, ez.cos_light);
    if (s == 1) {
        float scale, cos_o, pp, pd;
        __global const spm_emitter *e = &sc->emitters[y->e];
        if (lt_emission(sc->tris, sc->mats, e, back, &scale, &cos_o) == SPM_NONE)
            return 0;
        fy = scale * y->ts * cos_o / qs->fwd;
        light_pdf_emission(sc->tris, e, qs->p, back, &pp, &pd);
        py = pd; /* the light's density of its ray toward pt */
    } else {
        light_side(sc, ky, y, s, back, &fy, &py, J);
    }
    J->c = pt->beta * fz * fy / (dist * dist);
    __global const spm_emitter *ye = &sc->emitters[y->e];
    uint qt = s > 1 ? qs->tri : ye->kind == SPM_LIGHT_AREA ? ye->tri : 0xFFFFFFFFu;
    if (!(J->c > 0.0f) || !bd_visible_join(sc, pt->p, pt->tri, qs->p, qt, w, dist))
        return 0;
    J->pt_rev = to_area(py, qs->p, pt->p, pt->n);
    J->ptm_rev = to_area(lobe_pdf(0, m, &fr, &b, w, fr.back, SPM_RADIANCE), pt->p, pm->p, pm->n);
    J->qs_rev = to_area(lobe_pdf(0, m, &fr, &b, fr.back, w, SPM_RADIANCE), pt->p, qs->p, qs->n);
    return 1;
}

/* s = 1, t >= 2, a light at infinity along one direction (a distant
 * light; refcpu_bdpt.c join_infinite): z[t-1] lit along the light
 * subpath's direction, unoccluded to infinity, beta_z f_z |cos| Le / pmf;
 * pt's density by the light pdf_pos |cos at pt|, the light vertex's by pt
 * in solid angle (pbrt-v4's PdfLight of an infinite light). */
SPM_ALWAYS_INLINE int join_infinite(const bd_scene *sc, spm_key k, const bd_subpath *z, int t,
                                    const bd_subpath *y, bd_join *J)
{
    const bd_vertex *pt = &z->v[t - 1], *pm = &z->v[t - 2];
    __global const spm_emitter *e = &sc->emitters[y->e];
    float3 d0 = y->v[0].d, w = -d0;
    float scale, cos_o, pp, pd;
    if (pt->delta || lt_emission(sc->tris, sc->mats, e, d0, &scale, &cos_o) == SPM_NONE)
        return 0;
    spm_material m;
    spm_frame fr;
    spm_bsdf b;
    vertex_state(sc, z, t - 1, k, &m, &fr, &b);
    spm_eval ez = bsdf_eval(m, &b, &fr, w, SPM_RADIANCE | SPM_JOIN);
    J->arg_pt = ez.cos_light;
    J->c = pt->beta * ((ez.k * ez.f / ez.div) / ez.post) * scale * cos_o / e->pdf;
    if (!(J->c > 0.0f) || !bd_visible(sc, pt->p, pt->tri, w, INFINITY))
        return 0;
    light_pdf_emission(sc->tris, e, y->v[0].p, d0, &pp, &pd);
    J->pt_rev = pp * fabs(dot3(pt->n, w));
    J->ptm_rev = to_area(lobe_pdf(0, m, &fr, &b, w, fr.back, SPM_RADIANCE), pt->p, pm->p, pm->n);
    J->qs_rev = lobe_pdf(0, m, &fr, &b, fr.back, w, SPM_RADIANCE);
    return 1;
}

/* pbrt-v4 MISWeight over the subpaths' densities with the join's put in
 * (the joined vertices no deltas): with r_i the ratio of the densities of
 * the strategy that samples one more vertex from the other side to this
 * one's, w = 1 / (1 + sum_i prod_{j <= i} rev_j / fwd_j), a term left out
 * when the vertex it moves (or its neighbour) is a delta
 * (refcpu_bdpt.c spm_ref_bdpt_mis). */
SPM_ALWAYS_INLINE float join_mis(const bd_subpath *z, int t, const bd_subpath *y, int s,
                                 const bd_join *J, int light_delta)
{
    if (s + t == 2)
        return 1.0f;
    float sum = 0.0f, r = 1.0f;
    for (int i = t - 1; i > 0; i--) {
        float rev = i == t - 1 ? J->pt_rev : i == t - 2 ? J->ptm_rev : z->v[i].rev;
        r *= remap0(rev) / remap0(z->v[i].fwd);
        int d0 = i == t - 1 ? 0 : z->v[i].delta, d1 = i - 1 == t - 1 ? 0 : z->v[i - 1].delta;
        if (!d0 && !d1)
            sum += r;
    }
    r = 1.0f;
    for (int i = s - 1; i >= 0; i--) {
        float rev = i == s - 1 ? J->qs_rev : i == s - 2 ? J->qsm_rev : y->v[i].rev;
        r *= remap0(rev) / remap0(y->v[i].fwd);
        int d0 = i == s - 1 ? 0 : y->v[i].delta;
        int before = i > 0 ? y->v[i - 1].delta : light_delta;
        if (!d0 && !before)
            sum += r;
    }
    return 1.0f / (1.0f + sum);
}

/* ---- the connected path's record ---------------------------------------- */

/* the argument of light vertex i's segment toward the vertex it came from
 * (the medium's length inside when both are of the absorbing kind) */
SPM_ALWAYS_INLINE float light_arg(const bd_subpath *y, int i)
{
    const bd_vertex *v = &y->v[i], *from = &y->v[i - 1];
    if (SPM_VX_KIND(v->x) != SPM_FK_ABSORB)
        return v->x.lobe;
    return i > 1 && SPM_VX_KIND(from->x) == SPM_FK_ABSORB ? from->x.lobe : 0.0f;
}

/* A dispersive vertex's words: the connected path's first one (in record
 * order) commits it to the sample's bin lam with 1 / its pdf (spm_shared.h
 * SPM_VX_LAMBDA), so the wavelength's pdf is counted once whichever subpath
 * drew it; the others carry no bin. */
SPM_ALWAYS_INLINE void disp_words(spm_vertex_ext *x, int *first, uint lam)
{
    uint col = *first ? lam : SPM_NONE;
    x->ids = (x->ids & ~SPM_VX_COLMASK) | ((col + 1u) & SPM_VX_COLMASK);
    if (*first)
        x->light = (float)SPM_TRUTH_BINS;
    *first = 0;
}

/* Record vertex n of the connected path: the subpath vertex it is (camera
 * vertex i for n < t - 1, else light vertex s - 1 - (n - (t - 1))) and its
 * words; a joined vertex's argument its eval's, the last one carries the
 * light's emission, whose factor reads the light sample's word. */
SPM_ALWAYS_INLINE const bd_vertex *path_vertex(const bd_subpath *z, int t, const bd_subpath *y,
                                              int s, const bd_join *J, int n, int nv,
                                              spm_vertex_ext *x)
{
    int camera = n < t - 1;
    int i = camera ? n + 1 : s - 1 - (n - (t - 1));
    const bd_vertex *v = camera ? &z->v[i] : &y->v[i];
    *x = v->x;
    if (camera && i < t - 1)
        return v;
    int joined = i == s - 1 && SPM_VX_KIND(v->x) != SPM_FK_ABSORB; /* else its segment's */
    float arg = camera ? J->arg_pt : joined ? J->arg_qs : light_arg(y, i);
    int last = n == nv - 1;
    x->lobe = last ? 0.0f : arg;
    x->light = last ? arg : x->light;
    return v;
}

/* Writes strategy (s, t)'s path with weight c at its emission into record
 * slot `slot` of stride npaths, its level byte too (the feeler over its
 * colours, refcpu_bdpt.c path_level's order). 0: a black vertex on it, no
 * slot taken. */
SPM_ALWAYS_INLINE int write_path(const bd_subpath *z, int t, const bd_subpath *y, int s,
                                 const bd_join *J, float c, uint lam, __global const uchar *lvlk,
                                 uint init_level, uint npaths, __global spm_dev_head *heads,
                                 __global spm_vertex *verts, __global uchar *levels,
                                 __global int *rstat, uint *slot)
{
    int nv = (t - 1) + (s > 0 ? s - 1 : 0) - (s == 0), first = 1;
    uint emit = s == 0 ? z->v[t - 1].emit : y->colour;
    spm_vertex_ext x;
    for (int n = 0; n < nv; n++)
        if (path_vertex(z, t, y, s, J, n, nv, &x)->refl == SPM_NONE)
            return 0;
    *slot = (uint)atomic_inc(&rstat[0]);
    if (*slot >= npaths)
        return 1;
    spm_path_head hd = {(uint)nv, SPM_END_ABSORBED, SPM_NONE, 0.0f, SPM_NONE, 0.0f, 0u, 0u};
    uint level = init_level, setby = SPM_SETBY_NONE;
    ushort seen[SPM_MAX_DEPTH];
    if (nv == 0) {
        hd.first_emit = emit;
        hd.first_emit_c = c;
        feel(lvlk, emit, 1u, SPM_SETBY_EMITTER, &level, &setby);
    }
    for (int n = 0; n < nv; n++) {
        const bd_vertex *v = path_vertex(z, t, y, s, J, n, nv, &x);
        spm_vertex rv = {v->refl | (SPM_NONE << 16), 0.0f};
        if (v->disp)
            disp_words(&x, &first, lam);
        if (n == nv - 1 && s == 0) { /* the emitter the last camera vertex's ray hit */
            x.ids = (x.ids & 0xFFFFu) | SPM_VX_HIT_BITS(emit);
            x.hit_c = c;
        } else if (n == nv - 1) {
            rv.ids = (rv.ids & 0xFFFFu) | (emit << 16);
            rv.c = c;
        }
        verts[(size_t)n * npaths + *slot] = rv;
        ((__global spm_vertex_ext *)SPM_VERTEX_EXT(verts, npaths) + *slot)[(size_t)n * npaths] = x;
        seen[n] = (ushort)v->refl;
        feel(lvlk, v->refl, occurrences(seen, (uint)n, v->refl), SPM_SETBY_REFLECTOR, &level,
             &setby);
        if ((rv.ids >> 16) != SPM_NONE)
            feel(lvlk, rv.ids >> 16, 1u, SPM_SETBY_EMITTER, &level, &setby);
        if (SPM_VX_HIT(x) != SPM_NONE)
            feel(lvlk, SPM_VX_HIT(x), 1u, SPM_SETBY_EMITTER, &level, &setby);
        if (v->col2 != SPM_NONE)
            feel(lvlk, v->col2, 1u, SPM_SETBY_REFLECTOR, &level, &setby);
    }
    heads[*slot] = spm_dev_head_pack(&hd);
    levels[*slot] = (uchar)(level | (setby << SPM_SETBY_SHIFT));
    return 1;
}

/* One work-item per sample: sample first_path + gid of the pass, keyed as
 * that camera path (pixel i / spp, sample first_sample + i % spp); each
 * strategy that finds light becomes a record and its pixel word. */
__kernel void spm_bdpt_trace(SPM_TRACE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA),
                             SPM_BDPT_TRACE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint gid = get_global_id(0);
    if (gid >= nsamples)
        return;
    uint i = first_path + gid;
    spm_key k = {p.seed, i / p.spp_per_pass, p.first_sample + i % p.spp_per_pass};
    spm_key ky = {p.seed ^ SPM_BDPT_LIGHT_SEED, k.pixel, k.sample};
    bd_scene sc = {tris, nodes,     emitters, mats,  light_pdf, vnormals, disp,
                   uvs,  tex,       counters, p.cam, p.disperse, SPM_NONE};
    bd_subpath z, y;
    spm_walk rw = {disp, p.disperse, SPM_NONE};
    camera_subpath(&sc, k, &rw, &z);
    y.n = 0;
    y.e = 0u;
    if (p.nemitters > 0u)
        light_subpath(&sc, &p, ky, &rw, &y);
    sc.lam = rw.lam;
    int light_delta = y.n > 0 && emitters[y.e].kind != SPM_LIGHT_AREA;
    int infinite = y.n > 0 && light_at_infinity(&emitters[y.e]);
    for (int t = 1; t <= z.n; t++)
        for (int s = t == 1 ? 2 : 0; s <= y.n; s++) {
            bd_join J = {0.0f, 0.0f, 0.0f, k.pixel, 0.0f, 0.0f, 0.0f, 0.0f};
            int ok = s == 0   ? join_emitter(&sc, &z, t, &J)
                     : t == 1 ? join_camera(&sc, ky, &y, s, &J)
                     : s == 1 && infinite ? join_infinite(&sc, k, &z, t, &y, &J)
                              : join_inner(&sc, k, ky, &z, t, &y, s, &J);
            if (!ok)
                continue;
            float c = J.c * join_mis(&z, t, &y, s, &J, light_delta);
            uint slot;
            if (c > 0.0f && write_path(&z, t, &y, s, &J, c, sc.lam, lvlk, init_level, npaths, heads,
                                       verts, levels, rstat, &slot) &&
                slot < npaths) {
                rpx[slot] = J.px;
                rsam[slot] = i;
            }
        }
}

/* The largest binary exponent of a finite record value (frexp's, as
 * host/output/film_splat.c) into rstat[1]. Parameters: SPM_BDPT_EXP_ARGS. */
__kernel void spm_bdpt_exponent(SPM_BDPT_EXP_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint i = get_global_id(0);
    if (i >= n)
        return;
    int e = -1074, fin = 1;
    for (uint c = 0; c < SPM_PATH_CH; c++) {
        float v = xyz[(size_t)SPM_PATH_CH * i + c];
        int ex;
        fin &= (as_uint(v) & 0x7f800000u) != 0x7f800000u;
        if (v != 0.0f && (frexp(v, &ex), ex > e))
            e = ex;
    }
    if (fin && e > -1074)
        atomic_max(&rstat[1], e);
}
