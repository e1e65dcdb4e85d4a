/* The material and emitter type descriptors (materials.h): the entries of
 * include/spm_types.h, and the fill and derive functions they name. */
#include "materials.h"
#include <stdio.h>
#include <math.h>
#include <string.h>
#include "spm_rng.h"
#include "fluor.h"
#include "coated.h"

static double colour_mean(const spm_scene *sc, int c)
{
    return c >= 0 ? spm_spectrum_mean(&sc->colours[c].s) : 0.0;
}

/* ---- material types -------------------------------------------------------- */

/* A conductor (a metal): eta + i k per wavelength, smooth or GGX-rough of
 * width alpha (Mitsuba 3's alpha); its lobe draws the visible normal from
 * SPM_DIM_TYPE(j, SPM_DIM_COND_M_A/B). Russian roulette survives with its
 * scalar albedo: the mean over the 1 nm bins of its normal-incidence
 * reflectance F(eta, k, 1) = ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2). */
double spm_conductor_fresnel(double eta, double k, double c)
{
    /* the exact Fresnel reflectance of a conductor, unpolarised, from real
     * arithmetic: s2 = 1 - c^2, t0 = eta^2 - k^2 - s2, a2b2 = |n^2 - s2| =
     * sqrt(t0^2 + 4 eta^2 k^2), a = sqrt((a2b2 + t0) / 2);
     * Rs = (a2b2 + c^2 - 2 a c) / (a2b2 + c^2 + 2 a c),
     * Rp = Rs (c^2 a2b2 + s2^2 - 2 a c s2) / (c^2 a2b2 + s2^2 + 2 a c s2) */
    double s2 = 1.0 - c * c, t0 = eta * eta - k * k - s2;
    double a2b2 = sqrt(t0 * t0 + 4.0 * eta * eta * k * k);
    double a = sqrt(fmax(0.5 * (a2b2 + t0), 0.0));
    double t1 = a2b2 + c * c, t2 = 2.0 * a * c;
    double rs = (t1 - t2) / fmax(t1 + t2, 1e-300);
    double t3 = c * c * a2b2 + s2 * s2, t4 = t2 * s2;
    double rp = rs * (t3 - t4) / fmax(t3 + t4, 1e-300);
    return 0.5 * (rs + rp);
}

static void conductor_fill(const spm_scene *sc, const spm_scene_material *s, spm_material *d)
{
    double mean = 0.0;
    if (s->refl >= 0 && s->col2 >= 0) {
        const double *eta = sc->colours[s->refl].s.nm1, *k = sc->colours[s->col2].s.nm1;
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            mean += spm_conductor_fresnel(eta[i], k[i], 1.0);
        mean /= SPM_TRUTH_BINS;
    }
    d->mean = (float)mean;
    d->inv_mean = mean > 0.0 ? (float)(1.0 / mean) : 0.0f;
    /* widths below SPM_COND_MIN_ALPHA render as the smooth lobe (alpha 0) */
    d->p[SPM_COND_P_ALPHA] = s->p[SPM_COND_P_ALPHA] < SPM_COND_MIN_ALPHA
                                 ? 0.0f
                                 : (float)s->p[SPM_COND_P_ALPHA];
}

/* Fluorescent (Wilkie et al. 2006, fluor.h): diffuse, its reflection a
 * re-radiation matrix. The vertex records the diagonal colour D = SPEC (1 -
 * A) the scene derives for it (last among the colours, so the shade stage
 * knows it by its id); the matrix's fluorescent part lives in the shade
 * tables. Russian roulette survives with the mean column sum (the albedo to
 * equal-energy light), so a dye whose diagonal is black still carries paths. */
static void fluor_fill(const spm_scene *sc, const spm_scene_material *s, spm_material *d)
{
    double mean = spm_fluor_albedo(sc, s);
    d->refl = s->diag >= 0 ? (spm_u32)s->diag : SPM_NONE;
    d->col2 = SPM_NONE; /* the absorption enters through the matrix alone */
    d->mean = (float)mean;
    d->inv_mean = mean > 0.0 ? (float)(1.0 / mean) : 0.0f;
    d->p[0] = (float)s->p[SPM_FLUOR_P_YIELD];
}

static int fluor_derive(spm_scene *sc, spm_scene_material *s, spm_error *err)
{
    (void)err;
    sc->colours = spm_xrealloc(sc->colours, ((size_t)sc->ncolours + 2) * sizeof *sc->colours);
    spm_colour *c = &sc->colours[sc->ncolours];
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "%.50s:diagonal", s->name);
    spm_fluor_diagonal(sc, s, &c->s);
    s->diag = sc->ncolours++;
    return 0;
}

/* A dielectric (glass) of one index, smooth or GGX-rough (alpha, sampled by
 * visible normals as the conductor's), absorbing inside by Beer-Lambert:
 * transmittance exp(-sigma d) over a length d inside, sigma = DENSITY SPEC
 * per scene unit ('absorb SPEC DENSITY', an optical colour: the scale is the
 * density). Its vertex records sigma as its colour, so clear glass derives a
 * zero one. Fresnel with one index is the same at every wavelength, so the
 * reflect/refract choice and the weights are scalar (kernels/dielectric.clh).
 * Russian roulette: the interface's scalar albedo, R + T = 1, so a glass
 * vertex always survives (absorption is spectral and left to the shade
 * stage; the record's depth bounds a path trapped by total internal
 * reflection). */
static void dielectric_fill(const spm_scene *sc, const spm_scene_material *s, spm_material *d)
{
    (void)sc;
    d->refl = s->col2 >= 0 ? (spm_u32)s->col2 : SPM_NONE;
    d->col2 = SPM_NONE;
    d->mean = 1.0f;
    d->inv_mean = 1.0f;
    d->p[SPM_DIEL_P_IOR] = (float)s->p[SPM_DIEL_P_IOR];
    d->p[SPM_DIEL_P_DISP] = (float)s->p[SPM_DIEL_P_DISP];
    d->p[SPM_DIEL_P_ALPHA] = s->p[SPM_DIEL_P_ALPHA] < SPM_COND_MIN_ALPHA
                                 ? 0.0f
                                 : (float)s->p[SPM_DIEL_P_ALPHA];
}

/* The longest straight segment inside the scene's objects of material m:
 * the diagonal of its triangles' bounding box (a segment inside an object
 * lies in its box), for the absorption's pretest. */
static double dielectric_length(const spm_scene *sc, int m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < sc->ntris; i++)
        for (int v = 0; sc->tris[i].material == m && v < 3; v++)
            for (int k = 0; k < 3; k++) {
                lo[k] = fmin(lo[k], sc->tris[i].p[v][k]);
                hi[k] = fmax(hi[k], sc->tris[i].p[v][k]);
            }
    double d2 = 0.0;
    for (int k = 0; k < 3; k++)
        d2 += hi[k] >= lo[k] ? (hi[k] - lo[k]) * (hi[k] - lo[k]) : 0.0;
    return sqrt(d2);
}

/* A dispersive glass (an index table, SPM_DIEL_P_DISP) refuses fluorescent
 * materials in its scene: their light-end walk carries every lane, and a
 * committed path has one (docs/METHODS.md "Dispersion"). */
static int dielectric_derive(spm_scene *sc, spm_scene_material *s, spm_error *err)
{
    /* an index is a required clause: the parser has checked it */
    for (int i = 0; s->p[SPM_DIEL_P_DISP] > 0.0 && i < sc->nmaterials; i++)
        if (sc->materials[i].type == (int)SPM_MAT_FLUOR ||
            sc->materials[i].type == (int)SPM_MAT_DONALDSON) {
            spm_errorf(err, "material '%s' (dispersive dielectric) and material '%s' "
                            "(fluorescent): a scene cannot have both yet",
                       s->name, sc->materials[i].name);
            return 1;
        }
    s->p[SPM_DIEL_P_LEN] = dielectric_length(sc, (int)(s - sc->materials));
    if (s->col2 >= 0)
        return 0;
    sc->colours = spm_xrealloc(sc->colours, ((size_t)sc->ncolours + 2) * sizeof *sc->colours);
    spm_colour *c = &sc->colours[sc->ncolours];
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "%.50s:clear", s->name);
    spm_spectrum_constant(0.0, SPM_KIND_REFLECTANCE, &c->s);
    s->col2 = sc->ncolours++;
    return 0;
}

/* A type whose derived colour would follow a fluorescent material's diagonal
 * refuses fluorescent materials in its scene: their diagonals must be the
 * scene's last colours (the shade stage knows them by id), and their
 * light-end walk has no case for its vertices. */
static int refuse_fluor(const spm_scene *sc, const spm_scene_material *s, const char *type,
                        spm_error *err)
{
    for (int i = 0; i < sc->nmaterials; i++)
        if (sc->materials[i].type == (int)SPM_MAT_FLUOR ||
            sc->materials[i].type == (int)SPM_MAT_DONALDSON) {
            spm_errorf(err, "material '%s' (%s) and material '%s' (fluorescent): a scene "
                            "cannot have both types yet", s->name, type, sc->materials[i].name);
            return 1;
        }
    return 0;
}

/* Coated (coated.h): a Lambertian base under a smooth or GGX-rough dielectric
 * coating, Mitsuba 3's plastic / roughplastic with nonlinear true. The vertex
 * records the derived colour D (col3, the diffuse lobe) or the derived white
 * (col2, the specular lobe); Fresnel, GGX and the lobe choice are scalars of
 * the trace stage (kernels/coated.clh). p[]: alpha, eta, the diffuse factor
 * 1 / (eta^2 (1 - Fdr_i)) and the specular lobe's sampling weight, Mitsuba's
 * 1 / (1 + mean R). mean: D's mean over the 1 nm bins, the diffuse lobe's
 * colour in Russian roulette's scalar albedo (kernels/coated.clh). */
static double coat_eta(const spm_scene_material *s)
{
    return s->p[SPM_COAT_P_ETA] > 0.0 ? s->p[SPM_COAT_P_ETA] : SPM_COAT_DEFAULT_ETA;
}

static void coated_fill(const spm_scene *sc, const spm_scene_material *s, spm_material *d)
{
    double eta = coat_eta(s), fdr = spm_coat_fdr_internal(eta);
    double mean = colour_mean(sc, s->col3);
    d->refl = s->col3 >= 0 ? (spm_u32)s->col3 : SPM_NONE;
    d->col2 = s->col2 >= 0 ? (spm_u32)s->col2 : SPM_NONE;
    d->mean = (float)mean;
    d->inv_mean = mean > 0.0 ? (float)(1.0 / mean) : 0.0f;
    d->p[SPM_COAT_P_ALPHA] = s->p[SPM_COAT_P_ALPHA] < SPM_COND_MIN_ALPHA
                                 ? 0.0f
                                 : (float)s->p[SPM_COAT_P_ALPHA];
    d->p[SPM_COAT_P_ETA] = (float)eta;
    d->p[SPM_COAT_P_KD] = (float)(1.0 / (eta * eta * (1.0 - fdr)));
    d->p[SPM_COAT_P_SPEC] = (float)(1.0 / (1.0 + colour_mean(sc, s->refl)));
}

/* A palette derived from the scene's first (scene.h palette), for a type
 * whose vertex records a colour made from its reflectance: each node's
 * colour c becomes a new scene colour f(c, arg) named after `name`. Its
 * index among the palettes, with *best the new colour of the largest mean
 * (the material's colour for Russian roulette's survival). */
static int palette_derive(spm_scene *s, const char *name,
                          void (*f)(const spm_spectrum *in, double arg, spm_spectrum *out),
                          double arg, int *best)
{
    const size_t n = SPM_TEX_NODES_ALL;
    int k = s->npalettes++, used = 0;
    s->palette = spm_xrealloc(s->palette, (size_t)s->npalettes * n * sizeof *s->palette);
    int *to = s->palette + (size_t)k * n;
    for (size_t i = 0; i < n; i++)
        used += s->palette[i] >= 0;
    s->colours = spm_xrealloc(s->colours, ((size_t)s->ncolours + (size_t)used) * sizeof *s->colours);
    double best_mean = -1.0;
    *best = -1;
    for (size_t i = 0; i < n; i++) {
        to[i] = -1;
        if (s->palette[i] < 0)
            continue;
        spm_colour *c = &s->colours[s->ncolours];
        memset(c, 0, sizeof *c);
        snprintf(c->name, sizeof c->name, "%.40s:tex%zu", name, i);
        f(&s->colours[s->palette[i]].s, arg, &c->s);
        to[i] = s->ncolours++;
        double mean = spm_spectrum_mean(&c->s);
        if (mean > best_mean)
            best_mean = mean, *best = to[i];
    }
    return k;
}

/* D into col3 (a new colour per material) and the white the specular lobe
 * records into col2 (one for the scene, shared). A textured base gets a
 * palette of D, one per colour of the lifted grid, and col3 its D of the
 * largest mean (Russian roulette's bound). A scene with fluorescent
 * materials is refused: their diagonal colours must be the scene's last (the
 * shade stage knows them by id), and their light-end walk has no case for
 * the coated vertex's hit. */
static int coated_derive(spm_scene *sc, spm_scene_material *s, spm_error *err)
{
    if (refuse_fluor(sc, s, "coated", err))
        return 1;
    static const char white_name[] = "coated:white";
    int white = -1;
    for (int i = 0; i < sc->ncolours && white < 0; i++)
        if (!strcmp(sc->colours[i].name, white_name))
            white = i;
    sc->colours = spm_xrealloc(sc->colours, ((size_t)sc->ncolours + 2) * sizeof *sc->colours);
    spm_colour *c = &sc->colours[sc->ncolours];
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "%.50s:effective", s->name);
    spm_coat_effective(s->refl >= 0 ? &sc->colours[s->refl].s : NULL,
                       spm_coat_fdr_internal(coat_eta(s)), &c->s);
    s->col3 = sc->ncolours++;
    if (white < 0) {
        c = &sc->colours[sc->ncolours];
        memset(c, 0, sizeof *c);
        snprintf(c->name, sizeof c->name, "%s", white_name);
        spm_spectrum_constant(1.0, SPM_KIND_REFLECTANCE, &c->s);
        white = sc->ncolours++;
    }
    s->col2 = white;
    if (s->tex) /* a textured base: D of each colour its texels pick */
        s->tpal = palette_derive(sc, s->name, spm_coat_effective, spm_coat_fdr_internal(coat_eta(s)),
                                 &s->col3);
    return 0;
}

/* The types' own host code, written in their entries (SPM_TYPE_HOST_CODE):
 * the functions their descriptors name, which may use the helpers above. */
#define SPM_TYPE_HOST_CODE
#define SPM_MATERIAL_TYPE(name, ...)
#define SPM_EMITTER_TYPE(name, ...)
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
#undef SPM_EMITTER_TYPE
#undef SPM_TYPE_HOST_CODE

/* The descriptors: spm_types.h's entries, each at its tag. */
#define SPM_MATERIAL_TYPE(name, ...) [SPM_MAT_##name] = {.tag = SPM_MAT_##name, __VA_ARGS__},
#define SPM_EMITTER_TYPE(name, ...)
const spm_mtype_desc spm_material_types[] = {
#include "spm_types.h"
};
#undef SPM_MATERIAL_TYPE
#undef SPM_EMITTER_TYPE
const int spm_nmaterial_types = (int)(sizeof spm_material_types / sizeof spm_material_types[0]);

/* ---- emitter types --------------------------------------------------------- */

/* An area light: the triangle emits its colour from its front face, or with
 * 'twosided' (pbrt-v4's) from both. */
static void area_fill(const spm_scene *sc, const spm_scene_material *s, spm_material *d)
{
    (void)sc;
    if (s->flags & 1u << SPM_AREA_FLAG_TWOSIDED)
        d->type |= SPM_EMIT_TWOSIDED;
}

#define SPM_MATERIAL_TYPE(name, ...)
#define SPM_EMITTER_TYPE(name, ...) [SPM_EMIT_##name] = {.tag = SPM_EMIT_##name, __VA_ARGS__},
const spm_mtype_desc spm_emitter_types[] = {
#include "spm_types.h"
};
#undef SPM_MATERIAL_TYPE
#undef SPM_EMITTER_TYPE
const int spm_nemitter_types = (int)(sizeof spm_emitter_types / sizeof spm_emitter_types[0]);

_Static_assert(sizeof spm_material_types / sizeof spm_material_types[0] <= SPM_MAT_TYPES,
               "more material types than SPM_MAT_TYPES");
_Static_assert(sizeof spm_emitter_types / sizeof spm_emitter_types[0] <= SPM_EMIT_TYPES,
               "more emitter types than SPM_EMIT_TYPES");

int spm_material_faces(const spm_scene_material *s)
{
    return s->etype == SPM_EMIT_AREA && (s->flags & 1u << SPM_AREA_FLAG_TWOSIDED) ? 2 : 1;
}

const spm_mtype_desc *spm_material_type_find(const char *kw)
{
    for (int i = 0; i < spm_nmaterial_types; i++)
        if (spm_material_types[i].keyword && !strcmp(spm_material_types[i].keyword, kw))
            return &spm_material_types[i];
    return NULL;
}

const spm_mtype_desc *spm_material_type_default(void)
{
    return &spm_material_types[SPM_MAT_LAMBERT];
}

/* A type without a fill of its own (Lambertian): its numbers into p[slot];
 * Russian roulette survives with q, the largest mean of its reflectance
 * colours, and weighs 1 / q. Whichever of them a vertex records, survival
 * times weight is 1, so any choice among them stays unbiased, and q > 0
 * whenever one of them is not black. */
static void generic_fill(const spm_mtype_desc *t, const spm_scene *sc,
                         const spm_scene_material *s, spm_material *d)
{
    double mean = 0.0;
    int any = 0;
    for (int i = 0; i < t->nparams; i++) {
        const spm_mparam *q = &t->params[i];
        if (q->kind == SPM_MP_NUMBER)
            d->p[q->slot] = (float)s->p[q->slot];
        else if (q->kind == SPM_MP_EMIT_NUMBER)
            d->ep[q->slot] = (float)s->ep[q->slot];
        else if (q->kind == SPM_MP_REFLECTANCE) {
            double m = colour_mean(sc, q->slot == SPM_MSLOT_REFL   ? s->refl
                                       : q->slot == SPM_MSLOT_COL2 ? s->col2
                                                                   : s->col3);
            mean = fmax(mean, m); /* colour means are >= 0 */
            any = 1;
        }
    }
    if (any) {
        d->mean = (float)mean;
        d->inv_mean = mean > 0.0 ? (float)(1.0 / mean) : 0.0f;
    }
}

void spm_material_fill(const spm_scene *sc, const spm_scene_material *s, spm_material *d)
{
    memset(d, 0, sizeof *d);
    d->refl = s->refl >= 0 ? (spm_u32)s->refl : SPM_NONE;
    d->emit = s->emit >= 0 ? (spm_u32)s->emit : SPM_NONE;
    d->col2 = s->col2 >= 0 ? (spm_u32)s->col2 : SPM_NONE;
    d->type = (spm_u32)s->type | (spm_u32)s->etype << 16;
    const spm_mtype_desc *mt = &spm_material_types[s->type], *et = &spm_emitter_types[s->etype];
    if (mt->fill)
        mt->fill(sc, s, d);
    else
        generic_fill(mt, sc, s, d);
    if (et->fill)
        et->fill(sc, s, d);
    else
        generic_fill(et, sc, s, d);
}

void spm_material_types_used(const spm_material *mats, int n, int used_m[SPM_MAT_TYPES],
                             int used_e[SPM_EMIT_TYPES])
{
    memset(used_m, 0, SPM_MAT_TYPES * sizeof *used_m);
    memset(used_e, 0, SPM_EMIT_TYPES * sizeof *used_e);
    for (int i = 0; i < n; i++) {
        spm_u32 mt = SPM_MAT_TAG(mats[i]), et = SPM_EMIT_TAG(mats[i]);
        if (mt < SPM_MAT_TYPES)
            used_m[mt] = 1;
        if (et < SPM_EMIT_TYPES && mats[i].emit != SPM_NONE)
            used_e[et] = 1;
    }
}

int spm_material_defines(const spm_material *mats, int n, char *buf, size_t size)
{
    int um[SPM_MAT_TYPES], ue[SPM_EMIT_TYPES], len = 0;
    spm_material_types_used(mats, n, um, ue);
    buf[0] = '\0';
    for (int i = 0; i < spm_nmaterial_types; i++)
        if (um[i] && len < (int)size)
            len += snprintf(buf + len, size - (size_t)len, "-D%s ", spm_material_types[i].define);
    for (int i = 0; i < spm_nemitter_types; i++)
        if (ue[i] && len < (int)size)
            len += snprintf(buf + len, size - (size_t)len, "-D%s ", spm_emitter_types[i].define);
    return len;
}

size_t spm_material_vertex_bytes(const spm_material *mats, int n)
{
    int um[SPM_MAT_TYPES], ue[SPM_EMIT_TYPES];
    spm_material_types_used(mats, n, um, ue);
    /* the types that declare words share one record (spm_vertex_ext, its kind
     * bit telling them apart): the widest's */
    size_t words = 0;
    for (int i = 0; i < spm_nmaterial_types; i++)
        if (um[i] && (size_t)spm_material_types[i].vertex_u32 > words)
            words = (size_t)spm_material_types[i].vertex_u32;
    for (int i = 0; i < spm_nemitter_types; i++)
        if (ue[i] && (size_t)spm_emitter_types[i].vertex_u32 > words)
            words = (size_t)spm_emitter_types[i].vertex_u32;
    return sizeof(spm_vertex) + 4 * words;
}
