/* The CPU reference's light contract (kernels/lights.clh has the kernels'
 * own and says what each call means): one switch per call on the selected
 * light's kind, generated from include/spm_lights.h, each kind in a file of
 * its own (refcpu_light_<name>.c). Plain scalar float C, in the kernels'
 * operation order. */
#ifndef SPM_REFCPU_LIGHTS_H
#define SPM_REFCPU_LIGHTS_H
#include "geometry.h"
#include "refcpu_bsdf.h"

/* A light sample toward a shading point (kernels/lights.clh spm_light_sample). */
typedef struct {
    float wi[3];
    float g, pdf, scale;
    spm_u32 colour;
    int delta;
    float pmf, inv_pmf; /* the selection's probability of the light, and its inverse */
} spm_ref_lsample;

/* The light tree's walk (refcpu_light_tree.c; g->ntree > 0): the emitter it
 * picks from shading point x of geometric normal n with uniform number u
 * (-1: none lights x), *pmf its probability; the probability of emitter em
 * (the pick's, by the same walk); the emitter index of area light triangle
 * tri. */
int spm_ref_ltree_pick(const spm_geometry *g, const float x[3], const float n[3], float u,
                       float *pmf);
float spm_ref_ltree_pmf(const spm_geometry *g, const float x[3], const float n[3], spm_u32 em);
spm_u32 spm_ref_ltree_area_index(const spm_geometry *g, spm_u32 tri);
/* The selection's probability of light em from shading point x on triangle
 * from (its geometric normal; the light tree's) */
float spm_ref_light_pmf(const spm_geometry *g, const float x[3], spm_u32 from, spm_u32 em);
/* the light the power selection picks with vertex dimension dim's number
 * (the light tracer's, which has no shading point) */
const spm_emitter *spm_ref_light_pick(const spm_geometry *g, const spm_ref_key *k, spm_u32 dim);
/* the emission of material m toward cosine cos_e > 0 to its face: its colour
 * and *scale (SPM_NONE: none) */
spm_u32 spm_ref_light_eval(const spm_material *m, float cos_e, float *scale);
/* colour c and factor *scale of emitting triangle hit's material at its
 * point x, with a texture on the emission: the palette colour picked there
 * from dimensions SPM_DIM_ETEX(j, k0 .. k0 + 2), *scale times the
 * material's factor (kernels/light_area.clh emit_texture) */
spm_u32 spm_ref_emit_texture(const spm_geometry *g, spm_u32 hit, const float x[3],
                             const spm_ref_key *k, spm_u32 j, spm_u32 k0, spm_u32 c, float *scale);
/* the background an escaping ray of direction d meets (SPM_NONE: dark) */
spm_u32 spm_ref_light_background(const spm_trace_params *p, const float d[3]);
/* What an escaping ray of direction d meets in vertex j's place of path k
 * (kernels/lights.clh light_escape): a daylight sky's sun inside its disc
 * (the entry before the map), the environment map, the selection's last
 * entry when the scene has one, else the background; *scale the colour's
 * factor, *pdf light_sample's density of d (0: the background). */
spm_u32 spm_ref_light_escape(const spm_geometry *g, const spm_trace_params *p, const float d[3],
                             const spm_ref_key *k, spm_u32 j, float *scale, float *pdf);
spm_u32 spm_ref_light_escape_ENVMAP(const spm_geometry *g, const spm_emitter *e, float pmf,
                                    const float d[3], const spm_ref_key *k, spm_u32 j, float *scale,
                                    float *pdf);
spm_u32 spm_ref_light_escape_SUN(const spm_emitter *e, float pmf, const float d[3], float *scale,
                                 float *pdf);
/* light_sample's density of the point a ray from o (on triangle from) found
 * at distance t on emitting triangle tri (face cosine ce), in solid angle */
float spm_ref_light_pdf_hit(const spm_geometry *g, const float o[3], spm_u32 from, spm_u32 tri,
                            float t, float ce);
/* A light sample from x on triangle hit (frame h) with vertex dimension dim's
 * random numbers; 0 when occluded, back-facing or on the other side. */
int spm_ref_light_sample(const spm_geometry *g, const spm_material *mats, const spm_ref_key *k,
                         spm_u32 dim, const float x[3], spm_u32 hit, const spm_ref_hit *h,
                         spm_ref_lsample *ls);
/* A ray leaving light k of the selection from o along d (unit), from four
 * uniform numbers: *pdf_pos the density of the point (per area; 1 for a
 * point light), *pdf_dir of the direction (per solid angle). */
void spm_ref_light_sample_emission(const spm_geometry *g, spm_u32 k, const float u[4], float o[3],
                                   float d[3], float *pdf_pos, float *pdf_dir);
/* its densities of a ray leaving light k from o along d */
void spm_ref_light_pdf_emission(const spm_geometry *g, spm_u32 k, const float o[3],
                                const float d[3], float *pdf_pos, float *pdf_dir);

/* Each kind's part (include/spm_lights.h; host/cpu/refcpu_light_<name>.c):
 * its sample from light e of the selection, its emission ray and densities. */
#define SPM_LIGHT_KIND(NAME, ...)                                                               \
    int spm_ref_light_sample_##NAME(const spm_geometry *g, const spm_material *mats,           \
                                    const spm_emitter *e, const spm_ref_key *k, spm_u32 dim,    \
                                    const float x[3], spm_u32 hit, const spm_ref_hit *h,        \
                                    spm_ref_lsample *ls);                                       \
    void spm_ref_light_sample_emission_##NAME(const spm_geometry *g, const spm_emitter *e,     \
                                              const float u[4], float o[3], float d[3],         \
                                              float *pdf_pos, float *pdf_dir);                  \
    void spm_ref_light_pdf_emission_##NAME(const spm_geometry *g, const spm_emitter *e,        \
                                           const float o[3], const float d[3], float *pdf_pos, \
                                           float *pdf_dir);
#include "spm_lights.h"
#undef SPM_LIGHT_KIND
/* toward the position of light e from x on a surface (frame h): ls->wi and
 * the squared distance *d2; 0 when it is there or on the other side of the
 * surface than the viewer (no transmission) */
int spm_ref_light_toward(const spm_emitter *e, const float x[3], const spm_ref_hit *h,
                         spm_ref_lsample *ls, float *d2);
/* the shadow ray from x along wi (recorded for the ray bench, as every
 * light sample's): 1 when no triangle but hit's lies on it nearer than dist */
int spm_ref_light_unblocked(const spm_geometry *g, const float x[3], const float wi[3], spm_u32 hit,
                            float dist);
/* 1 when wi leaves the surface (frame h) on the viewer's side: no light
 * reaches the viewer through it (no transmission) */
int spm_ref_light_faces(const float wi[3], const spm_ref_hit *h);
/* a delta light's sample (no MIS): weight g, light e's colour at factor
 * scale; returns 1 */
int spm_ref_light_delta(spm_ref_lsample *ls, const spm_emitter *e, float g, float scale);
/* l in the frame whose z axis is n (unit): kernels/lights.clh light_to_world */
void spm_ref_light_to_world(const float n[3], const float l[3], float out[3]);
/* the ray sink's hook (refcpu.h spm_ref_rays): ray o + t d, what it asks */
void spm_ref_record_ray(const float o[3], const float d[3], spm_u32 skip, spm_u32 emitter);
/* 1 when light e is at infinity (a distant light, the sun, the map): its
 * emission rays leave a disc of the scene's bounding sphere, pdf_pos per
 * unit area across the ray (pbrt-v4's infinite lights in BDPT) */
int spm_ref_light_at_infinity(const spm_emitter *e);
/* An area light's density of emission direction d (unit) from its face of
 * normal n, in solid angle (refcpu_light_area.c): cos / pi on the front, a
 * two-sided light's |cos| / (2 pi) */
float spm_ref_light_area_pdf_dir(int twosided, const float n[3], const float d[3]);
/* A spot light's falloff f(theta) at cosine cos_l to its axis
 * (refcpu_light_spot.c): the light tracer's intensity in a sampled direction. */
float spm_ref_spot_falloff(const spm_emitter *e, float cos_l);
#endif
