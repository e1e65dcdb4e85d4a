/* CPU reference, the bidirectional path tracer (--integrator bdpt; refcpu_bdpt.h,
 * docs/ARCHITECTURE.md "Connected paths"). Per sample, in order:
 *   the camera subpath z (the pixel's ray as a camera path draws it, then
 *   the radiance-mode walk of the path loop: hit, BSDF, roulette, sampled
 *   direction) and the light subpath y (the light tracer's start and its
 *   importance-mode walk, keyed by a seed of its own so the two subpaths
 *   draw independent numbers); then every strategy (s, t), t >= 1, but
 *   (1, 1): s = 0 a camera vertex on an emitter, t = 1 a light vertex seen
 *   by the camera (splatted where it lands), else z[t-1] joined to y[s-1].
 * Each vertex keeps its densities per unit area in both directions (pbrt-v4's
 * pdfFwd, pdfRev) for MIS. A connected path is written as a camera path's
 * record (camera vertices, then the light's reversed, the light's emission
 * at the last) with its weight folded into the emission's, and shaded by the
 * shade stage at the level the feeler finds over its own colours; each
 * becomes a splat. Like the path loop it names no material type and no
 * light kind. */
#include "refcpu_bdpt.h"
#include <math.h>
#include <string.h>
#include <float.h>
#include "geometry_vec3.h"
#include "spm_rng.h"
#include "refcpu_bsdf.h"
#include "refcpu_lights.h"
#include "refcpu_camera.h"
#include "refcpu_shading.h"
#include "refcpu_feeler.h"
#include "refcpu_texture.h"
#include "refcpu_metalrough.h"

/* A subpath vertex: v[0] the endpoint (the lens or the light), v[1..] the
 * surface vertices. n: its triangle's normal (0 off a surface: a lens, a
 * point light); beta: the subpath's colour-independent throughput arriving
 * there (the colours apart, which the shade stage applies); emit, escale: a
 * camera vertex on an emitter, its emission toward the vertex before; disp:
 * its index is the sample's committed bin's (dispersive glass). */
typedef struct {
    float p[3], n[3];
    spm_ref_hit h;
    spm_ref_bsdf b;
    const spm_material *m;
    spm_material mix; /* m: the metallic-roughness mix's pick */
    spm_u32 tri, refl, col2, emit;
    float escale, beta;
    int disp;
    spm_bdpt_pdf pdf;
    spm_vertex_ext x;
} bd_vertex;

typedef struct {
    bd_vertex v[SPM_BDPT_SUBPATH + 1];
    int n;
    const spm_emitter *e; /* the light subpath's light and its colour */
    spm_u32 colour;
    float d0[3]; /* its ray's direction (a light at infinity's, for s = 1) */
    float ts; /* a textured emission's factor at the light's point */
} bd_subpath;

static float remap0(float f)
{
    return f != 0.0f ? f : 1.0f;
}

/* pbrt-v4 MISWeight: with r_i the ratio of the densities of the strategy
 * that samples one more vertex from the other side to this one's,
 *   w = 1 / (1 + sum_i prod_{j <= i} rev_j / fwd_j),
 * a term left out when the vertex it moves (or its neighbour) is a delta. */
float spm_ref_bdpt_mis(const spm_bdpt_pdf *z, int t, const spm_bdpt_pdf *y, int s,
                       int light_delta)
{
    if (s + t == 2)
        return 1.0f;
    float sum = 0.0f, r = 1.0f;
    for (int i = t - 1; i > 0; i--) {
        r *= remap0(z[i].rev) / remap0(z[i].fwd);
        if (!z[i].delta && !z[i - 1].delta)
            sum += r;
    }
    r = 1.0f;
    for (int i = s - 1; i >= 0; i--) {
        r *= remap0(y[i].rev) / remap0(y[i].fwd);
        int before = i > 0 ? y[i - 1].delta : light_delta;
        if (!y[i].delta && !before)
            sum += r;
    }
    return 1.0f / (1.0f + sum);
}

/* a solid-angle density at `from` toward `to` per unit area at `to`:
 * pdf |cos at to| / d^2 (no cosine off a surface) */
static float to_area(float pdf, const bd_vertex *from, const bd_vertex *to)
{
    float d[3];
    v3_sub(d, to->p, from->p);
    float d2 = v3_dot(d, d);
    if (!(d2 > 0.0f))
        return 0.0f;
    float c = v3_dot(to->n, to->n) > 0.0f ? fabsf(v3_dot(to->n, d)) / sqrtf(d2) : 1.0f;
    return pdf * c / d2;
}

/* w in the vertex's shading frame (t, n x t, n), the contract's pdf's */
static void to_local(const spm_ref_hit *h, const float w[3], float l[3])
{
    float b[3];
    v3_cross(b, h->n, h->t);
    l[0] = v3_dot(w, h->t);
    l[1] = v3_dot(w, b);
    l[2] = v3_dot(w, h->n);
}

/* the type's density at surface vertex v of sampling wi seen from wo (0 at
 * a delta), in solid angle */
static float lobe_pdf(const bd_vertex *v, const float wo[3], const float wi[3], int mode)
{
    float lo[3], li[3];
    if (v->pdf.delta)
        return 0.0f;
    to_local(&v->h, wo, lo);
    to_local(&v->h, wi, li);
    return spm_ref_pdf(v->m, &v->b, lo, li, mode);
}

/* unit direction from a to b, and the distance */
static float toward(const float a[3], const float b[3], float w[3])
{
    float d[3];
    v3_sub(d, b, a);
    float l = sqrtf(v3_dot(d, d));
    for (int i = 0; i < 3; i++)
        w[i] = l > 0.0f ? d[i] / l : 0.0f;
    return l;
}

/* surface vertex v's emission toward the camera vertex before it (a camera
 * subpath's vertex on an emitting face) */
static void vertex_emission(const spm_geometry *g, bd_vertex *v, const float d[3],
                            const spm_ref_key *k, int j)
{
    const spm_tri *tri = &g->tris[v->tri];
    float ecos = -v3_dot(d, tri->n);
    if (v->m->type & SPM_EMIT_TWOSIDED)
        ecos = fabsf(ecos);
    v->emit = ecos > 0.0f ? spm_ref_light_eval(v->m, ecos, &v->escale) : SPM_NONE;
    v->emit = spm_ref_emit_texture(g, v->tri, v->p, k, (spm_u32)j, 0u, v->emit, &v->escale);
}

/* The walk from the subpath's last vertex along o + t d (pdf_dir the
 * density of d there, in solid angle), in mode (SPM_REF_RADIANCE: the
 * camera's), until roulette, a miss or the cap ends it. rw is the sample's,
 * shared by both subpaths: the first dispersive vertex either meets commits
 * the bin (its own key's draw, the dimension of a camera path's and a light
 * subpath's), every later one on either subpath takes it. */
static void walk(const spm_geometry *g, const spm_material *mats, const spm_ref_key *k, int mode,
                 spm_ref_walk *rw, float o[3], float d[3], spm_u32 skip, float beta, float pdf_dir,
                 bd_subpath *sp)
{
    int seg = 0;
    while (sp->n <= SPM_BDPT_SUBPATH) {
        int j = sp->n - 1;
        float t;
        bd_vertex *v = &sp->v[sp->n], *prev = &sp->v[sp->n - 1];
        int hit = spm_ref_next_vertex(g, o, d, skip, &t, v->p, &v->h);
        if (hit < 0)
            return;
        v->tri = (spm_u32)hit;
        spm_u32 mi = spm_ref_mix_pick(g, mats, (spm_u32)hit, v->p, k, j, &v->mix);
        v->m = &v->mix;
        memcpy(v->n, g->tris[hit].n, sizeof v->n);
        v->beta = beta;
        v->pdf = (spm_bdpt_pdf){to_area(pdf_dir, prev, v), 0.0f, 0};
        if (seg) /* the segment's length inside: the medium's absorption */
            prev->x.lobe = t;
        v->emit = SPM_NONE;
        if (mode == SPM_REF_RADIANCE)
            vertex_emission(g, v, d, k, j);
        v->b.commit = 0; /* only the types whose index a bin sets write it */
        spm_ref_begin(v->m, &v->h, k, j, rw, &v->b);
        v->disp = v->b.commit != 0;
        float mmean, minv;
        v->refl = spm_ref_lobe(v->m, &v->b, &mmean, &minv);
        v->refl = spm_ref_texture_seen(g, mi, (spm_u32)hit, v->p, k, j, v->refl, v->m->refl,
                                       &mmean, &minv);
        v->x = (spm_vertex_ext){0u, 0.0f, 0.0f, 0.0f};
        v->col2 = spm_ref_record(v->m, &v->b, rw, &v->x);
        v->pdf.delta = !v->b.nee;
        sp->n++;
        spm_ref_bsample s;
        if (v->refl == SPM_NONE || !(spm_ref_rnd(k, SPM_DIM_VERTEX(j) + SPM_DIM_RR) < mmean) ||
            sp->n > SPM_BDPT_SUBPATH || !spm_ref_sample_sided(v->m, &v->b, &v->h, k, j, mode, &s))
            return;
        beta *= minv;
        beta *= s.wt;
        beta *= s.w;
        float wo[3] = {-d[0], -d[1], -d[2]};
        if (mode == SPM_REF_IMPORTANCE)
            beta *= spm_ref_adjoint_ns(&v->h, wo, s.wi);
        pdf_dir = lobe_pdf(v, wo, s.wi, mode);
        prev->pdf.rev = to_area(lobe_pdf(v, s.wi, wo, mode), v, prev);
        seg = s.inside;
        v->x.lobe = s.cos_lobe;
        for (int i = 0; i < 3; i++)
            o[i] = v->p[i], d[i] = s.wi[i];
        skip = (spm_u32)hit;
    }
}

/* The camera subpath of sample k: the lens vertex, then the walk. */
static void camera_subpath(const spm_geometry *g, const spm_material *mats, const spm_ref_key *k,
                           spm_ref_walk *rw, bd_subpath *z)
{
    float o[3], d[3], pp, pd;
    spm_ref_pixel_ray(&g->cam, k->seed, k->pixel, k->sample, o, d);
    spm_ref_camera_pdf_We(&g->cam, o, d, &pp, &pd);
    bd_vertex *v = &z->v[0];
    memset(v, 0, sizeof *v);
    memcpy(v->p, o, sizeof v->p);
    v->beta = 1.0f;
    v->pdf.fwd = pp;
    z->n = 1;
    if (pd > 0.0f)
        walk(g, mats, k, SPM_REF_RADIANCE, rw, o, d, 0xFFFFFFFFu, 1.0f, pd, z);
}

/* The light subpath (the light tracer's start): the light by the selection,
 * its ray, beta = Le |cos_o| / (pmf pdf_pos pdf_dir); then the walk. */
static void light_subpath(const spm_geometry *g, const spm_material *mats, const spm_ref_key *k,
                          spm_ref_walk *rw, bd_subpath *y)
{
    const spm_emitter *e = spm_ref_light_pick(g, k, SPM_DIM_VERTEX(0));
    float u[4] = {spm_ref_rnd(k, SPM_DIM_LT_EMIT), spm_ref_rnd(k, SPM_DIM_LT_EMIT + 1u),
                  spm_ref_rnd(k, SPM_DIM_LT_EMIT + 2u), spm_ref_rnd(k, SPM_DIM_LT_EMIT + 3u)};
    float o[3], d[3], pp, pd, scale, cos_o;
    bd_vertex *v = &y->v[0];
    memset(v, 0, sizeof *v);
    y->n = 0;
    y->e = e;
    spm_ref_light_sample_emission(g, (spm_u32)(e - g->emitters), u, o, d, &pp, &pd);
    if (!(pp > 0.0f && pd > 0.0f))
        return;
    y->colour = spm_ref_lt_emission(g, mats, e, d, &scale, &cos_o);
    y->ts = 1.0f; /* a textured emission, looked up once as the light tracer's start does */
    if (e->kind == SPM_LIGHT_AREA)
        y->colour = spm_ref_emit_texture(g, e->tri, o, k, SPM_MAX_DEPTH, 0u, y->colour, &y->ts);
    memcpy(v->p, o, sizeof v->p);
    if (e->kind == SPM_LIGHT_AREA)
        memcpy(v->n, g->tris[e->tri].n, sizeof v->n);
    v->pdf.fwd = e->pdf * pp;
    y->n = 1;
    if (y->colour == SPM_NONE)
        return;
    spm_u32 skip = e->kind == SPM_LIGHT_AREA ? e->tri : 0xFFFFFFFFu;
    memcpy(y->d0, d, sizeof y->d0);
    walk(g, mats, k, SPM_REF_IMPORTANCE, rw, o, d, skip, scale * y->ts * cos_o / (e->pdf * pp * pd),
         pd, y);
    if (y->n > 1 && spm_ref_light_at_infinity(e)) /* y[1] by the disc: pdf_pos |cos| */
        y->v[1].pdf.fwd = pp * fabsf(v3_dot(y->v[1].n, y->d0));
}

/* ---- one connected path ------------------------------------------------- */

/* What strategy (s, t) found: its weight without MIS, the pixel, the spectral
 * arguments of the two joined vertices (their eval's cos_light), and the
 * densities the connected path gives the joined vertices and their
 * neighbours (pbrt-v4's a1 .. a4: pt, pt-, qs, qs-). */
typedef struct {
    float c, arg_pt, arg_qs;
    spm_u32 px;
    float pt_rev, ptm_rev, qs_rev, qsm_rev;
} bd_join;

/* the segment from a to b is clear (a's triangle skipped from a) */
static int visible(const spm_geometry *g, const float a[3], spm_u32 skip, const float w[3],
                   float dist)
{
    float ts;
    spm_ref_record_ray(a, w, skip, SPM_RAY_CLOSEST);
    return !(spm_bvh_intersect(g, a, w, skip, &ts) >= 0 && ts < dist * (1.0f - 1e-4f));
}

/* the segment from a to b is clear both ways, a's and b's triangles skipped
 * (bt: none off a surface). The test from a passes a face within dist 1e-4
 * of b: at an edge of a closed box of metal, a light vertex on one face
 * sees out through the next. A face other than b's met in that last piece
 * is judged from b, where it lies at the start of the ray; b's own face
 * first clears the segment with one ray. */
static int visible_join(const spm_geometry *g, const float a[3], spm_u32 at, const float b[3],
                        spm_u32 bt, const float w[3], float dist)
{
    float ts, back[3] = {-w[0], -w[1], -w[2]};
    spm_ref_record_ray(a, w, at, SPM_RAY_CLOSEST);
    int hit = spm_bvh_intersect(g, a, w, at, &ts);
    if (hit < 0 || (spm_u32)hit == bt)
        return 1;
    return ts >= dist * (1.0f - 1e-4f) && visible(g, b, bt, back, dist);
}

/* One end of a join lies in the other's face plane, within the rounding of
 * the hit points (|dot(b - a, n_a)| <= 16 ulps of the largest coordinate;
 * measured: two ulps between the faces of a wall of the closed lamp): the
 * cosine there is rounding noise, of either sign, and would let two
 * vertices on the two faces of one wall join through it. Such a join's
 * true cosine is below 16 ulps / dist: what is dropped is of that order.
 * n = 0: an end off a surface (a point light). */
static int in_plane(const float a[3], const float na[3], const float b[3], const float nb[3])
{
    float d[3], m = 0.0f;
    v3_sub(d, b, a);
    for (int i = 0; i < 3; i++)
        m = fmaxf(m, fmaxf(fabsf(a[i]), fabsf(b[i])));
    float tau = 16.0f * FLT_EPSILON * m;
    return (v3_dot(na, na) > 0.0f && fabsf(v3_dot(d, na)) <= tau) ||
           (v3_dot(nb, nb) > 0.0f && fabsf(v3_dot(d, nb)) <= tau);
}

/* s = 0: camera vertex pt = z[t-1] on an emitter, Le toward z[t-2]; the
 * light's densities of pt (pmf / area) and of its ray to z[t-2] (its
 * emission sampling's: the face's cosine lobe, either face's of a
 * two-sided light). */
static int join_emitter(const spm_geometry *g, const bd_subpath *z, int t, bd_join *J)
{
    const bd_vertex *pt = &z->v[t - 1], *pm = &z->v[t - 2];
    if (pt->emit == SPM_NONE)
        return 0;
    J->c = pt->beta * pt->escale;
    const spm_tri *tri = &g->tris[pt->tri];
    float w[3];
    toward(pt->p, pm->p, w);
    J->pt_rev = g->light_pdf[pt->tri] / tri->area; /* the light subpaths pick by power */
    int two = (pt->m->type & SPM_EMIT_TWOSIDED) != 0;
    J->ptm_rev = to_area(spm_ref_light_area_pdf_dir(two, tri->n, w), pt, pm);
    return J->c > 0.0f;
}

/* t = 1, s >= 2: light vertex qs = y[s-1] seen from the camera (a lens
 * point of its own), splatted where it lands: beta f |cos| We / pdf_Wi (the
 * light's own point seen, (1, 1), is the camera subpath's (0, 2)). */
static int join_camera(const spm_geometry *g, const spm_ref_key *k, const bd_subpath *y, int s,
                       bd_join *J)
{
    const bd_vertex *qs = &y->v[s - 1];
    if (qs->pdf.delta)
        return 0;
    float wi[3], dist, pdf, film[2], lens[3], pp, pd, f;
    spm_u32 dim = SPM_DIM_VERTEX(s - 2) + SPM_DIM_EPOINT_A;
    float we = spm_ref_camera_sample_Wi(&g->cam, qs->p, spm_ref_rnd(k, dim),
                                        spm_ref_rnd(k, dim + 1u), wi, &dist, &pdf, film);
    if (!(we > 0.0f) || !(pdf > 0.0f) || !visible(g, qs->p, qs->tri, wi, dist))
        return 0;
    J->px = spm_ref_lt_film_pixel(&g->cam, film);
    spm_ref_eval e =
        spm_ref_eval_bsdf(qs->m, &qs->b, &qs->h, wi, SPM_REF_IMPORTANCE | SPM_REF_JOIN);
    float wq[3] = {-qs->h.d[0], -qs->h.d[1], -qs->h.d[2]};
    f = qs->beta * (e.k * e.f / e.div) / e.post * spm_ref_adjoint_ns(&qs->h, wq, wi);
    J->arg_qs = e.cos_light;
    J->c = f * we / pdf;
    bd_vertex lv = {0};
    for (int i = 0; i < 3; i++)
        lv.p[i] = qs->p[i] + wi[i] * dist, lens[i] = lv.p[i];
    float back[3] = {-wi[0], -wi[1], -wi[2]};
    spm_ref_camera_pdf_We(&g->cam, lens, back, &pp, &pd);
    J->qs_rev = to_area(pd, &lv, qs);
    float wo[3] = {-qs->h.d[0], -qs->h.d[1], -qs->h.d[2]};
    J->qsm_rev = to_area(lobe_pdf(qs, wi, wo, SPM_REF_IMPORTANCE), qs, &y->v[s - 2]);
    return J->c > 0.0f;
}

/* Camera vertex v's argument for its join along w (dist long), arg its
 * eval's: an absorbing vertex's (the ABSORB kind: glass) is the medium's
 * length when the join runs into its back face's side, inside (a sampled
 * ray's `inside`), else none. */
static float join_arg(const bd_vertex *v, const float w[3], float dist, float arg)
{
    if (SPM_VX_KIND(v->x) != SPM_FK_ABSORB)
        return arg;
    return v3_dot(w, v->h.ng) < 0.0f ? dist : 0.0f;
}

/* s >= 1, t >= 2: z[t-1] joined to y[s-1] (s = 1: the light's point):
 *   beta_z f_z |cos| f_y |cos| beta_y / d^2, f_y |cos| the light's
 *   Le |cos_o| / (pmf pdf_pos) at s = 1. */
static int join_inner(const spm_geometry *g, const spm_material *mats, const bd_subpath *z, int t,
                      const bd_subpath *y, int s, bd_join *J)
{
    const bd_vertex *pt = &z->v[t - 1], *qs = &y->v[s - 1], *pm = &z->v[t - 2];
    if (pt->pdf.delta || (s > 1 && qs->pdf.delta))
        return 0;
    float w[3], back[3], fy, py;
    if (in_plane(pt->p, pt->n, qs->p, qs->n))
        return 0;
    float dist = toward(pt->p, qs->p, w);
    for (int i = 0; i < 3; i++)
        back[i] = -w[i];
    spm_ref_eval ez =
        spm_ref_eval_bsdf(pt->m, &pt->b, &pt->h, w, SPM_REF_RADIANCE | SPM_REF_JOIN);
    float fz = (ez.k * ez.f / ez.div) / ez.post;
    J->arg_pt = join_arg(pt, w, dist, ez.cos_light);
    if (s == 1) {
        float scale, cos_o, pp, pd;
        if (spm_ref_lt_emission(g, mats, y->e, back, &scale, &cos_o) == SPM_NONE)
            return 0;
        fy = scale * y->ts * cos_o / qs->pdf.fwd;
        spm_ref_light_pdf_emission(g, (spm_u32)(y->e - g->emitters), qs->p, back, &pp, &pd);
        py = pd; /* the light's density of its ray toward pt */
    } else {
        spm_ref_eval ey = spm_ref_eval_bsdf(qs->m, &qs->b, &qs->h, back,
                                            SPM_REF_IMPORTANCE | SPM_REF_JOIN);
        float wo[3] = {-qs->h.d[0], -qs->h.d[1], -qs->h.d[2]};
        fy = qs->beta * (ey.k * ey.f / ey.div) / ey.post * spm_ref_adjoint_ns(&qs->h, wo, back);
        J->arg_qs = ey.cos_light;
        py = lobe_pdf(qs, wo, back, SPM_REF_IMPORTANCE);
        J->qsm_rev = to_area(lobe_pdf(qs, back, wo, SPM_REF_IMPORTANCE), qs, &y->v[s - 2]);
    }
    J->c = pt->beta * fz * fy / (dist * dist);
    spm_u32 qt = s > 1 ? qs->tri : y->e->kind == SPM_LIGHT_AREA ? y->e->tri : 0xFFFFFFFFu;
    if (!(J->c > 0.0f) || !visible_join(g, pt->p, pt->tri, qs->p, qt, w, dist))
        return 0;
    float wz[3] = {-pt->h.d[0], -pt->h.d[1], -pt->h.d[2]};
    J->pt_rev = to_area(py, qs, pt);
    J->ptm_rev = to_area(lobe_pdf(pt, w, wz, SPM_REF_RADIANCE), pt, pm);
    J->qs_rev = to_area(lobe_pdf(pt, wz, w, SPM_REF_RADIANCE), pt, qs);
    return 1;
}

/* s = 1, t >= 2, a light at infinity along one direction (a distant
 * light): z[t-1] lit along the light subpath's direction d0, unoccluded to
 * infinity; with f_y = Le / (pmf pdf_pos) over the disc the subpath left,
 *   beta_z f_z |cos| Le / pmf.
 * pbrt-v4's densities of an infinite light's vertex: pt's by the light its
 * disc's, pdf_pos |cos at pt| (PdfLight); the light vertex's by pt in solid
 * angle (no distance to convert by). */
static int join_infinite(const spm_geometry *g, const spm_material *mats, const bd_subpath *z,
                         int t, const bd_subpath *y, bd_join *J)
{
    const bd_vertex *pt = &z->v[t - 1], *pm = &z->v[t - 2];
    float w[3] = {-y->d0[0], -y->d0[1], -y->d0[2]}, scale, cos_o, pp, pd;
    if (pt->pdf.delta ||
        spm_ref_lt_emission(g, mats, y->e, y->d0, &scale, &cos_o) == SPM_NONE)
        return 0;
    spm_ref_eval ez =
        spm_ref_eval_bsdf(pt->m, &pt->b, &pt->h, w, SPM_REF_RADIANCE | SPM_REF_JOIN);
    J->arg_pt = ez.cos_light;
    J->c = pt->beta * (ez.k * ez.f / ez.div) / ez.post * scale * cos_o / y->e->pdf;
    if (!(J->c > 0.0f) || !visible(g, pt->p, pt->tri, w, INFINITY))
        return 0;
    spm_ref_light_pdf_emission(g, (spm_u32)(y->e - g->emitters), y->v[0].p, y->d0, &pp, &pd);
    float wz[3] = {-pt->h.d[0], -pt->h.d[1], -pt->h.d[2]};
    J->pt_rev = pp * fabsf(v3_dot(pt->n, w));
    J->ptm_rev = to_area(lobe_pdf(pt, w, wz, SPM_REF_RADIANCE), pt, pm);
    J->qs_rev = lobe_pdf(pt, wz, w, SPM_REF_RADIANCE);
    return 1;
}

/* MIS of the join: the subpaths' densities with the connection's (a1 .. a4)
 * put in, the joined vertices no deltas. */
static float join_mis(const bd_subpath *z, int t, const bd_subpath *y, int s, const bd_join *J)
{
    spm_bdpt_pdf zp[SPM_BDPT_SUBPATH + 1], yp[SPM_BDPT_SUBPATH + 1];
    for (int i = 0; i < t; i++)
        zp[i] = z->v[i].pdf;
    for (int i = 0; i < s; i++)
        yp[i] = y->v[i].pdf;
    if (t > 1) {
        zp[t - 1].rev = J->pt_rev, zp[t - 1].delta = 0;
        zp[t - 2].rev = J->ptm_rev;
    }
    if (s > 0)
        yp[s - 1].rev = J->qs_rev, yp[s - 1].delta = 0;
    if (s > 1)
        yp[s - 2].rev = J->qsm_rev;
    return spm_ref_bdpt_mis(zp, t, yp, s, y->e && y->e->kind != SPM_LIGHT_AREA);
}

/* ---- the connected path's record ---------------------------------------- */

/* Surface vertex v's words in the record, given its argument for the ray
 * toward the light end: a joined vertex its eval's; a light vertex the
 * argument of the segment it shares with the vertex it came from (the
 * medium's length inside when both are of the absorbing kind, the
 * symmetric Fresnel angle otherwise); last: the vertex carries the light's
 * emission, whose factor reads the light sample's word. */
static spm_vertex_ext words(const bd_vertex *v, float arg, int last)
{
    spm_vertex_ext x = v->x;
    x.lobe = last ? 0.0f : arg;
    x.light = last ? arg : x.light;
    return x;
}

/* A dispersive vertex's words: the connected path's first one (in record
 * order) commits it to the sample's bin lam with 1 / its pdf (spm_shared.h
 * SPM_VX_LAMBDA), so the wavelength's pdf is counted once whichever subpath
 * drew it; the others carry no bin. */
static void disp_words(spm_vertex_ext *x, int *first, spm_u32 lam)
{
    spm_u32 col = *first ? lam : SPM_NONE;
    x->ids = (x->ids & ~SPM_VX_COLMASK) | ((col + 1u) & SPM_VX_COLMASK);
    if (*first)
        x->light = (float)SPM_TRUTH_BINS;
    *first = 0;
}

static float light_arg(const bd_subpath *y, int i)
{
    const bd_vertex *v = &y->v[i], *from = &y->v[i - 1];
    if (SPM_VX_KIND(v->x) != SPM_FK_ABSORB)
        return v->x.lobe;
    return i > 1 && SPM_VX_KIND(from->x) == SPM_FK_ABSORB ? from->x.lobe : 0.0f;
}

/* Writes strategy (s, t)'s path in camera order with weight c at its
 * emission; col2[] the vertices' second colours for the feeler. 0: a black
 * vertex on it. */
static int write_path(const bd_subpath *z, int t, const bd_subpath *y, int s, const bd_join *J,
                      float c, spm_u32 lam, spm_path *r, spm_u32 *col2)
{
    int first = 1, n = 0, nv = (t - 1) + (s > 0 ? s - 1 : 0) - (s == 0);
    r->h = (spm_path_head){(spm_u32)nv, SPM_END_ABSORBED, SPM_NONE, 0.0f, SPM_NONE, 0.0f, 0, 0};
    spm_u32 emit = s == 0 ? z->v[t - 1].emit : y->colour;
    if (nv == 0) {
        r->h.first_emit = emit;
        r->h.first_emit_c = c;
        return 1;
    }
    for (int i = 1; i < t && n < nv; i++, n++) {
        const bd_vertex *v = &z->v[i];
        float arg = i == t - 1 ? J->arg_pt : v->x.lobe;
        r->x[n] = i < t - 1 ? v->x : words(v, arg, n == nv - 1);
        if (v->disp)
            disp_words(&r->x[n], &first, lam);
        r->v[n] = (spm_vertex){v->refl | (SPM_NONE << 16), 0.0f};
        col2[n] = v->col2;
    }
    for (int i = s - 1; i >= 1; i--, n++) {
        const bd_vertex *v = &y->v[i];
        int joined = i == s - 1 && SPM_VX_KIND(v->x) != SPM_FK_ABSORB; /* else its segment's */
        r->x[n] = words(v, joined ? J->arg_qs : light_arg(y, i), n == nv - 1);
        if (v->disp)
            disp_words(&r->x[n], &first, lam);
        r->v[n] = (spm_vertex){v->refl | (SPM_NONE << 16), 0.0f};
        col2[n] = v->col2;
    }
    for (int j = 0; j < nv; j++)
        if ((r->v[j].ids & 0xFFFFu) == SPM_NONE)
            return 0;
    if (s == 0) { /* the emitter the last camera vertex's sampled ray hit */
        r->x[nv - 1].ids = (r->x[nv - 1].ids & 0xFFFFu) | SPM_VX_HIT_BITS(emit);
        r->x[nv - 1].hit_c = c;
    } else {
        r->v[nv - 1].ids = (r->v[nv - 1].ids & 0xFFFFu) | (emit << 16);
        r->v[nv - 1].c = c;
    }
    return 1;
}

/* the level byte of record r: the feeler over its colours (refcpu.h's order) */
static uint8_t path_level(const spm_path *r, const spm_u32 *col2, const uint8_t *lvlk, int start)
{
    feeler f = {start, SPM_SETBY_NONE};
    if (r->h.first_emit != SPM_NONE)
        feel(&f, lvlk, r->h.first_emit, 1, SPM_SETBY_EMITTER);
    for (spm_u32 j = 0; j < r->h.nvert; j++) {
        spm_u32 refl = r->v[j].ids & 0xFFFFu, e = r->v[j].ids >> 16, hit = SPM_VX_HIT(r->x[j]);
        feel(&f, lvlk, refl, occurrences(r, (int)j, refl), SPM_SETBY_REFLECTOR);
        if (e != SPM_NONE)
            feel(&f, lvlk, e, 1, SPM_SETBY_EMITTER);
        if (hit != SPM_NONE)
            feel(&f, lvlk, hit, 1, SPM_SETBY_EMITTER);
        if (col2[j] != SPM_NONE)
            feel(&f, lvlk, col2[j], 1, SPM_SETBY_REFLECTOR);
    }
    return (uint8_t)((spm_u32)f.level | (f.setby << SPM_SETBY_SHIFT));
}

/* ---- a sample ------------------------------------------------------------ */

typedef struct {
    const spm_geometry *g;
    const spm_material *mats;
    const uint8_t *lvlk;
    int start_level, ch;
    const spm_mode_desc *m;
    const spm_shade_table *tabs;
    const spm_spec_map *maps;
    const spm_trace_params *p;
    spm_splats *out;
    size_t *hist;
    spm_path rec;
    spm_u32 lam; /* the sample's committed bin (SPM_NONE: none) */
} bd_ctx;

/* strategy (s, t) of sample i: joined, weighed, shaded, splatted */
static void strategy(bd_ctx *cx, const spm_ref_key *ky, size_t i, const bd_subpath *z, int t,
                     const bd_subpath *y, int s, spm_u32 pixel)
{
    bd_join J = {0.0f, 0.0f, 0.0f, pixel, 0.0f, 0.0f, 0.0f, 0.0f};
    int ok = s == 0   ? join_emitter(cx->g, z, t, &J)
             : t == 1 ? join_camera(cx->g, ky, y, s, &J)
             : s == 1 && spm_ref_light_at_infinity(y->e) ? join_infinite(cx->g, cx->mats, z, t, y, &J)
                      : join_inner(cx->g, cx->mats, z, t, y, s, &J);
    if (!ok)
        return;
    float c = J.c * join_mis(z, t, y, s, &J);
    spm_u32 col2[SPM_MAX_DEPTH];
    if (!(c > 0.0f) || !write_path(z, t, y, s, &J, c, cx->lam, &cx->rec, col2))
        return;
    uint8_t lv = path_level(&cx->rec, col2, cx->lvlk, cx->start_level);
    cx->hist[lv]++;
    float *o = spm_splats_push(cx->out, J.px);
    spm_ref_shade_spectral(cx->m, cx->tabs, cx->maps, cx->ch, cx->p, i, &cx->rec, &lv, 1, o);
}

void spm_ref_bdpt_range(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                        int start_level, const spm_mode_desc *m, const spm_shade_table *tabs,
                        const spm_spec_map *maps, int ch, const spm_trace_params *p, size_t begin,
                        size_t end, spm_splats *out, size_t hist[256])
{
    static _Thread_local bd_subpath z, y;
    static _Thread_local bd_ctx cx;
    cx.g = g, cx.mats = mats, cx.lvlk = lvlk, cx.start_level = start_level, cx.ch = ch;
    cx.m = m, cx.tabs = tabs, cx.maps = maps, cx.p = p, cx.out = out, cx.hist = hist;
    for (size_t i = begin; i < end; i++) {
        spm_ref_key k = {p->seed, 0, 0};
        spm_ref_path_key(p, i, &k.pixel, &k.sample);
        spm_ref_key ky = {p->seed ^ SPM_BDPT_LIGHT_SEED, k.pixel, k.sample};
        spm_ref_walk rw = {g->disp, p->disperse, SPM_NONE};
        camera_subpath(g, mats, &k, &rw, &z);
        y.n = 0;
        y.e = NULL;
        if (g->nemitters > 0)
            light_subpath(g, mats, &ky, &rw, &y);
        cx.lam = rw.lam;
        for (int t = 1; t <= z.n; t++)
            for (int s = t == 1 ? 1 : 0; s <= y.n; s++)
                if (!(s == 1 && t == 1) && (s > 0 || t > 1))
                    strategy(&cx, &ky, i, &z, t, &y, s, k.pixel);
    }
}
