/* The CPU reference's lights (refcpu_lights.h): the selection, and one
 * switch per call on the chosen light's kind. */
#include "refcpu_lights.h"
#include "refcpu.h"
#include "geometry_vec3.h"

/* by power a constant per light, through the tree a walk from x */
float spm_ref_light_pmf(const spm_geometry *g, const float x[3], spm_u32 from, spm_u32 em)
{
    if (g->ntree)
        return spm_ref_ltree_pmf(g, x, g->tris[from].n, em);
    return g->emitters[em].pdf;
}

/* The power selection (spm_shared.h spm_emitter): by power through the
 * table, or MiniLight's uniform pick when the powers are equal. */
const spm_emitter *spm_ref_light_pick(const spm_geometry *g, const spm_ref_key *k, spm_u32 dim)
{
    int ne = g->nemitters;
    if (g->emit_power) {
        spm_u32 u24 = spm_rng_u32(k->seed, k->pixel, k->sample, dim + SPM_DIM_EMITTER) >> 8;
        return &g->emitters[spm_emitter_search(g->emitters, (spm_u32)ne, u24)];
    }
    int pick = (int)(spm_ref_rnd(k, dim + SPM_DIM_EMITTER) * (float)ne);
    return &g->emitters[pick < ne ? pick : ne - 1];
}

int spm_ref_light_sample(const spm_geometry *g, const spm_material *mats, const spm_ref_key *k,
                         spm_u32 dim, const float x[3], spm_u32 hit, const spm_ref_hit *h,
                         spm_ref_lsample *ls)
{
    const spm_emitter *e;
    if (g->ntree) { /* the tree's pick from x */
        int em = spm_ref_ltree_pick(g, x, g->tris[hit].n, spm_ref_rnd(k, dim + SPM_DIM_EMITTER),
                                    &ls->pmf);
        if (em < 0)
            return 0;
        e = &g->emitters[em];
        ls->inv_pmf = 1.0f / ls->pmf;
    } else {
        e = spm_ref_light_pick(g, k, dim);
        ls->pmf = e->pdf;
        ls->inv_pmf = e->inv_pdf;
    }
    switch (e->kind) {
#define SPM_LIGHT_KIND(NAME, ...) \
    case SPM_LIGHT_##NAME: return spm_ref_light_sample_##NAME(g, mats, e, k, dim, x, hit, h, ls);
#include "spm_lights.h"
#undef SPM_LIGHT_KIND
    default:
        return 0;
    }
}

void spm_ref_light_sample_emission(const spm_geometry *g, spm_u32 k, const float u[4], float o[3],
                                   float d[3], float *pdf_pos, float *pdf_dir)
{
    const spm_emitter *e = &g->emitters[k];
    switch (e->kind) {
#define SPM_LIGHT_KIND(NAME, ...)                                              \
    case SPM_LIGHT_##NAME:                                                     \
        spm_ref_light_sample_emission_##NAME(g, e, u, o, d, pdf_pos, pdf_dir); \
        return;
#include "spm_lights.h"
#undef SPM_LIGHT_KIND
    default:
        *pdf_pos = *pdf_dir = 0.0f;
    }
}

void spm_ref_light_pdf_emission(const spm_geometry *g, spm_u32 k, const float o[3],
                                const float d[3], float *pdf_pos, float *pdf_dir)
{
    const spm_emitter *e = &g->emitters[k];
    switch (e->kind) {
#define SPM_LIGHT_KIND(NAME, ...)                                           \
    case SPM_LIGHT_##NAME:                                                  \
        spm_ref_light_pdf_emission_##NAME(g, e, o, d, pdf_pos, pdf_dir);    \
        return;
#include "spm_lights.h"
#undef SPM_LIGHT_KIND
    default:
        *pdf_pos = *pdf_dir = 0.0f;
    }
}

/* Duff et al. 2017's branchless orthonormal basis (b1, b2, n) */
void spm_ref_light_to_world(const float n[3], const float l[3], float out[3])
{
    float sg = n[2] >= 0.0f ? 1.0f : -1.0f, a = -1.0f / (sg + n[2]), b = n[0] * n[1] * a;
    float b1[3] = {1.0f + sg * n[0] * n[0] * a, sg * b, -sg * n[0]};
    float b2[3] = {b, sg + n[1] * n[1] * a, -n[1]};
    for (int i = 0; i < 3; i++)
        out[i] = l[0] * b1[i] + l[1] * b2[i] + l[2] * n[i];
}

int spm_ref_light_at_infinity(const spm_emitter *e)
{
    return e->kind == SPM_LIGHT_DISTANT || e->kind == SPM_LIGHT_SUN || e->kind == SPM_LIGHT_ENVMAP;
}

int spm_ref_light_delta(spm_ref_lsample *ls, const spm_emitter *e, float g, float scale)
{
    ls->pdf = 0.0f;
    ls->g = g;
    ls->scale = scale;
    ls->colour = e->colour;
    ls->delta = 1;
    return 1;
}

int spm_ref_light_unblocked(const spm_geometry *g, const float x[3], const float wi[3], spm_u32 hit,
                            float dist)
{
    float ts;
    spm_ref_record_ray(x, wi, hit, SPM_RAY_CLOSEST);
    return !(spm_bvh_intersect(g, x, wi, hit, &ts) >= 0 && ts < dist);
}

int spm_ref_light_faces(const float wi[3], const spm_ref_hit *h)
{
    float cos_i = v3_dot(wi, h->ng), cos_o = -v3_dot(h->d, h->ng);
    return (cos_i < 0.0f) == (cos_o < 0.0f);
}

int spm_ref_light_toward(const spm_emitter *e, const float x[3], const spm_ref_hit *h,
                         spm_ref_lsample *ls, float *d2)
{
    float ev[3];
    v3_sub(ev, &e->p[SPM_LIGHT_P_POS], x);
    *d2 = v3_dot(ev, ev);
    v3_normalise(ls->wi, ev);
    return *d2 > 0.0f && spm_ref_light_faces(ls->wi, h);
}

spm_u32 spm_ref_light_escape(const spm_geometry *g, const spm_trace_params *p, const float d[3],
                             const spm_ref_key *k, spm_u32 j, float *scale, float *pdf)
{
    spm_u32 n = g->nemitters, s = n - 1 - (n > 0 && g->emitters[n - 1].kind == SPM_LIGHT_ENVMAP);
    int map = n > 0 && g->emitters[n - 1].kind == SPM_LIGHT_ENVMAP;
    /* the sun, next before the map: inside its disc, the disc alone (no
     * shading point: the pmf of a light beside the tree is the same from all) */
    if (n > (spm_u32)map && g->emitters[s].kind == SPM_LIGHT_SUN) {
        float pmf = spm_ref_light_pmf(g, d, 0, s);
        spm_u32 c = spm_ref_light_escape_SUN(&g->emitters[s], pmf, d, scale, pdf);
        if (c != SPM_NONE)
            return c;
    }
    if (map)
        return spm_ref_light_escape_ENVMAP(g, &g->emitters[n - 1],
                                           spm_ref_light_pmf(g, d, 0, n - 1), d, k, j, scale, pdf);
    *scale = 1.0f;
    *pdf = 0.0f;
    return spm_ref_light_background(p, d);
}
