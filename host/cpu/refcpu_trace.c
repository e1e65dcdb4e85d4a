/* CPU reference, trace stage: MiniLight's light transport in plain scalar
 * float C, writing colour-independent path records and each path's level.
 * The order of operations is spelled out so a kernel can follow it:
 *   camera ray -> for each vertex j: hit, first-hit emission (j = 0), the
 *   emission the last vertex's sampled ray hit (with its MIS weight), the
 *   vertex's BSDF, next-event estimation, Russian roulette, the BSDF's
 *   sampled direction; a ray that hits nothing records the background and
 *   ends the path. The loop names no material type: it asks each vertex's
 *   type through the contract of refcpu_bsdf.h, and computes MIS here, once. */
#include "refcpu.h"
#include "render_plan.h"
#include "geometry_vec3.h"
#include "spm_rng.h"
#include "refcpu_bsdf.h"
#include "refcpu_lights.h"
#include "refcpu_camera.h"
#include "refcpu_shading.h"
#include "refcpu_feeler.h"
#include "refcpu_texture.h"
#include "refcpu_bdpt.h"
#include "refcpu_metalrough.h"
#include <stdlib.h>
#include <string.h>

/* One strategy alone, for tests/test_strategies.c: SPECMIP_TEST_STRATEGY=light
 * (light sampling alone: the lobes' emitter hits weigh 0) or lobe (the lobes
 * alone: light samples weigh 0), through the light density the power
 * heuristic sees (infinite or 0); unset, MIS. The estimators' own 1 / pdf are
 * untouched, so each strategy alone is unbiased where it can reach the light. */
static _Thread_local int strategy;

static float mis_pick(float pdf_light)
{
    return strategy == 1 ? INFINITY : strategy == 2 ? 0.0f : pdf_light;
}

static int strategy_from_env(void)
{
    const char *s = getenv("SPECMIP_TEST_STRATEGY");
    return !s ? 0 : !strcmp(s, "light") ? 1 : !strcmp(s, "lobe") ? 2 : 0;
}

/* The camera ray of a jittered point in pixel (x, y), y = 0 at the top
 * (refcpu_camera.c); a thin lens draws its disk point from its own dimensions. */
void spm_ref_pixel_ray(const spm_camera *cam, spm_u32 seed, spm_u32 pixel, spm_u32 sample,
                       float o[3], float d[3])
{
    spm_u32 w = (spm_u32)cam->width, h = (spm_u32)cam->height;
    float u = spm_rng(seed, pixel, sample, SPM_DIM_CAM_X);
    float v = spm_rng(seed, pixel, sample, SPM_DIM_CAM_Y);
    float cx = 2.0f * ((float)(pixel % w) + u) / (float)w - 1.0f;
    float cy = 1.0f - 2.0f * ((float)(pixel / w) + v) / (float)h;
    float lu = 0.5f, lv = 0.5f;
    if (cam->lens_radius > 0.0f)
        lu = spm_rng(seed, pixel, sample, SPM_DIM_LENS_A), lv = spm_rng(seed, pixel, sample, SPM_DIM_LENS_B);
    spm_ref_camera_ray(cam, cx, cy, lu, lv, o, d);
}

/* Next-event estimation's weight, the light sample ls's at a vertex of
 * material m (BSDF b, frame h):
 *   g f |cos_i| w_mis,
 * f |cos_i| the type's (spm_ref_eval_bsdf), w_mis the power heuristic
 * against the type's density of sampling the same direction when its
 * sampled rays count emission too and the light is not a delta. Returns the
 * emission's colour (SPM_NONE: nothing) and *c its weight; *cos_light the
 * type's spectral argument. */
static spm_u32 light_weight(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                            const spm_ref_lsample *ls, float *c, float *cos_light)
{
    spm_ref_eval e = spm_ref_eval_bsdf(m, b, h, ls->wi, SPM_REF_RADIANCE);
    *cos_light = e.cos_light;
    float wm = 1.0f;
    if (!(e.pdf < 0.0f) && !ls->delta)
        wm = spm_ref_cond_power(mis_pick(ls->pdf), e.pdf);
    float w = ls->g * (e.k * (e.f * wm) / e.div) / e.post;
    if (!(w > 0.0f))
        return SPM_NONE;
    *c = w * ls->scale;
    return ls->colour;
}

/* Emission hit by the sampled ray of the last vertex, of density cpdf (0: a
 * delta): counted there, into its record x, with the throughput so far and
 * the power heuristic against the light sample's density of the same point
 * (spm_ref_light_pdf_hit); ce: the face's cosine to the viewer (twosided:
 * its size), escale: the emission's factor there. A face that does not emit
 * counts nothing. */
static void lobe_hit(const spm_geometry *g, const float o[3], spm_u32 from, spm_u32 tri, float ce,
                     float t, float cpdf, float weight, spm_u32 memit, float escale,
                     spm_vertex_ext *x, feeler *f,
                     const uint8_t *lvlk)
{
    if (!(ce > 0.0f))
        return;
    float wm = 1.0f;
    if (cpdf > 0.0f)
        wm = spm_ref_cond_power(cpdf, mis_pick(spm_ref_light_pdf_hit(g, o, from, tri, t, ce)));
    x->ids = (x->ids & 0xFFFFu) | SPM_VX_HIT_BITS(memit);
    x->hit_c = weight * wm * escale;
    feel(f, lvlk, memit, 1, SPM_SETBY_EMITTER);
}

/* The ray leaving the scene after vertex j - 1 (whose sampled ray had
 * density cpdf): what it meets, with the power heuristic against
 * light_sample's density when that reaches it too (the map): 1 after a
 * delta (cpdf 0), 0 when the vertex's sampled rays count no emission
 * (cpdf < 0), 1 for the camera's ray. */
static void escape(const spm_geometry *g, const spm_trace_params *p, const float d[3],
                   const spm_ref_key *k, int j, float cpdf, float weight, spm_path *path)
{
    float scale, lpdf;
    spm_u32 bg = spm_ref_light_escape(g, p, d, k, (spm_u32)j, &scale, &lpdf);
    if (lpdf > 0.0f && j > 0)
        scale *= cpdf < 0.0f ? 0.0f : cpdf > 0.0f ? spm_ref_cond_power(cpdf, mis_pick(lpdf)) : 1.0f;
    if (!(scale > 0.0f))
        bg = SPM_NONE;
    path->h.end = SPM_END_ESCAPED;
    path->h.bg = bg;
    path->h.bg_c = bg != SPM_NONE ? weight * scale : 0.0f;
}

/* The hit's emission: the first hit's (an emitting face towards the viewer),
 * and the one the last vertex's sampled ray hit (cpdf its density, >= 0),
 * counted there with its MIS weight (lobe_hit; the ray left o on triangle
 * from). */
static void hit_emission(const spm_geometry *g, const spm_material *m, int hit, int j, float t,
                         const float o[3], const float d[3], const float x[3],
                         const spm_ref_key *k, spm_u32 from, float cpdf, float weight,
                         spm_path *path, feeler *f, const uint8_t *lvlk)
{
    const spm_tri *tri = &g->tris[hit];
    float ecos = -v3_dot(d, tri->n), escale; /* the emitting face's cosine to the viewer */
    if (m->type & SPM_EMIT_TWOSIDED)
        ecos = fabsf(ecos);
    spm_u32 memit = spm_ref_emit_texture(g, (spm_u32)hit, x, k, (spm_u32)j, 0u,
                                         spm_ref_light_eval(m, ecos, &escale), &escale);
    if (j == 0 && memit != SPM_NONE && (-v3_dot(d, tri->n) > 0.0f || (m->type & SPM_EMIT_TWOSIDED))) {
        path->h.first_emit = memit; /* local emission: first hit, an emitting face */
        path->h.first_emit_c = escale;
        feel(f, lvlk, memit, 1, SPM_SETBY_EMITTER);
    }
    if (j > 0 && cpdf >= 0.0f && memit != SPM_NONE)
        lobe_hit(g, o, from, (spm_u32)hit, ecos, t, cpdf, weight, memit, escale, &path->x[j - 1],
                 f, lvlk);
}

static uint8_t trace_path(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                          int start_level, const spm_trace_params *p, size_t i, spm_path *path)
{
    spm_ref_key k = {p->seed, 0, 0};
    spm_ref_path_key(p, i, &k.pixel, &k.sample);
    feeler f = {start_level, SPM_SETBY_NONE};
    spm_path_head *h = &path->h;
    *h = (spm_path_head){0, SPM_END_ABSORBED, SPM_NONE, 0.0f, SPM_NONE, 0.0f, 0, 0};
    spm_ref_walk walk = {g->disp, p->disperse, SPM_NONE};

    float o[3], d[3], weight = 1.0f; /* product of the weights over survived vertices */
    float cpdf = -1.0f; /* the last vertex's density of its sampled ray, for MIS at the
                           emission it hits (< 0: not counted, 0: a delta) */
    int seg = 0;        /* the last vertex records the length of its ray's segment */
    spm_ref_pixel_ray(&p->cam, k.seed, k.pixel, k.sample, o, d);
    spm_u32 skip = 0xFFFFFFFFu;
    /* a textured vertex's ray cone (texture.clh): width w, spread g, from a
     * pixel's angle (an orthographic pixel's width, spread 0) */
    float pix = 2.0f * p->cam.tan_half / (float)p->cam.width;
    float cone_w = p->cam.ortho ? pix : 0.0f, cone_g = p->cam.ortho ? 0.0f : pix;
    for (int j = 0;; j++) {
        float t, x[3];
        spm_ref_hit hf;
        int hit = spm_ref_next_vertex(g, o, d, skip, &t, x, &hf);
        if (hit < 0) {
            escape(g, p, d, &k, j, cpdf, weight, path);
            if (h->bg != SPM_NONE)
                feel(&f, lvlk, h->bg, 1, SPM_SETBY_EMITTER);
            break;
        }
        const spm_tri *tri = &g->tris[hit];
        spm_material mix;
        spm_u32 mi = spm_ref_mix_pick(g, mats, (spm_u32)hit, x, &k, j, &mix);
        const spm_material *m = &mix;
        if (seg && j > 0) /* the segment's length: a medium's absorption, in the shade stage */
            path->x[j - 1].lobe = t;
        hit_emission(g, m, hit, j, t, o, d, x, &k, skip, cpdf, weight, path, &f, lvlk);
        spm_ref_bsdf b;
        spm_ref_begin(m, &hf, &k, j, &walk, &b);
        spm_u32 dim = SPM_DIM_VERTEX(j);
        float c = 0.0f, cos_light = 0.0f;
        spm_u32 e = SPM_NONE;
        spm_ref_lsample ls;
        if (g->nemitters > 0 && b.nee && /* next-event estimation */
            spm_ref_light_sample(g, mats, &k, dim, x, (spm_u32)hit, &hf, &ls))
            e = light_weight(m, &b, &hf, &ls, &c, &cos_light);
        float mmean, minv;
        spm_u32 refl = spm_ref_lobe(m, &b, &mmean, &minv);
        if (g->ntex) {
            cone_w += cone_g * t;
            float r = 1.0f; /* Russian roulette on the pick's own mean (SPM_TEXD_SURVIVE) */
            refl = spm_ref_texture_colour(g, mi, (spm_u32)hit, x, d, cone_w, &k, j, refl,
                                          m->refl, &r);
            mmean *= r;
            minv = r > 0.0f ? minv / r : 0.0f;
        }
        spm_vertex *vx = &path->v[j];
        vx->ids = (refl & 0xFFFFu) | (e << 16);
        vx->c = c * weight;
        path->x[j] = (spm_vertex_ext){0u, 0.0f, cos_light, 0.0f};
        spm_u32 col2 = spm_ref_record(m, &b, &walk, &path->x[j]);
        cpdf = -1.0f;
        seg = 0;
        h->nvert = (spm_u32)j + 1;
        if (refl != SPM_NONE)
            feel(&f, lvlk, refl, occurrences(path, j, refl), SPM_SETBY_REFLECTOR);
        if (e != SPM_NONE)
            feel(&f, lvlk, e, 1, SPM_SETBY_EMITTER);
        if (col2 != SPM_NONE)
            feel(&f, lvlk, col2, 1, SPM_SETBY_REFLECTOR);

        if (!(spm_ref_rnd(&k, dim + SPM_DIM_RR) < mmean)) {
            h->end = SPM_END_ABSORBED;
            break;
        }
        if (j + 1 == SPM_MAX_DEPTH) {
            h->end = SPM_END_TRUNCATED; /* it would go on, but the record is full */
            break;
        }
        weight *= minv;
        spm_ref_bsample s;
        /* a sampled direction on the wrong side of its frame, or on the other
         * side of the geometric surface than of the shading one (a reflection
         * under it, a refraction over it): the path ends */
        if (!spm_ref_sample_sided(m, &b, &hf, &k, j, SPM_REF_RADIANCE, &s)) {
            h->end = SPM_END_ABSORBED;
            break;
        }
        weight *= s.wt;
        weight *= s.w;
        if (g->ntex)
            cone_g = spm_ref_cone_bounce(g, tri, cone_g, cone_w, hf.n, b.eta, d, &s);
        cpdf = s.pdf;
        seg = s.inside;
        path->x[j].lobe = s.cos_lobe;
        for (int i = 0; i < 3; i++)
            o[i] = x[i], d[i] = s.wi[i];
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
