/* The CPU reference's area light kind (kernels/light_area.clh): triangles
 * of an emitting material, their profile the material's emitter type. */
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu.h"
#include "refcpu_lights.h"
#include "refcpu_texture.h"
#include <string.h>

/* a uniform emitter, its colour the material's emission */
static spm_u32 light_eval_AREA(const spm_material *m, float cos_e, float *scale)
{
    (void)cos_e;
    *scale = 1.0f;
    return m->emit;
}

spm_u32 spm_ref_light_eval(const spm_material *m, float cos_e, float *scale)
{
    switch (SPM_EMIT_TAG(*m)) {
#define SPM_MATERIAL_TYPE(NAME, ...)
#define SPM_EMITTER_TYPE(NAME, ...) \
    case SPM_EMIT_##NAME: return light_eval_##NAME(m, cos_e, scale);
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
#undef SPM_EMITTER_TYPE
    default:
        *scale = 0.0f;
        return SPM_NONE;
    }
}

spm_u32 spm_ref_emit_texture(const spm_geometry *g, spm_u32 hit, const float x[3],
                             const spm_ref_key *k, spm_u32 j, spm_u32 k0, spm_u32 c, float *scale)
{
    const spm_u32 *tex = g->tex;
    if (!g->ntex || tex[SPM_TEXD_EMIT] == 0u || c == SPM_NONE)
        return c;
    const spm_tri *tr = &g->tris[hit];
    const spm_u32 *mw = tex + tex[SPM_TEXD_EMIT] + 2u * tr->material;
    spm_u32 tx = mw[0] & 0xFFFFu;
    if (tx == 0u)
        return c;
    float u, v, f;
    spm_tri_uv(tr, g->uvs + 6u * hit, x, &u, &v);
    spm_u32 node = spm_ref_texture_node(g, tex + tex[tex[SPM_TEXD_TEXS] + tx - 1u], 0u, u, v,
                                        spm_ref_rnd(k, SPM_DIM_ETEX(j, k0)),
                                        spm_ref_rnd(k, SPM_DIM_ETEX(j, k0 + 1u)),
                                        spm_ref_rnd(k, SPM_DIM_ETEX(j, k0 + 2u)));
    memcpy(&f, &mw[1], sizeof f);
    *scale *= f;
    return tex[tex[SPM_TEXD_PALETTE] + (mw[0] >> 16) * SPM_TEX_NODES_ALL + node];
}

float spm_ref_light_pdf_hit(const spm_geometry *g, const float o[3], spm_u32 from, spm_u32 tri,
                            float t, float ce)
{
    const spm_tri *tr = &g->tris[tri];
    float d2 = t * t, d2min = SPM_D2_MIN_REL * tr->area;
    float pmf = g->ntree ? spm_ref_light_pmf(g, o, from, spm_ref_ltree_area_index(g, tri))
                         : g->light_pdf[tri];
    return pmf * (d2 > d2min ? d2 : d2min) / (tr->area * ce);
}

int spm_ref_light_sample_AREA(const spm_geometry *g, const spm_material *mats, const spm_emitter *e,
                              const spm_ref_key *k, spm_u32 dim, const float x[3], spm_u32 hit,
                              const spm_ref_hit *h, spm_ref_lsample *ls)
{
    spm_u32 ei = e->tri;
    const spm_tri *em = &g->tris[ei];
    float sqr1 = sqrtf(spm_ref_rnd(k, dim + SPM_DIM_EPOINT_A));
    float a = 1.0f - sqr1, b = (1.0f - spm_ref_rnd(k, dim + SPM_DIM_EPOINT_B)) * sqr1;
    float q[3], ev[3], ts;
    for (int i = 0; i < 3; i++)
        q[i] = em->v0[i] + (em->v1[i] - em->v0[i]) * a + (em->v2[i] - em->v0[i]) * b;
    v3_sub(ev, q, x);
    v3_normalise(ls->wi, ev);
    spm_ref_record_ray(x, ls->wi, hit, ei);
    int blocker = spm_bvh_intersect(g, x, ls->wi, hit, &ts);
    if (blocker >= 0 && (spm_u32)blocker != ei)
        return 0;
    if (blocker < 0 && g->ntex) { /* the light's surface not there at the point (opacity) */
        float xs[3]; /* where the shadow ray starts (spm_ray_spawn) */
        spm_ray_spawn(g, hit, x, ls->wi, xs);
        float te = spm_tri_intersect(&g->tris[ei], xs, ls->wi);
        if (te > 0.0f && !spm_alpha_there(g, ei, xs, ls->wi, te))
            return 0;
    }
    float cos_e = -v3_dot(ls->wi, em->n);
    if (mats[em->material].type & SPM_EMIT_TWOSIDED)
        cos_e = fabsf(cos_e); /* 'twosided': the back face emits too */
    if (!(cos_e > 0.0f))
        return 0; /* emitters emit from their front face only (unless twosided) */
    float cos_i = v3_dot(ls->wi, h->ng), cos_o = -v3_dot(h->d, h->ng);
    if ((cos_i < 0.0f) != (cos_o < 0.0f))
        return 0; /* light and viewer on different sides: no transmission */
    float d2 = v3_dot(ev, ev), d2min = SPM_D2_MIN_REL * em->area;
    float d2c = d2 > d2min ? d2 : d2min;
    ls->pdf = ls->pmf * d2c / (em->area * cos_e);
    ls->g = ls->inv_pmf * cos_e * em->area / d2c;
    ls->colour = spm_ref_light_eval(&mats[em->material], cos_e, &ls->scale);
    ls->colour = spm_ref_emit_texture(g, ei, q, k, (dim - SPM_DIM_VERTEX(0)) / SPM_DIMS_PER_VERTEX,
                                      SPM_DIM_ETEX_NEE, ls->colour, &ls->scale);
    ls->delta = 0;
    return 1;
}

/* the face an emission ray leaves by, from u4: the front; a two-sided
 * light's (p[D] = 1) either, each with probability 1/2, u4 rescaled to
 * [0, 1) for the cosine it then draws. Returns the face's sign. */
static float emission_face(const spm_emitter *e, float *u4)
{
    if (!(e->p[SPM_LIGHT_P_D] > 0.0f))
        return 1.0f;
    float u = 2.0f * *u4, side = u < 1.0f ? 1.0f : -1.0f;
    *u4 = u < 1.0f ? u : u - 1.0f;
    return side;
}

float spm_ref_light_area_pdf_dir(int twosided, const float n[3], const float d[3])
{
    float c = v3_dot(d, n);
    if (twosided)
        return fabsf(c) / (2.0f * SPM_PI_F);
    return fmaxf(c, 0.0f) / SPM_PI_F;
}

/* a uniform point on the triangle (density 1 / area), a cosine-weighted
 * direction about its emitting face (density cos / pi; a two-sided light's
 * either face, |cos| / (2 pi)) */
void spm_ref_light_sample_emission_AREA(const spm_geometry *g, const spm_emitter *e,
                                        const float u[4], float o[3], float d[3], float *pdf_pos,
                                        float *pdf_dir)
{
    const spm_tri *et = &g->tris[e->tri];
    float u4 = u[3], side = emission_face(e, &u4);
    float sqr1 = sqrtf(u[0]), a = 1.0f - sqr1, b = (1.0f - u[1]) * sqr1, c[3];
    float phi = 2.0f * SPM_PI_F * u[2], sr = sqrtf(u4), z = sqrtf(1.0f - u4);
    v3_cross(c, et->n, et->t);
    for (int i = 0; i < 3; i++) {
        o[i] = et->v0[i] + (et->v1[i] - et->v0[i]) * a + (et->v2[i] - et->v0[i]) * b;
        d[i] = et->t[i] * (cosf(phi) * sr) + c[i] * (sinf(phi) * sr) + et->n[i] * (side * z);
    }
    *pdf_pos = 1.0f / et->area;
    *pdf_dir = z / (e->p[SPM_LIGHT_P_D] > 0.0f ? 2.0f * SPM_PI_F : SPM_PI_F);
}

void spm_ref_light_pdf_emission_AREA(const spm_geometry *g, const spm_emitter *e, const float o[3],
                                     const float d[3], float *pdf_pos, float *pdf_dir)
{
    (void)o;
    const spm_tri *tr = &g->tris[e->tri];
    *pdf_pos = 1.0f / tr->area;
    *pdf_dir = spm_ref_light_area_pdf_dir(e->p[SPM_LIGHT_P_D] > 0.0f, tr->n, d);
}
