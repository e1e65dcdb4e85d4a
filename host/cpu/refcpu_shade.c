/* CPU reference, shade stage: every mode evaluates the same path record with
 * the formula of spm_path_head's comment over a set of spectral "lanes"
 * (bins, 1 nm bins, spike lanes, RGB channels or hero wavelengths), then
 * turns the lanes into XYZ with per-lane weights. Plain scalar float loops. */
#include "refcpu.h"
#include "spm_rng.h"

#define MAX_LANES SPM_TRUTH_BINS

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

/* A shade table (modes.h) as lanes: its rows and weight rows (none in a
 * mode that draws its lanes per path). */
static lanes table_lanes(const spm_shade_table *tab)
{
    lanes v = {tab->rows, (size_t)tab->stride, tab->lanes, NULL, {NULL, NULL, NULL}};
    for (int ch = 0; tab->w && ch < 3; ch++)
        v.w[ch] = tab->w + (size_t)ch * (size_t)tab->stride;
    return v;
}

/* Per-path lanes: the bins they read and their weights. */
typedef struct {
    int idx[SPM_HERO_LANES];
    float w[3][SPM_HERO_LANES];
} path_lanes;

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
static lanes hero_path(const spm_shade_table *tab, float u, path_lanes *pl)
{
    const float *cdf = tab->extra + SPM_HERO_CDF, *pdfs = tab->extra + SPM_HERO_PDF;
    for (int i = 0; i < SPM_HERO_LANES; i++) {
        float xi = u + (float)i / (float)SPM_HERO_LANES;
        if (xi >= 1.0f)
            xi -= 1.0f;
        int j = hero_bin(cdf, xi);
        float width = cdf[j + 1] - cdf[j];
        float f = width > 0.0f ? (xi - cdf[j]) / width : 0.0f;
        f = f < 0.0f ? 0.0f : (f > 1.0f ? 1.0f : f);
        float pdf = pdfs[j];
        pl->idx[i] = j / (SPM_TRUTH_BINS / SPM_L0_BINS);
        for (int ch = 0; ch < 3; ch++) {
            const float *cp = tab->extra + SPM_HERO_CMF + ch * (SPM_TRUTH_BINS + 1);
            float a = cp[j], b = cp[j + 1];
            float cmf = a + (b - a) * f;
            pl->w[ch][i] = pdf > 0.0f ? cmf / pdf / (float)SPM_HERO_LANES : 0.0f;
        }
    }
    return (lanes){tab->rows, (size_t)tab->stride, SPM_HERO_LANES, pl->idx,
                   {pl->w[0], pl->w[1], pl->w[2]}};
}

void spm_ref_shade_tables(const spm_mode_desc *m, const spm_shade_table *tabs,
                          const spm_trace_params *p, size_t first, const spm_path *paths,
                          const uint8_t *levels, size_t n, float *xyz)
{
    lanes lv[SPM_NUM_LEVELS];
    for (int s = 0; s < spm_mode_nslots(m); s++)
        lv[s] = table_lanes(&tabs[s]);
    float L[MAX_LANES];
    path_lanes pl;
    for (size_t i = 0; i < n; i++) {
        lanes v = lv[spm_mode_slot(m, levels[i])];
        if (m->per_path) {
            spm_u32 pixel, sample;
            spm_ref_path_key(p, first + i, &pixel, &sample);
            v = hero_path(&tabs[0], spm_rng(p->seed, pixel, sample, SPM_DIM_HERO), &pl);
        }
        shade_lanes(&paths[i], &v, L);
        lanes_to_xyz(&v, L, &xyz[3 * i]);
    }
}

void spm_ref_shade(const spm_tables *t, int mode, const spm_trace_params *p, size_t first,
                   const spm_path *paths, const uint8_t *levels, size_t n, float *xyz)
{
    const spm_mode_desc *m = spm_mode(mode);
    spm_shade_table tabs[SPM_NUM_LEVELS];
    for (int s = 0; s < spm_mode_nslots(m); s++)
        spm_shade_table_build(m, t, s, &tabs[s]);
    spm_ref_shade_tables(m, tabs, p, first, paths, levels, n, xyz);
    for (int s = 0; s < spm_mode_nslots(m); s++)
        spm_shade_table_free(&tabs[s]);
}
