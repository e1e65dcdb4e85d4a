/* CPU reference, trace stage: MiniLight's light transport in plain scalar
 * float C, writing colour-independent path records and each path's level.
 * The order of operations is spelled out so a kernel can follow it:
 *   camera ray -> for each vertex j: hit, first-hit emission (j = 0),
 *   next-event estimation, Russian roulette, cosine-weighted bounce;
 *   a ray that hits nothing records the background and ends the path. */
#include "refcpu.h"
#include "render_plan.h"
#include "geometry_vec3.h"
#include "spm_rng.h"
#include "refcpu_conductor.h"
#include "refcpu_coated.h"
#include "refcpu_dielectric.h"
#include "refcpu_shading.h"
#include <stdlib.h>
#include <string.h>

/* One strategy alone, for tests/test_strategies.c: SPECMIP_TEST_STRATEGY=light
 * (light sampling alone: the lobes' emitter hits weigh 0) or lobe (the lobes
 * alone: light samples weigh 0), through the light-pick probability the power
 * heuristic sees (infinite or 0); unset, MIS. The estimators' own 1 / pdf are
 * untouched, so each strategy alone is unbiased where it can reach the light. */
static _Thread_local int strategy;

static float mis_pick(float pick)
{
    return strategy == 1 ? INFINITY : strategy == 2 ? 0.0f : pick;
}

static int strategy_from_env(void)
{
    const char *s = getenv("SPECMIP_TEST_STRATEGY");
    return !s ? 0 : !strcmp(s, "light") ? 1 : !strcmp(s, "lobe") ? 2 : 0;
}

/* The level feeler: the finest (smallest) level among the colours met,
 * starting from the coarsest level in use; a colour lowers it only when
 * strictly finer, so "set by" names the first colour that needed it. */
typedef struct {
    int level;
    spm_u32 setby;
} feeler;

static void feel(feeler *f, const uint8_t *lvlk, spm_u32 colour, int k, spm_u32 who)
{
    if (!lvlk)
        return;
    int kk = k < SPM_PRETEST_KMAX ? k : SPM_PRETEST_KMAX;
    int l = lvlk[colour * SPM_PRETEST_KMAX + (spm_u32)(kk - 1)];
    if (l < f->level)
        f->level = l, f->setby = who;
}

/* MiniLight's camera: jittered position in pixel (x, y), y = 0 at the top. */
static void camera_ray(const spm_camera *cam, spm_u32 seed, spm_u32 pixel, spm_u32 sample,
                       float d[3])
{
    spm_u32 w = (spm_u32)cam->width, h = (spm_u32)cam->height;
    float u = spm_rng(seed, pixel, sample, SPM_DIM_CAM_X);
    float v = spm_rng(seed, pixel, sample, SPM_DIM_CAM_Y);
    float cx = 2.0f * ((float)(pixel % w) + u) / (float)w - 1.0f;
    float cy = 1.0f - 2.0f * ((float)(pixel / w) + v) / (float)h;
    float sy = cy * (float)h / (float)w;
    float s[3];
    for (int i = 0; i < 3; i++)
        s[i] = cam->dir[i] + cam->tan_half * (cam->right[i] * cx + cam->up[i] * sy);
    v3_normalise(d, s);
}

typedef struct {
    spm_u32 seed, pixel, sample;
} rng_key;

static float rnd(const rng_key *k, spm_u32 dim)
{
    return spm_rng(k->seed, k->pixel, k->sample, dim);
}

/* The material and emitter types (spm_shared.h SPM_MAT_*, SPM_EMIT_*): one
 * switch each, the reference's arithmetic for every type (as trace.cl's
 * vertex_lobe and vertex_emission). */

/* The vertex's reflection: the colour it records, its Russian-roulette
 * survival (*mean) and weight (*inv_mean); a type's own random numbers are
 * SPM_DIM_TYPE(j, k). */
static spm_u32 vertex_lobe(const spm_material *m, const rng_key *k, int j, float *mean,
                           float *inv_mean)
{
    (void)k, (void)j;
    switch (SPM_MAT_TAG(*m)) {
    case SPM_MAT_LAMBERT:
        *mean = m->mean;
        *inv_mean = m->inv_mean;
        return m->refl;
    case SPM_MAT_CONDUCTOR: /* eta as the colour; k in the vertex's own words */
        *mean = m->mean;
        *inv_mean = m->inv_mean;
        return m->refl;
    case SPM_MAT_DIELECTRIC: /* its absorption colour; R + T = 1: always survives */
        *mean = m->mean;
        *inv_mean = m->inv_mean;
        return m->refl;
    case SPM_MAT_FLUOR:
    case SPM_MAT_DONALDSON: /* diffuse: its diagonal colour marks it for the shade stage */
        *mean = m->mean;
        *inv_mean = m->inv_mean;
        return m->refl;
    case SPM_MAT_COATED: /* its lobe's colour and survival: trace_path's (refcpu_coated.h) */
        *mean = m->mean;
        *inv_mean = m->inv_mean;
        return m->refl;
    default:
        *mean = 0.0f;
        *inv_mean = 0.0f;
        return SPM_NONE;
    }
}

/* The emission of an emitter's material towards a direction at cosine
 * cos_e > 0 to its emitting face's normal: its colour, and *scale, the
 * factor its radiance there takes (1 for a uniform emitter). */
static spm_u32 vertex_emission(const spm_material *m, float cos_e, float *scale)
{
    (void)cos_e;
    switch (SPM_EMIT_TAG(*m)) {
    case SPM_EMIT_AREA:
        *scale = 1.0f;
        return m->emit;
    default:
        *scale = 0.0f;
        return SPM_NONE;
    }
}

_Thread_local spm_ref_ray_sink spm_ref_rays;

static void record_ray(const float o[3], const float d[3], spm_u32 skip, spm_u32 emitter)
{
    if (!spm_ref_rays.fn)
        return;
    spm_ray r = {{o[0], o[1], o[2]}, skip, {d[0], d[1], d[2]}, emitter};
    spm_ref_rays.fn(spm_ref_rays.ctx, &r);
}

/* The emitter triangle for a vertex (spm_shared.h spm_emitter): by power
 * through the table, or MiniLight's uniform pick when the powers are equal. */
static const spm_emitter *pick_emitter(const spm_geometry *g, const rng_key *k, spm_u32 dim)
{
    int ne = g->nemitters;
    if (g->emit_power) {
        spm_u32 u24 = spm_rng_u32(k->seed, k->pixel, k->sample, dim + SPM_DIM_EMITTER) >> 8;
        return &g->emitters[spm_emitter_search(g->emitters, (spm_u32)ne, u24)];
    }
    int pick = (int)(rnd(k, dim + SPM_DIM_EMITTER) * (float)ne);
    return &g->emitters[pick < ne ? pick : ne - 1];
}

/* Next-event estimation at hit point x on triangle `hit` (normal n) reached
 * along d: one emitter triangle (pick_emitter), a uniform point on it, a
 * shadow ray. Returns the emitter's emission colour and its weight
 *   (1 / pdf) * cos_e * area / max(d2, SPM_D2_MIN_REL * area) * |cos_i| / pi
 * or SPM_NONE (weight 0) when occluded, back-facing or on the other side. At a
 * rough conductor (cc) the factor after the distance is its lobe's
 * (spm_ref_cond_light), and *cos_h its Fresnel angle; at a rough dielectric
 * (cc and its relative index deta > 0) its reflection's (spm_ref_diel_light);
 * at a coated vertex (co) its chosen lobe's (spm_ref_coat_light). At a smooth
 * triangle (sn, its shading normal on the viewer's side) |cos_i| is the cosine
 * to sn, and light below sn's horizon counts nothing (refcpu_shading.h). */
static spm_u32 sample_emitter(const spm_geometry *g, const spm_material *mats, const rng_key *k,
                              spm_u32 dim, const float x[3], spm_u32 hit, const float n[3],
                              const float d[3], const spm_ref_cond *cc, float deta,
                              const spm_ref_coat *co, const float *sn, float *c, float *cos_h)
{
    *c = 0.0f;
    if (g->nemitters == 0)
        return SPM_NONE;
    const spm_emitter *pe = pick_emitter(g, k, dim);
    spm_u32 ei = pe->tri;
    const spm_tri *em = &g->tris[ei];
    float sqr1 = sqrtf(rnd(k, dim + SPM_DIM_EPOINT_A));
    float a = 1.0f - sqr1, b = (1.0f - rnd(k, dim + SPM_DIM_EPOINT_B)) * sqr1;
    float q[3], ev[3], l[3], ts;
    for (int i = 0; i < 3; i++)
        q[i] = em->v0[i] + (em->v1[i] - em->v0[i]) * a + (em->v2[i] - em->v0[i]) * b;
    v3_sub(ev, q, x);
    v3_normalise(l, ev);
    record_ray(x, l, hit, ei);
    int blocker = spm_bvh_intersect(g, x, l, hit, &ts);
    if (blocker >= 0 && (spm_u32)blocker != ei)
        return SPM_NONE;
    float cos_e = -v3_dot(l, em->n);
    if (mats[em->material].type & SPM_EMIT_TWOSIDED)
        cos_e = fabsf(cos_e); /* 'twosided': the back face emits too */
    if (!(cos_e > 0.0f))
        return SPM_NONE; /* emitters emit from their front face only (unless twosided) */
    float cos_i = v3_dot(l, n), cos_o = -v3_dot(d, n);
    if ((cos_i < 0.0f) != (cos_o < 0.0f))
        return SPM_NONE; /* light and viewer on different sides: no transmission */
    float d2 = v3_dot(ev, ev), d2min = SPM_D2_MIN_REL * em->area;
    float w;
    if (cc && deta > 0.0f) {
        float d2c = d2 > d2min ? d2 : d2min;
        w = pe->inv_pdf * cos_e * em->area / d2c *
            spm_ref_diel_light(cc, deta, l, mis_pick(pe->pdf), d2c, em->area, cos_e);
        if (sn && !(v3_dot(l, cc->n) > 0.0f))
            w = 0.0f;
    } else if (cc) {
        float d2c = d2 > d2min ? d2 : d2min;
        w = pe->inv_pdf * cos_e * em->area / d2c *
            spm_ref_cond_light(cc, l, mis_pick(pe->pdf), d2c, em->area, cos_e, cos_h);
        if (sn && !(v3_dot(l, cc->n) > 0.0f))
            w = 0.0f;
    } else if (co) {
        float d2c = d2 > d2min ? d2 : d2min;
        float ci = sn ? fmaxf(v3_dot(l, sn), 0.0f) : cos_i;
        w = pe->inv_pdf * cos_e * em->area / d2c *
            spm_ref_coat_light(co, l, ci, mis_pick(pe->pdf), d2c, em->area, cos_e);
        if (sn && co->spec && !(v3_dot(l, co->f.n) > 0.0f))
            w = 0.0f;
    } else if (sn) {
        float cs = v3_dot(l, sn);
        w = pe->inv_pdf * cos_e * em->area / (d2 > d2min ? d2 : d2min) * fmaxf(cs, 0.0f) / SPM_PI_F;
    } else {
        w = pe->inv_pdf * cos_e * em->area / (d2 > d2min ? d2 : d2min) * fabsf(cos_i) / SPM_PI_F;
    }
    if (!(w > 0.0f))
        return SPM_NONE;
    float es;
    spm_u32 e = vertex_emission(&mats[em->material], cos_e, &es);
    *c = w * es;
    return e;
}

/* Cosine-weighted direction about the normal n on the incoming side, tangent
 * tg (MiniLight: x = cos(2 pi u) sqrt(v), y = sin(2 pi u) sqrt(v), z = sqrt(1 - v);
 * out = t x + (n x t) y + n z). */
static void bounce(const float n[3], const float tg[3], const rng_key *k, spm_u32 dim,
                   float out[3])
{
    float phi = 2.0f * SPM_PI_F * rnd(k, dim + SPM_DIM_DIR_A);
    float v = rnd(k, dim + SPM_DIM_DIR_B);
    float sr = sqrtf(v);
    float x = cosf(phi) * sr, y = sinf(phi) * sr, z = sqrtf(1.0f - v);
    float c[3];
    v3_cross(c, n, tg);
    for (int i = 0; i < 3; i++)
        out[i] = tg[i] * x + c[i] * y + n[i] * z;
}

/* Occurrences of reflectance colour r among vertices 0..j of the record. */
static int occurrences(const spm_path *path, int j, spm_u32 r)
{
    int k = 0;
    for (int i = 0; i <= j; i++)
        k += (path->v[i].ids & 0xFFFFu) == r;
    return k;
}

/* Emission hit by the sampled ray of the last vertex, a conductor's lobe of
 * density cpdf (0: the smooth one): counted there, into its record x, with
 * the throughput so far and the power heuristic against the light sample
 * (light_pdf: the hit triangle's pick probability; the solid-angle density
 * light_pdf d^2 / (area cos_e)); ce: the face's cosine to the viewer (twosided:
 * its size), escale: the emission's factor there (vertex_emission). A face
 * that does not emit counts nothing. */
static void lobe_hit(const spm_tri *tri, float ce, float t, float light_pdf, float cpdf,
                     float weight, spm_u32 memit, float escale, spm_vertex_ext *x, feeler *f,
                     const uint8_t *lvlk)
{
    if (!(ce > 0.0f))
        return;
    float wm = 1.0f;
    if (cpdf > 0.0f) {
        float d2 = t * t, d2min = SPM_D2_MIN_REL * tri->area;
        float pl = light_pdf * (d2 > d2min ? d2 : d2min) / (tri->area * ce);
        wm = spm_ref_cond_power(cpdf, pl);
    }
    x->ids = (x->ids & 0xFFFFu) | SPM_EXT_IDS(SPM_NONE, memit);
    x->hit_c = weight * wm * escale;
    feel(f, lvlk, memit, 1, SPM_SETBY_EMITTER);
}

static void escape(const spm_trace_params *p, const float d[3], float weight, spm_path *path)
{
    spm_u32 bg = d[1] > 0.0f ? p->bg_up : p->bg_down; /* MiniLight: sky for an upward ray */
    path->h.end = SPM_END_ESCAPED;
    path->h.bg = bg;
    path->h.bg_c = bg != SPM_NONE ? weight : 0.0f;
}

static uint8_t trace_path(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                          int start_level, const spm_trace_params *p, size_t i, spm_path *path)
{
    rng_key k = {p->seed, 0, 0};
    spm_ref_path_key(p, i, &k.pixel, &k.sample);
    feeler f = {start_level, SPM_SETBY_NONE};
    spm_path_head *h = &path->h;
    *h = (spm_path_head){0, SPM_END_ABSORBED, SPM_NONE, 0.0f, SPM_NONE, 0.0f, 0, 0};

    float o[3], d[3], weight = 1.0f; /* product of 1 / mean over survived vertices */
    float cpdf = -1.0f; /* the last vertex's conductor, dielectric or coating's specular lobe
                           density (< 0: none, 0: a delta or a refraction) */
    int din = 0;        /* the last vertex's sampled ray runs inside its glass */
    spm_u32 lam = SPM_NONE; /* the 1 nm bin the path committed to (none yet) */
    for (int i = 0; i < 3; i++)
        o[i] = p->cam.eye[i];
    camera_ray(&p->cam, k.seed, k.pixel, k.sample, d);
    spm_u32 skip = 0xFFFFFFFFu;
    for (int j = 0;; j++) {
        float t;
        record_ray(o, d, skip, SPM_RAY_CLOSEST);
        int hit = spm_bvh_intersect(g, o, d, skip, &t);
        if (hit < 0) {
            escape(p, d, weight, path);
            if (h->bg != SPM_NONE)
                feel(&f, lvlk, h->bg, 1, SPM_SETBY_EMITTER);
            break;
        }
        const spm_tri *tri = &g->tris[hit];
        const spm_material *m = &mats[tri->material];
        float x[3];
        v3_madd(x, o, d, t);
        float ecos = -v3_dot(d, tri->n), escale; /* the emitting face's cosine to the viewer */
        if (m->type & SPM_EMIT_TWOSIDED)
            ecos = fabsf(ecos);
        spm_u32 memit = vertex_emission(m, ecos, &escale);
        if (j == 0 && memit != SPM_NONE &&
            (-v3_dot(d, tri->n) > 0.0f || (m->type & SPM_EMIT_TWOSIDED))) {
            h->first_emit = memit; /* local emission: first hit, an emitting face */
            h->first_emit_c = escale;
            feel(&f, lvlk, memit, 1, SPM_SETBY_EMITTER);
        }
        if (din && j > 0) /* the segment's length inside: its absorption, in the shade stage */
            path->x[j - 1].cos_lobe = t;
        if (j > 0 && cpdf >= 0.0f && memit != SPM_NONE)
            lobe_hit(tri, ecos, t, mis_pick(g->light_pdf[hit]), cpdf, weight, memit, escale,
                     &path->x[j - 1], &f, lvlk);
        /* The hit's shading frame, the one place a type finds it: the normal
         * sn on the viewer's side and tangent st every type shades with; gn,
         * the geometric normal on the viewer's side (MiniLight: dot(n, -d) < 0
         * flips n), decides which side a direction is on. A flat triangle's
         * is gn and its own tangent (refcpu_shading.h). */
        float gn[3] = {tri->n[0], tri->n[1], tri->n[2]}, sn[3], st[3];
        if (v3_dot(gn, d) > 0.0f)
            gn[0] = -gn[0], gn[1] = -gn[1], gn[2] = -gn[2];
        int smooth = tri->vn != 0u;
        if (smooth)
            spm_ref_shading_frame(tri, &g->vnormals[9 * (size_t)(tri->vn - 1u)], o, d, gn, sn, st);
        else
            for (int i = 0; i < 3; i++)
                sn[i] = gn[i], st[i] = tri->t[i];
        int cond = SPM_MAT_TAG(*m) == SPM_MAT_CONDUCTOR;
        int diel = SPM_MAT_TAG(*m) == SPM_MAT_DIELECTRIC;
        spm_ref_cond cc;
        float deta = 0.0f; /* a dielectric's relative index eta_t / eta_i */
        if (cond && smooth)
            spm_ref_cond_frame(sn, st, d, m->p[SPM_COND_P_ALPHA], &cc);
        else if (cond)
            spm_ref_cond_make(tri, d, m->p[SPM_COND_P_ALPHA], &cc);
        int dcommit = 0; /* this vertex commits the path to a wavelength */
        if (diel) { /* the shading frame's lobes; inside or outside by the winding */
            /* a dispersive glass: n of the path's committed bin, the first such vertex
             * drawing it (p->disperse 0, rgb: n_d) */
            float ior = m->p[SPM_DIEL_P_IOR];
            spm_u32 row = p->disperse ? (spm_u32)m->p[SPM_DIEL_P_DISP] : 0u;
            if (row) {
                if (lam == SPM_NONE) {
                    lam = spm_ref_disp_bin(
                        spm_rng_stratified_u32(k.seed, k.pixel, k.sample, SPM_DIM_TYPE(0u, SPM_DIM_DIEL_LAMBDA)));
                    dcommit = 1;
                }
                ior = g->disp[(size_t)(row - 1u) * SPM_TRUTH_BINS + lam];
            }
            if (smooth)
                spm_ref_cond_frame(sn, st, d, m->p[SPM_DIEL_P_ALPHA], &cc);
            else
                spm_ref_cond_make(tri, d, m->p[SPM_DIEL_P_ALPHA], &cc);
            deta = spm_ref_diel_eta(tri, d, ior);
        }
        int coat = SPM_MAT_TAG(*m) == SPM_MAT_COATED;
        spm_ref_coat co;
        if (coat) { /* its lobe first, from its own dimensions */
            spm_ref_cond cf;
            if (smooth)
                spm_ref_cond_frame(sn, st, d, m->p[SPM_COAT_P_ALPHA], &cf);
            else
                spm_ref_cond_make(tri, d, m->p[SPM_COAT_P_ALPHA], &cf);
            spm_ref_coat_make(&cf, m, rnd(&k, SPM_DIM_TYPE(j, SPM_DIM_COAT_LOBE)),
                              rnd(&k, SPM_DIM_TYPE(j, SPM_DIM_COAT_M_A)),
                              rnd(&k, SPM_DIM_TYPE(j, SPM_DIM_COAT_M_B)), &co);
        }
        spm_u32 dim = SPM_DIM_VERTEX(j);
        float c = 0.0f, cos_h = 0.0f;
        spm_u32 e = SPM_NONE;
        if (!((cond || diel) && cc.alpha == 0.0f) && !(coat && co.spec && co.f.alpha == 0.0f))
            e = sample_emitter(g, mats, &k, dim, x, (spm_u32)hit, tri->n, d,
                               cond || diel ? &cc : NULL, deta, coat ? &co : NULL,
                               smooth ? sn : NULL, &c, &cos_h); /* none on a delta lobe */
        float mmean, minv;
        spm_u32 refl = vertex_lobe(m, &k, j, &mmean, &minv);
        if (coat) { /* the lobe's colour; survival q = min(1, w mean), weight w / q */
            float q = fminf(1.0f, co.w * (co.spec ? 1.0f : m->mean));
            refl = co.spec ? m->col2 : m->refl;
            mmean = q;
            minv = q > 0.0f ? co.w / q : 0.0f;
        }
        spm_vertex *vx = &path->v[j];
        vx->ids = (refl & 0xFFFFu) | (e << 16);
        vx->c = c * weight;
        cpdf = -1.0f;
        path->x[j] = (spm_vertex_ext){0u, 0.0f, 0.0f, 0.0f};
        if (cond) {
            path->x[j].ids = SPM_EXT_IDS(m->col2, SPM_NONE);
            path->x[j].cos_light = cos_h;
        }
        din = 0;
        if (diel)
            path->x[j].ids = SPM_EXT_KIND; /* the length inside comes with the next hit */
        if (dcommit) { /* the committed bin and 1 / its pdf (spm_shared.h SPM_EXT_LAMBDA) */
            path->x[j].ids |= lam + 1u;
            path->x[j].cos_light = (float)SPM_TRUTH_BINS;
        }
        h->nvert = (spm_u32)j + 1;
        if (refl != SPM_NONE)
            feel(&f, lvlk, refl, occurrences(path, j, refl), SPM_SETBY_REFLECTOR);
        if (e != SPM_NONE)
            feel(&f, lvlk, e, 1, SPM_SETBY_EMITTER);
        if (cond && m->col2 != SPM_NONE)
            feel(&f, lvlk, m->col2, 1, SPM_SETBY_REFLECTOR);

        if (!(rnd(&k, dim + SPM_DIM_RR) < mmean)) {
            h->end = SPM_END_ABSORBED;
            break;
        }
        if (j + 1 == SPM_MAX_DEPTH) {
            h->end = SPM_END_TRUNCATED; /* it would go on, but the record is full */
            break;
        }
        weight *= minv;
        float nd[3];
        int refracted = 0; /* a dielectric's refraction: to the other side */
        if (diel) {
            float wt, wg;
            int ok = spm_ref_diel_lobe(&cc, deta, rnd(&k, SPM_DIM_TYPE(j, SPM_DIM_DIEL_M_A)),
                                       rnd(&k, SPM_DIM_TYPE(j, SPM_DIM_DIEL_M_B)),
                                       rnd(&k, SPM_DIM_TYPE(j, SPM_DIM_DIEL_CHOICE)), nd, &wt, &wg,
                                       &cpdf);
            if (!ok) { /* the wrong side: the path ends */
                cpdf = -1.0f;
                h->end = SPM_END_ABSORBED;
                break;
            }
            refracted = ok == 2;
            if (wt != 1.0f)
                weight *= wt;
            if (cc.alpha > 0.0f)
                weight *= wg;
            din = v3_dot(nd, tri->n) < 0.0f; /* into the back face's side: inside */
        } else if (cond) {
            float lw;
            int up = spm_ref_cond_lobe(&cc, rnd(&k, SPM_DIM_TYPE(j, SPM_DIM_COND_M_A)),
                                       rnd(&k, SPM_DIM_TYPE(j, SPM_DIM_COND_M_B)), nd,
                                       &path->x[j].cos_lobe, &lw, &cpdf);
            if (!up) { /* below the surface: the path ends */
                path->x[j].cos_lobe = 0.0f;
                cpdf = -1.0f;
                h->end = SPM_END_ABSORBED;
                break;
            }
            if (cpdf > 0.0f)
                weight *= lw;
        } else if (coat && co.spec) { /* its hit counted at the next vertex */
            for (int i = 0; i < 3; i++)
                nd[i] = co.dir[i];
            cpdf = co.pdf;
        } else {
            bounce(sn, st, &k, dim, nd);
            if (coat) /* the diffuse lobe's transmission out: 1 - F(cos_i), cos_i = sqrt(1 - v) */
                weight *= 1.0f - spm_ref_coat_fresnel(co.eta,
                                                      sqrtf(1.0f - rnd(&k, dim + SPM_DIM_DIR_B)));
        }
        /* a direction on the other side of the geometric surface than of the
         * shading one (a reflection under it, a refraction over it): ends */
        if (smooth && (refracted ? !(v3_dot(nd, gn) < 0.0f) : !(v3_dot(nd, gn) > 0.0f))) {
            if (cond)
                path->x[j].cos_lobe = 0.0f;
            h->end = SPM_END_ABSORBED;
            break;
        }
        for (int i = 0; i < 3; i++)
            o[i] = x[i], d[i] = nd[i];
        skip = (spm_u32)hit;
    }
    return (uint8_t)((spm_u32)f.level | (f.setby << SPM_SETBY_SHIFT));
}

void spm_ref_trace_range(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                         int start_level, const spm_trace_params *p, size_t begin, size_t end,
                         spm_path *paths, uint8_t *levels)
{
    strategy = strategy_from_env();
    for (size_t i = begin; i < end; i++)
        levels[i - begin] = trace_path(g, mats, lvlk, start_level, p, i, &paths[i - begin]);
}

void spm_ref_trace(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                   const spm_trace_params *p, spm_path *paths, uint8_t *levels)
{
    size_t n = (size_t)p->cam.width * (size_t)p->cam.height * p->spp_per_pass;
    int start = spm_plan_level_start(g, mats, lvlk, p);
    spm_ref_trace_range(g, mats, lvlk, start, p, 0, n, paths, levels);
}
