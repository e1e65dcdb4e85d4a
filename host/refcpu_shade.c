/* CPU reference, shade stage: every mode evaluates the same path record with
 * the formula of spm_path_head's comment over a set of spectral "lanes"
 * (bins, 1 nm bins, spike lanes, RGB channels or hero wavelengths), then
 * turns the lanes into XYZ with per-lane weights. Plain scalar float loops. */
#include "refcpu.h"
#include "colour.h"
#include "spm_rng.h"

#define MAX_LANES SPM_TRUTH_BINS
#define MLC_LANES (SPM_L0_BINS + SPM_MAX_SPIKES)

/* Colour c's lane l is base[c * stride + (idx ? idx[l] : l)]; XYZ channel ch
 * of the lanes is sum over l of lane l * w[ch][l]. */
typedef struct {
    const float *base;
    size_t stride;
    int n;
    const int *idx;
    const float *w[3];
} lanes;

static void fetch(const lanes *v, spm_u32 c, float *out)
{
    const float *row = v->base + (size_t)c * v->stride;
    for (int l = 0; l < v->n; l++)
        out[l] = row[v->idx ? v->idx[l] : l];
}

/* P = 1; L = first_emit_c E[first]; per vertex P *= R, L += P E c; then the
 * background. A black vertex (no reflectance colour) ends every later term. */
static void shade_lanes(const spm_path *path, const lanes *v, float *L)
{
    float P[MAX_LANES], X[MAX_LANES];
    const spm_path_head *h = &path->h;
    for (int l = 0; l < v->n; l++)
        L[l] = 0.0f, P[l] = 1.0f;
    if (h->first_emit != SPM_NONE) {
        fetch(v, h->first_emit, X);
        for (int l = 0; l < v->n; l++)
            L[l] = h->first_emit_c * X[l];
    }
    for (spm_u32 j = 0; j < h->nvert; j++) {
        spm_u32 r = path->v[j].ids & 0xFFFFu, e = path->v[j].ids >> 16;
        if (r == SPM_NONE)
            return;
        fetch(v, r, X);
        for (int l = 0; l < v->n; l++)
            P[l] *= X[l];
        if (e != SPM_NONE) {
            fetch(v, e, X);
            for (int l = 0; l < v->n; l++)
                L[l] += P[l] * X[l] * path->v[j].c;
        }
    }
    if (h->bg != SPM_NONE) {
        fetch(v, h->bg, X);
        for (int l = 0; l < v->n; l++)
            L[l] += P[l] * X[l] * h->bg_c;
    }
}

static void lanes_to_xyz(const lanes *v, const float *L, float xyz[3])
{
    for (int ch = 0; ch < 3; ch++) {
        float s = 0.0f;
        for (int l = 0; l < v->n; l++)
            s += L[l] * v->w[ch][l];
        xyz[ch] = s;
    }
}

/* Per-call state: the lane layout of each level for the mode, and the weight
 * tables that are not stored in spm_tables as such. */
typedef struct {
    lanes lv[SPM_NUM_LEVELS];
    float mlc_w[SPM_NUM_LEVELS][3][MLC_LANES];
    float rgb_w[3][3];
    int hero_idx[SPM_HERO_LANES];
    float hero_w[3][SPM_HERO_LANES];
} shade_setup;

static void setup_levels(const spm_tables *t, shade_setup *s)
{
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        int nb = SPM_LEVEL_BINS(l);
        s->lv[l] = (lanes){t->lvl[l], (size_t)nb, nb, NULL,
                           {t->cmf_lvl[l][0], t->cmf_lvl[l][1], t->cmf_lvl[l][2]}};
    }
}

/* Composite Model: smooth bins, then the scene's spike lanes weighted by the
 * CMFs at the spike wavelengths. */
static void setup_mlc(const spm_tables *t, shade_setup *s)
{
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        int nb = SPM_LEVEL_BINS(l);
        for (int ch = 0; ch < 3; ch++) {
            for (int b = 0; b < nb; b++)
                s->mlc_w[l][ch][b] = t->cmf_lvl[l][ch][b];
            for (int k = 0; k < t->nspikes; k++)
                s->mlc_w[l][ch][nb + k] = t->spike_cmf[ch][k];
        }
        s->lv[l] = (lanes){t->mlc_lvl[l], (size_t)(nb + SPM_MAX_SPIKES), nb + t->nspikes, NULL,
                           {s->mlc_w[l][0], s->mlc_w[l][1], s->mlc_w[l][2]}};
    }
}

static void setup_truth(const spm_tables *t, shade_setup *s)
{
    s->lv[0] = (lanes){t->truth, SPM_TRUTH_BINS, SPM_TRUTH_BINS, NULL,
                       {t->cmf_truth[0], t->cmf_truth[1], t->cmf_truth[2]}};
}

/* rgb: XYZ = M rgb with M the sRGB-to-XYZ matrix, read off colour.h's
 * conversion of the unit vectors. */
static void setup_rgb(const spm_tables *t, shade_setup *s)
{
    for (int i = 0; i < 3; i++) {
        double e[3] = {0.0, 0.0, 0.0}, xyz[3];
        e[i] = 1.0;
        spm_linear_srgb_to_xyz(e, xyz);
        for (int ch = 0; ch < 3; ch++)
            s->rgb_w[ch][i] = (float)xyz[ch];
    }
    s->lv[0] = (lanes){t->rgb, 4, 3, NULL, {s->rgb_w[0], s->rgb_w[1], s->rgb_w[2]}};
}

/* The 1 nm bin j holding sample-space position xi: cdf[j] <= xi < cdf[j + 1]. */
static int hero_bin(const float *cdf, float xi)
{
    int lo = 0, hi = SPM_TRUTH_BINS;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (cdf[mid] <= xi)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Hero wavelengths of one path: lane i at xi = frac(u + i/4) mapped through
 * the inverse of the piecewise-linear cdf; spectra from the level-0 bin
 * holding it (piecewise constant), CMF interpolated linearly, each lane
 * divided by its density and by the lane count. */
static void setup_hero_path(const spm_tables *t, float u, shade_setup *s)
{
    for (int i = 0; i < SPM_HERO_LANES; i++) {
        float xi = u + (float)i / (float)SPM_HERO_LANES;
        if (xi >= 1.0f)
            xi -= 1.0f;
        int j = hero_bin(t->hero_cdf, xi);
        float width = t->hero_cdf[j + 1] - t->hero_cdf[j];
        float f = width > 0.0f ? (xi - t->hero_cdf[j]) / width : 0.0f;
        f = f < 0.0f ? 0.0f : (f > 1.0f ? 1.0f : f);
        float pdf = t->hero_pdf[j];
        s->hero_idx[i] = j / (SPM_TRUTH_BINS / SPM_L0_BINS);
        for (int ch = 0; ch < 3; ch++) {
            float a = t->cmf_point[ch][j], b = t->cmf_point[ch][j + 1];
            float cmf = a + (b - a) * f;
            s->hero_w[ch][i] = pdf > 0.0f ? cmf / pdf / (float)SPM_HERO_LANES : 0.0f;
        }
    }
    s->lv[0] = (lanes){t->lvl[0], SPM_L0_BINS, SPM_HERO_LANES, s->hero_idx,
                       {s->hero_w[0], s->hero_w[1], s->hero_w[2]}};
}

static int path_level(int mode, const uint8_t *levels, size_t i)
{
    if (mode != SPM_MODE_ML && mode != SPM_MODE_MLC)
        return 0;
    int l = (int)(levels[i] & SPM_LEVEL_MASK);
    return l < SPM_NUM_LEVELS ? l : SPM_NUM_LEVELS - 1;
}

void spm_ref_shade(const spm_tables *t, int mode, const spm_trace_params *p, size_t first,
                   const spm_path *paths, const uint8_t *levels, size_t n, float *xyz)
{
    shade_setup s;
    switch (mode) {
    case SPM_MODE_TRUTH: setup_truth(t, &s); break;
    case SPM_MODE_MLC: setup_mlc(t, &s); break;
    case SPM_MODE_RGB: setup_rgb(t, &s); break;
    default: setup_levels(t, &s); break;
    }
    float L[MAX_LANES];
    for (size_t i = 0; i < n; i++) {
        if (mode == SPM_MODE_HERO) {
            spm_u32 pixel, sample;
            spm_ref_path_key(p, first + i, &pixel, &sample);
            setup_hero_path(t, spm_rng(p->seed, pixel, sample, SPM_DIM_HERO), &s);
        }
        const lanes *v = &s.lv[path_level(mode, levels, i)];
        shade_lanes(&paths[i], v, L);
        lanes_to_xyz(v, L, &xyz[3 * i]);
    }
}
