/* Test helpers: small scenes built in memory (flat spectra), hand-made
 * spectral tables whose Y is the mean of a spectrum, and a tiny RNG. */
#ifndef GEOMTEST_SCENE_H
#define GEOMTEST_SCENE_H
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "refcpu.h"

#define TS_MAX 64

static inline void ts_init(spm_scene *s)
{
    memset(s, 0, sizeof *s);
    strcpy(s->path, "<test>");
    s->eye[2] = -1.0f;
    s->dir[2] = 1.0f;
    s->fov_deg = 45.0f;
    s->width = s->height = 4;
    s->colours = calloc(TS_MAX, sizeof *s->colours);
    s->materials = calloc(TS_MAX, sizeof *s->materials);
    s->tris = calloc(16384, sizeof *s->tris);
    s->bg_up = s->bg_down = -1;
}

static inline void ts_free(spm_scene *s)
{
    free(s->colours);
    free(s->materials);
    free(s->tris);
}

/* A spectrum of one value at every wavelength. */
static inline int ts_colour(spm_scene *s, spm_kind kind, double value)
{
    spm_colour *c = &s->colours[s->ncolours];
    snprintf(c->name, sizeof c->name, "c%d", s->ncolours);
    c->s.kind = kind;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        c->s.nm1[i] = value;
    return s->ncolours++;
}

static inline int ts_material(spm_scene *s, int refl, int emit)
{
    spm_scene_material *m = &s->materials[s->nmaterials];
    snprintf(m->name, sizeof m->name, "m%d", s->nmaterials);
    m->refl = refl;
    m->emit = emit;
    m->col2 = -1;
    return s->nmaterials++;
}

static inline void ts_tri(spm_scene *s, int m, const float a[3], const float b[3], const float c[3])
{
    spm_scene_tri *t = &s->tris[s->ntris];
    memcpy(t->p[0], a, sizeof t->p[0]);
    memcpy(t->p[1], b, sizeof t->p[1]);
    memcpy(t->p[2], c, sizeof t->p[2]);
    t->material = m;
    t->line = 100 + s->ntris; /* a made-up source line, checked by error messages */
    s->ntris++;
}

/* Quad a b c d (counter-clockwise seen from its front) as two triangles. */
static inline void ts_quad(spm_scene *s, int m, const float a[3], const float b[3], const float c[3],
                    const float d[3])
{
    ts_tri(s, m, a, b, c);
    ts_tri(s, m, a, c, d);
}

/* Axis-aligned box [lo, hi] with normals pointing inward (walls seen from
 * inside are front faces); `skip_top` leaves the +y side open. */
static inline void ts_box(spm_scene *s, int m, const float lo[3], const float hi[3], int skip_top)
{
    float v[8][3];
    for (int i = 0; i < 8; i++) {
        v[i][0] = (i & 1) ? hi[0] : lo[0];
        v[i][1] = (i & 2) ? hi[1] : lo[1];
        v[i][2] = (i & 4) ? hi[2] : lo[2];
    }
    ts_quad(s, m, v[0], v[4], v[5], v[1]); /* floor y = lo, normal +y */
    if (!skip_top)
        ts_quad(s, m, v[2], v[3], v[7], v[6]); /* ceiling, normal -y */
    ts_quad(s, m, v[0], v[2], v[6], v[4]); /* x = lo, normal +x */
    ts_quad(s, m, v[1], v[5], v[7], v[3]); /* x = hi, normal -x */
    ts_quad(s, m, v[0], v[1], v[3], v[2]); /* z = lo, normal +z */
    ts_quad(s, m, v[4], v[6], v[7], v[5]); /* z = hi, normal -z */
}

/* A closed UV sphere of 2 segs (rings - 1) triangles: vertex (ring i,
 * segment j) at centre + r (sin th cos ph, cos th, sin th sin ph), th = pi i /
 * rings, ph = 2 pi j / segs, computed once and shared by every triangle that
 * has it (so are the poles); a ring's quads are planar, the mesh convex. */
static inline void ts_sphere(spm_scene *s, int m, const double c[3], double r, int rings, int segs)
{
    float(*v)[3] = malloc(sizeof *v * (size_t)(rings + 1) * (size_t)segs);
#define TS_V(i, j) v[(size_t)(i) * (size_t)segs + (size_t)(j)]
    for (int i = 0; i <= rings; i++)
        for (int j = 0; j < segs; j++) {
            double th = M_PI * i / rings, ph = 2.0 * M_PI * j / segs;
            double p[3] = {c[0] + r * sin(th) * cos(ph), c[1] + r * cos(th),
                           c[2] + r * sin(th) * sin(ph)};
            for (int k = 0; k < 3; k++)
                TS_V(i, j)[k] = (float)(i == 0 || i == rings ? c[k] + (k == 1 ? (i ? -r : r) : 0.0)
                                                             : p[k]);
        }
    for (int j = 0; j < segs; j++) {
        int k = (j + 1) % segs;
        ts_tri(s, m, TS_V(0, 0), TS_V(1, k), TS_V(1, j));
        for (int i = 1; i < rings - 1; i++) {
            ts_tri(s, m, TS_V(i, j), TS_V(i, k), TS_V(i + 1, k));
            ts_tri(s, m, TS_V(i, j), TS_V(i + 1, k), TS_V(i + 1, j));
        }
        ts_tri(s, m, TS_V(rings - 1, j), TS_V(rings - 1, k), TS_V(rings, 0));
    }
#undef TS_V
    free(v);
}

/* Tables for flat spectra: every representation holds the colour's value,
 * Y weights are uniform (so Y = the spectrum's mean), X = Z = 0. lvlk = 0. */
static inline void ts_tables(const spm_scene *s, spm_tables *t)
{
    memset(t, 0, sizeof *t);
    int n = s->ncolours;
    t->ncolours = n;
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        int nb = SPM_LEVEL_BINS(l);
        t->lvl[l] = calloc((size_t)n * nb + 1, sizeof(float));
        t->mlc_lvl[l] = calloc((size_t)n * (nb + SPM_MAX_SPIKES) + 1, sizeof(float));
        for (int c = 0; c < n; c++)
            for (int b = 0; b < nb; b++)
                t->lvl[l][c * nb + b] = t->mlc_lvl[l][c * (nb + SPM_MAX_SPIKES) + b] =
                    (float)s->colours[c].s.nm1[0];
        for (int b = 0; b < nb; b++)
            t->cmf_lvl[l][1][b] = 1.0f / (float)nb;
    }
    t->truth = calloc((size_t)n * SPM_TRUTH_BINS + 1, sizeof(float));
    t->rgb = calloc((size_t)n * 4 + 1, sizeof(float));
    for (int c = 0; c < n; c++) {
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            t->truth[c * SPM_TRUTH_BINS + i] = (float)s->colours[c].s.nm1[i];
        for (int i = 0; i < 3; i++)
            t->rgb[c * 4 + i] = (float)s->colours[c].s.nm1[0];
    }
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        t->cmf_truth[1][i] = 1.0f / SPM_TRUTH_BINS;
    spm_tables_fill_hero(t);
    t->lvlk = calloc((size_t)n * SPM_PRETEST_KMAX + 1, 1);
    t->mlc_lvlk = calloc((size_t)n * SPM_PRETEST_KMAX + 1, 1);
    t->bg_up = s->bg_up >= 0 ? (spm_u32)s->bg_up : SPM_NONE;
    t->bg_down = s->bg_down >= 0 ? (spm_u32)s->bg_down : SPM_NONE;
    t->nmaterials = s->nmaterials;
    t->materials = calloc((size_t)s->nmaterials + 1, sizeof *t->materials);
    for (int m = 0; m < s->nmaterials; m++) {
        int r = s->materials[m].refl, e = s->materials[m].emit;
        double mean = r >= 0 ? s->colours[r].s.nm1[0] : 0.0;
        t->materials[m] = (spm_material){r >= 0 ? (spm_u32)r : SPM_NONE,
                                         e >= 0 ? (spm_u32)e : SPM_NONE, (float)mean,
                                         mean > 0 ? (float)(1.0 / mean) : 0.0f,
                                         SPM_MAT_LAMBERT | SPM_EMIT_AREA << 16, SPM_NONE,
                                         {0, 0, 0, 0}, {0}};
    }
}


static inline spm_trace_params ts_params(const spm_scene *s, const spm_geometry *g, spm_u32 spp,
                                  spm_u32 seed)
{
    spm_trace_params p;
    memset(&p, 0, sizeof p);
    p.cam = g->cam;
    p.ntris = (spm_u32)g->ntris;
    p.nemitters = (spm_u32)g->nemitters;
    p.emit_power = (spm_u32)g->emit_power;
    p.bg_up = s->bg_up >= 0 ? (spm_u32)s->bg_up : SPM_NONE;
    p.bg_down = s->bg_down >= 0 ? (spm_u32)s->bg_down : SPM_NONE;
    p.seed = seed;
    p.spp_per_pass = spp;
    return p;
}


/* Path Y over every path of the image: mean, its standard error, extremes. */
typedef struct {
    double mean, sem, min, max;
    long n;
} ts_ystats;

/* Traces and shades (ref mode) every path of the scene's image on the CPU
 * reference over the built geometry g. */
static inline ts_ystats ts_ref_y(const spm_scene *s, const spm_geometry *g, spm_u32 spp,
                                 spm_u32 seed)
{
    ts_ystats st = {0, 0, INFINITY, -INFINITY, 0};
    spm_tables t;
    ts_tables(s, &t);
    spm_trace_params p = ts_params(s, g, spp, seed);
    size_t n = (size_t)s->width * s->height * spp;
    spm_path *paths = malloc(n * sizeof *paths);
    uint8_t *levels = malloc(n);
    float *xyz = malloc(3 * n * sizeof *xyz);
    spm_ref_trace(g, t.materials, t.lvlk, &p, paths, levels);
    spm_ref_shade(&t, SPM_MODE_REF, &p, 0, paths, levels, n, xyz);
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < n; i++) {
        double y = xyz[3 * i + 1];
        sum += y, sum2 += y * y;
        st.min = fmin(st.min, y), st.max = fmax(st.max, y);
    }
    st.n = (long)n;
    st.mean = sum / (double)n;
    st.sem = sqrt(fmax(0.0, sum2 / (double)n - st.mean * st.mean) / (double)(n - 1));
    free(paths), free(levels), free(xyz);
    spm_tables_free(&t);
    return st;
}

/* xorshift32 in [0, 1) for test inputs. */
static inline float ts_rand(unsigned *state)
{
    unsigned x = *state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *state = x;
    return (float)(x >> 8) * (1.0f / 16777216.0f);
}
#endif
