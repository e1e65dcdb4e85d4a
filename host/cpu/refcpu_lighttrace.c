/* CPU reference, trace stage of the light integrator (--integrator light):
 * a subpath from a light, each of its vertices connected to the camera and
 * recorded with the pixel its splat lands in (refcpu.h spm_light_path;
 * docs/ARCHITECTURE.md "Light subpaths"). In order:
 *   the light by the selection, its ray (light_sample_emission), the light's
 *   own vertex to the camera (an area light's); then for each surface vertex
 *   j: hit, the vertex's BSDF, its connection to the camera (sample_Wi,
 *   visibility, the importance-mode eval), Russian roulette, the
 *   importance-mode sampled direction. A ray that meets nothing ends it.
 * Like the path loop it names no material type and no light kind. */
#include "refcpu.h"
#include <math.h>
#include "geometry_vec3.h"
#include "spm_rng.h"
#include "refcpu_bsdf.h"
#include "refcpu_metalrough.h"
#include "refcpu_lights.h"
#include "refcpu_camera.h"
#include "refcpu_shading.h"
#include "refcpu_feeler.h"
#include "refcpu_bdpt.h"
#include "refcpu_texture.h"

/* The pixel film point (fx, fy) in [-1, 1]^2 falls in (fy = 1 the top row),
 * the inverse of the camera ray's cx = 2 (x + u) / w - 1, cy = 1 - 2 (y + v) / h. */
static spm_u32 film_pixel(const spm_camera *cam, const float film[2])
{
    int x = (int)floorf((film[0] + 1.0f) * 0.5f * (float)cam->width);
    int y = (int)floorf((1.0f - film[1]) * 0.5f * (float)cam->height);
    x = x < 0 ? 0 : x >= cam->width ? cam->width - 1 : x;
    y = y < 0 ? 0 : y >= cam->height ? cam->height - 1 : y;
    return (spm_u32)y * (spm_u32)cam->width + (spm_u32)x;
}

/* The camera seen from p (leaving triangle skip) with the lens sample of
 * dimensions dim, dim + 1: We / pdf, pdf sample_Wi's density in solid angle
 * at p; wi toward the lens and the pixel. 0 when the camera does not see p
 * or something is between. A pass traces npix spp subpaths and a pixel's
 * importance is npix We (We integrates to 1 over the whole film), so a
 * pixel's estimate, its splats' sum over spp like a camera path's, needs no
 * other factor. */
static float camera_link(const spm_camera *cam, const spm_geometry *g, const spm_ref_key *k,
                         spm_u32 dim, const float p[3], spm_u32 skip, float wi[3], spm_u32 *px)
{
    float dist, pdf, film[2], t;
    float we = spm_ref_camera_sample_Wi(cam, p, spm_ref_rnd(k, dim), spm_ref_rnd(k, dim + 1u), wi,
                                        &dist, &pdf, film);
    if (!(we > 0.0f) || !(pdf > 0.0f))
        return 0.0f;
    spm_ref_record_ray(p, wi, skip, SPM_RAY_CLOSEST);
    if (spm_bvh_intersect(g, p, wi, skip, &t) >= 0 && t < dist)
        return 0.0f;
    *px = film_pixel(cam, film);
    return we / pdf;
}

/* The light's emission along d leaving o: its colour and *scale (Le for an
 * area light, I for a point light), *cos_o its cosine to the light's face (1
 * without a face). */
static spm_u32 emission(const spm_geometry *g, const spm_material *mats, const spm_emitter *e,
                        const float d[3], float *scale, float *cos_o)
{
    *cos_o = 1.0f;
    if (e->kind != SPM_LIGHT_AREA) { /* I, times a spot's falloff (it samples its whole cone) */
        *scale = e->p[SPM_LIGHT_P_SCALE];
        if (e->kind == SPM_LIGHT_SPOT)
            *scale *= spm_ref_spot_falloff(e, v3_dot(d, &e->p[SPM_LIGHT_P_DIR]));
        return e->colour;
    }
    const spm_tri *tr = &g->tris[e->tri];
    const spm_material *m = &mats[tr->material];
    float c = v3_dot(d, tr->n);
    if (m->type & SPM_EMIT_TWOSIDED)
        c = fabsf(c);
    *cos_o = c;
    if (!(c > 0.0f)) {
        *scale = 0.0f;
        return SPM_NONE;
    }
    return spm_ref_light_eval(m, c, scale);
}

/* The light's own vertex seen by the camera (an area light: a point light
 * is a delta no camera ray meets): Le |cos| We / (pdf_Wi pmf pdf_pos). */
static void light_vertex(const spm_geometry *g, const spm_material *mats, const spm_emitter *e,
                         const spm_ref_key *k, const float o[3], float pdf_pos, float ts,
                         spm_light_path *lp)
{
    float wi[3], scale, cos_o;
    spm_u32 px = SPM_NO_PIXEL;
    if (e->kind != SPM_LIGHT_AREA)
        return;
    float w = camera_link(&g->cam, g, k, SPM_DIM_LT_LENS, o, e->tri, wi, &px);
    if (!(w > 0.0f) || emission(g, mats, e, wi, &scale, &cos_o) == SPM_NONE)
        return;
    lp->p.h.first_emit_c = scale * ts * cos_o * w / (e->pdf * pdf_pos);
    lp->px[0] = px;
}

/* The vertex's connection to the camera: the splat weight
 *   beta f |cos_i| We / pdf_Wi,
 * f |cos_i| the type's in importance mode (its colour applied by the shade
 * stage's vertex_apply, which reads cos_light); 0: none. */
static float vertex_link(const spm_geometry *g, const spm_material *m, const spm_ref_bsdf *b,
                         const spm_ref_hit *h, const spm_ref_key *k, int j, const float x[3],
                         spm_u32 hit, float beta, spm_vertex_ext *xv, spm_u32 *px)
{
    float wi[3];
    if (!b->nee)
        return 0.0f; /* a delta lobe: no direction but its own reaches the lens */
    float w = camera_link(&g->cam, g, k, SPM_DIM_VERTEX(j) + SPM_DIM_EPOINT_A, x, hit, wi, px);
    if (!(w > 0.0f))
        return 0.0f;
    spm_ref_eval e = spm_ref_eval_bsdf(m, b, h, wi, SPM_REF_IMPORTANCE | SPM_REF_JOIN);
    xv->light = e.cos_light;
    float wo[3] = {-h->d[0], -h->d[1], -h->d[2]};
    float c = beta * (e.k * e.f / e.div) / e.post * w;
    c *= spm_ref_adjoint_ns(h, wo, wi);
    return c > 0.0f ? c : 0.0f;
}

/* Starts subpath k: the light, its ray o + t d, the emission's colour and
 * beta = Le |cos_o| / (pmf pdf_pos pdf_dir); 0 when the light gives none. */
static int start(const spm_geometry *g, const spm_material *mats, const spm_ref_key *k,
                 spm_light_path *lp, float o[3], float d[3], float *beta, spm_u32 *colour,
                 spm_u32 *skip)
{
    const spm_emitter *e = spm_ref_light_pick(g, k, SPM_DIM_VERTEX(0));
    float u[4] = {spm_ref_rnd(k, SPM_DIM_LT_EMIT), spm_ref_rnd(k, SPM_DIM_LT_EMIT + 1u),
                  spm_ref_rnd(k, SPM_DIM_LT_EMIT + 2u), spm_ref_rnd(k, SPM_DIM_LT_EMIT + 3u)};
    float pp, pd, scale, cos_o;
    spm_ref_light_sample_emission(g, (spm_u32)(e - g->emitters), u, o, d, &pp, &pd);
    if (!(pp > 0.0f && pd > 0.0f))
        return 0;
    float ts = 1.0f; /* a textured emission's factor at o, looked up once */
    *colour = emission(g, mats, e, d, &scale, &cos_o);
    if (e->kind == SPM_LIGHT_AREA)
        *colour = spm_ref_emit_texture(g, e->tri, o, k, SPM_MAX_DEPTH, 0u, *colour, &ts);
    if (*colour == SPM_NONE)
        return 0;
    *beta = scale * ts * cos_o / (e->pdf * pp * pd);
    *skip = e->kind == SPM_LIGHT_AREA ? e->tri : 0xFFFFFFFFu;
    lp->p.h.first_emit = *colour;
    light_vertex(g, mats, e, k, o, pp, ts, lp);
    return 1;
}

static uint8_t trace_light_path(const spm_geometry *g, const spm_material *mats,
                                const uint8_t *lvlk, int start_level, const spm_trace_params *p,
                                size_t i, spm_light_path *lp)
{
    spm_ref_key k = {p->seed, 0, 0};
    spm_ref_path_key(p, i, &k.pixel, &k.sample);
    feeler f = {start_level, SPM_SETBY_NONE};
    spm_path *path = &lp->p;
    spm_path_head *h = &path->h;
    *h = (spm_path_head){0, SPM_END_ABSORBED, SPM_NONE, 0.0f, SPM_NONE, 0.0f, 0, 0};
    for (int j = 0; j <= SPM_MAX_DEPTH; j++)
        lp->px[j] = SPM_NO_PIXEL;
    spm_ref_walk walk = {g->disp, p->disperse, SPM_NONE};
    float o[3], d[3], beta;
    spm_u32 colour, skip;
    if (g->nemitters == 0 || !start(g, mats, &k, lp, o, d, &beta, &colour, &skip))
        return (uint8_t)start_level;
    feel(&f, lvlk, colour, 1, SPM_SETBY_EMITTER);
    int seg = 0;
    for (int j = 0;; j++) {
        float t, x[3];
        spm_ref_hit hf;
        int hit = spm_ref_next_vertex(g, o, d, skip, &t, x, &hf);
        if (hit < 0) {
            h->end = SPM_END_ESCAPED;
            break;
        }
        spm_material mix;
        spm_u32 mi = spm_ref_mix_pick(g, mats, (spm_u32)hit, x, &k, j, &mix);
        const spm_material *m = &mix;
        if (seg && j > 0) /* the segment's length inside: its absorption, in the shade stage */
            path->x[j - 1].lobe = t;
        spm_ref_bsdf b;
        spm_ref_begin(m, &hf, &k, j, &walk, &b);
        float mmean, minv;
        spm_u32 refl = spm_ref_lobe(m, &b, &mmean, &minv);
        refl = spm_ref_texture_seen(g, mi, (spm_u32)hit, x, &k, j, refl, m->refl, &mmean, &minv);
        path->x[j] = (spm_vertex_ext){0u, 0.0f, 0.0f, 0.0f};
        float c = vertex_link(g, m, &b, &hf, &k, j, x, (spm_u32)hit, beta, &path->x[j],
                              &lp->px[j + 1]);
        if (!(c > 0.0f))
            lp->px[j + 1] = SPM_NO_PIXEL;
        path->v[j] = (spm_vertex){(refl & 0xFFFFu) | (colour << 16), c};
        spm_u32 col2 = spm_ref_record(m, &b, &walk, &path->x[j]);
        seg = 0;
        h->nvert = (spm_u32)j + 1;
        if (refl != SPM_NONE)
            feel(&f, lvlk, refl, occurrences(path, j, refl), SPM_SETBY_REFLECTOR);
        if (col2 != SPM_NONE)
            feel(&f, lvlk, col2, 1, SPM_SETBY_REFLECTOR);
        if (refl == SPM_NONE || !(spm_ref_rnd(&k, SPM_DIM_VERTEX(j) + SPM_DIM_RR) < mmean))
            break;
        if (j + 1 == SPM_MAX_DEPTH) {
            h->end = SPM_END_TRUNCATED;
            break;
        }
        beta *= minv;
        spm_ref_bsample s;
        if (!spm_ref_sample_sided(m, &b, &hf, &k, j, SPM_REF_IMPORTANCE, &s))
            break;
        beta *= s.wt;
        beta *= s.w;
        float wo[3] = {-d[0], -d[1], -d[2]};
        beta *= spm_ref_adjoint_ns(&hf, wo, s.wi);
        seg = s.inside;
        path->x[j].lobe = s.cos_lobe;
        for (int a = 0; a < 3; a++)
            o[a] = x[a], d[a] = s.wi[a];
        skip = (spm_u32)hit;
    }
    return (uint8_t)((spm_u32)f.level | (f.setby << SPM_SETBY_SHIFT));
}

void spm_ref_light_trace_range(const spm_geometry *g, const spm_material *mats,
                               const uint8_t *lvlk, int start_level, const spm_trace_params *p,
                               size_t begin, size_t end, spm_light_path *paths, uint8_t *levels)
{
    for (size_t i = begin; i < end; i++)
        levels[i - begin] =
            trace_light_path(g, mats, lvlk, start_level, p, i, &paths[i - begin]);
}

/* The pieces the bidirectional tracer shares (refcpu_bdpt.h). */
spm_u32 spm_ref_lt_film_pixel(const spm_camera *cam, const float film[2])
{
    return film_pixel(cam, film);
}

spm_u32 spm_ref_lt_emission(const spm_geometry *g, const spm_material *mats, const spm_emitter *e,
                            const float d[3], float *scale, float *cos_o)
{
    return emission(g, mats, e, d, scale, cos_o);
}
