/* CPU reference, shade stage: every mode evaluates the same path record with
 * the formula of spm_path_head's comment over a set of spectral "lanes"
 * (bins, 1 nm bins, spike lanes, RGB channels or hero wavelengths), then
 * turns the lanes into XYZ with per-lane weights. Plain scalar float loops. */
#include "refcpu.h"
#include <math.h>
#include "spm_rng.h"
#include "refcpu_factors.h"

#define MAX_LANES SPM_REF_MAX_LANES
typedef spm_ref_lanes lanes;

/* The walk from the light end, for a path with a vertex whose factor mixes
 * lanes (spm_ref_kind_of: a fluorescent colour), docs/METHODS.md
 * "Fluorescence": A = E_bg c_bg (when the path escaped), then for
 * j = n-1 .. 0 vertex j's factor on A (vertex_apply, eye 0); L += A.
 * Returns 0, L untouched, for a path without one. */
/* The vertices of path before its first black one into *n; 1 when one of
 * them mixes lanes (a fluorescent colour of a table with blocks). */
static int mixes(const spm_path *path, const lanes *v, spm_u32 *n)
{
    int mix = 0;
    *n = path->h.nvert;
    for (spm_u32 j = 0; j < path->h.nvert; j++) {
        spm_u32 r = path->v[j].ids & 0xFFFFu;
        if (r == SPM_NONE) {
            *n = j;
            break;
        }
        mix |= spm_ref_kind_of(SPM_FK_PLAIN, r, v) != SPM_FK_PLAIN;
    }
    return mix;
}

static int from_light(const spm_path *path, const lanes *v, float *L)
{
    const spm_path_head *h = &path->h;
    float A[MAX_LANES];
    spm_u32 n;
    if (!mixes(path, v, &n))
        return 0;
    int lit = n == h->nvert && h->bg != SPM_NONE;
    if (lit)
        spm_ref_fetch(v, h->bg, A);
    for (int l = 0; l < v->n; l++)
        A[l] = lit ? A[l] * h->bg_c : 0.0f;
    for (spm_u32 j = n; j > 0; j--) {
        const spm_vertex *vx = &path->v[j - 1];
        const spm_vertex_ext *x = &path->x[j - 1];
        spm_ref_vertex_apply(0, spm_ref_kind_of((int)SPM_VX_KIND(*x), vx->ids & 0xFFFFu, v), vx,
                             x, v, NULL, A);
    }
    for (int l = 0; l < v->n; l++)
        L[l] = L[l] + A[l];
    return 1;
}

/* P = 1; L = first_emit_c E[first]; per vertex its factor (vertex_apply,
 * eye 1); then the background. A black vertex (no reflectance colour) ends
 * every later term. */
static void shade_lanes(const spm_path *path, const lanes *v, float *L)
{
    float P[MAX_LANES], X[MAX_LANES];
    const spm_path_head *h = &path->h;
    for (int l = 0; l < v->n; l++)
        L[l] = 0.0f, P[l] = 1.0f;
    if (h->first_emit != SPM_NONE) {
        spm_ref_fetch(v, h->first_emit, X);
        for (int l = 0; l < v->n; l++)
            L[l] = h->first_emit_c * X[l];
    }
    if (v->fluor && from_light(path, v, L))
        return;
    for (spm_u32 j = 0; j < h->nvert; j++) {
        if ((path->v[j].ids & 0xFFFFu) == SPM_NONE)
            return;
        spm_ref_vertex_apply(1, (int)SPM_VX_KIND(path->x[j]), &path->v[j], &path->x[j], v, P, L);
    }
    if (h->bg != SPM_NONE)
        spm_ref_emit_eye(v, h->bg, h->bg_c, P, L);
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
    lanes v = {tab->rows, (size_t)tab->stride, tab->lanes, NULL, {NULL, NULL, NULL},
               tab->fluor_floats ? tab : NULL};
    for (int ch = 0; tab->w && ch < 3; ch++)
        v.w[ch] = tab->w + (size_t)ch * (size_t)tab->stride;
    return v;
}

/* Per-path lanes: the bins they read and their weights. */
typedef struct {
    int idx[SPM_HERO_LANES];
    float w[3][SPM_HERO_LANES];
    float sfw[SPM_HERO_LANES]; /* spectral records: a lane's radiance to its share of
                                  its 5 nm bin's mean, 1 / (density lanes 5 nm) */
} path_lanes;

/* Hero wavelengths of one path (host/spectral/tables.c derives the density):
 * lane i at xi = frac(u + i/4), y = t0 + xi dt, wavelength 538 + atanh(y)/a
 * nm; its 1 nm bin j is atanh's guess moved to the bin whose edges bracket y;
 * the lane reads the spectra's 1 nm bin j and weighs it by truth's weight of
 * that bin over the density a (1 - y^2) / dt and the lane count. */
static lanes hero_path(const spm_shade_table *tab, float u, path_lanes *pl)
{
    const float *hx = tab->extra, *edge = hx + SPM_HERO_EDGE;
    for (int i = 0; i < SPM_HERO_LANES; i++) {
        float xi = u + (float)i / (float)SPM_HERO_LANES;
        if (xi >= 1.0f)
            xi -= 1.0f;
        float y = hx[SPM_HERO_T0] + xi * hx[SPM_HERO_DT];
        float nm = atanhf(y) / SPM_HERO_A + (SPM_HERO_CENTER - (float)SPM_LAMBDA_MIN);
        int j = nm > 0.0f ? (int)nm : 0;
        j = j < SPM_TRUTH_BINS - 1 ? j : SPM_TRUTH_BINS - 1;
        while (j > 0 && y < edge[j])
            j--;
        while (j < SPM_TRUTH_BINS - 1 && y >= edge[j + 1])
            j++;
        float pdf = hx[SPM_HERO_PDFK] * (1.0f - y * y);
        float r = 1.0f / (pdf * (float)SPM_HERO_LANES);
        pl->idx[i] = j;
        pl->sfw[i] = r / (float)(SPM_TRUTH_BINS / SPM_NM5_BINS);
        for (int ch = 0; ch < 3; ch++)
            pl->w[ch][i] = hx[SPM_HERO_CMF + 4 * j + ch] * r;
    }
    return (lanes){tab->rows, (size_t)tab->stride, SPM_HERO_LANES, pl->idx,
                   {pl->w[0], pl->w[1], pl->w[2]}, NULL};
}

/* The spectral bins of lanes L: through the slot's map, or (per-path lanes)
 * each lane into the level-0 (5 nm) bin holding its 1 nm bin. */
static void lanes_to_bins(const spm_spec_map *map, const path_lanes *pl, int per_path, int nbins,
                          const float *L, float *out)
{
    if (per_path) { /* idx: the lane's 1 nm bin */
        for (int b = 0; b < nbins; b++)
            out[b] = 0.0f;
        for (int l = 0; l < SPM_HERO_LANES; l++)
            out[pl->idx[l] / (SPM_TRUTH_BINS / SPM_NM5_BINS)] += L[l] * pl->sfw[l];
        return;
    }
    const uint32_t *lane = map->idx + map->nbins + 1;
    for (int b = 0; b < nbins; b++) {
        float s = 0.0f;
        for (uint32_t e = map->idx[b]; e < map->idx[b + 1]; e++)
            s += L[lane[e]] * map->fac[e];
        out[b] = s;
    }
}

/* The first vertex of a path that committed it to a wavelength
 * (spm_shared.h SPM_VX_LAMBDA): its index (nvert: none), *b the 1 nm bin and
 * *iw 1 / its pdf. */
static spm_u32 commit_vertex(const spm_path *path, spm_u32 *b, float *iw)
{
    for (spm_u32 j = 0; j < path->h.nvert; j++) {
        *b = SPM_VX_LAMBDA(path->x[j]);
        *iw = path->x[j].light;
        if (*b != SPM_NONE)
            return j;
    }
    return path->h.nvert;
}

/* One lane, 1 nm bin b of every colour (tab->nm1), with truth's XYZ weights
 * at b in w. */
static lanes bin_lane(const spm_shade_table *tab, const int *idx, float w[3])
{
    for (int c = 0; c < 3; c++)
        w[c] = tab->nm1_w[(size_t)c * SPM_TRUTH_BINS + (spm_u32)*idx];
    return (lanes){tab->nm1, SPM_TRUTH_BINS, 1, idx, {&w[0], &w[1], &w[2]}, NULL};
}

/* Radiance L of bin b (already times 1 / pdf) into a record: XYZ, and
 * (ch > 3) the spectral bin holding b its share of that bin's mean. */
static void bin_record(const lanes *v, spm_u32 b, float L, int ch, float *out)
{
    lanes_to_xyz(v, &L, out);
    if (ch > 3) {
        int nb = ch - 3, wb = SPM_TRUTH_BINS / nb;
        for (int k = 0; k < nb; k++)
            out[3 + k] = 0.0f;
        out[3 + (int)b / wb] = L / (float)wb;
    }
}

/* A path committed to a wavelength (at its first dispersive vertex): shaded
 * as one lane, its 1 nm bin b of every colour, in every mode, times 1 / pdf.
 * Returns 0 for a path that did not commit. */
static int committed(const spm_path *path, const spm_shade_table *tab, int ch, float *out)
{
    spm_u32 b = SPM_NONE;
    float iw = 0.0f, w[3], L;
    if (commit_vertex(path, &b, &iw) == path->h.nvert)
        return 0;
    int idx = (int)b;
    lanes v = bin_lane(tab, &idx, w);
    shade_lanes(path, &v, &L);
    bin_record(&v, b, L * iw, ch, out);
    return 1;
}

void spm_ref_shade_tables(const spm_mode_desc *m, const spm_shade_table *tabs,
                          const spm_trace_params *p, size_t first, const spm_path *paths,
                          const uint8_t *levels, size_t n, float *xyz)
{
    spm_ref_shade_spectral(m, tabs, NULL, 3, p, first, paths, levels, n, xyz);
}

void spm_ref_shade_spectral(const spm_mode_desc *m, const spm_shade_table *tabs,
                            const spm_spec_map *maps, int ch, const spm_trace_params *p,
                            size_t first, const spm_path *paths, const uint8_t *levels, size_t n,
                            float *rec)
{
    lanes lv[SPM_NUM_LEVELS];
    for (int s = 0; s < spm_mode_nslots(m); s++)
        lv[s] = table_lanes(&tabs[s]);
    float L[MAX_LANES];
    path_lanes pl;
    for (size_t i = 0; i < n; i++) {
        float *out = &rec[(size_t)ch * i];
        if (tabs[0].nm1 && committed(&paths[i], &tabs[0], ch, out))
            continue;
        lanes v = lv[spm_mode_slot(m, levels[i])];
        if (m->per_path) {
            spm_u32 pixel, sample;
            spm_ref_path_key(p, first + i, &pixel, &sample);
            v = hero_path(&tabs[0], spm_rng(p->seed, pixel, sample, SPM_DIM_HERO), &pl);
        }
        shade_lanes(&paths[i], &v, L);
        lanes_to_xyz(&v, L, out);
        if (ch > 3)
            lanes_to_bins(&maps[spm_mode_slot(m, levels[i])], &pl, m->per_path, ch - 3, L,
                          out + 3);
    }
}

/* One splat: lanes L (ch > 3: and their bins) into a splat of pixel px. */
static void splat(const lanes *v, const spm_spec_map *map, const path_lanes *pl, int per_path,
                  int ch, const float *L, spm_u32 px, spm_splats *out)
{
    float *o = spm_splats_push(out, px);
    lanes_to_xyz(v, L, o);
    if (ch > 3)
        lanes_to_bins(map, pl, per_path, ch - 3, L, o + 3);
}

/* A light subpath with a vertex that mixes lanes (a fluorescent colour),
 * walked in light-flow order (docs/METHODS.md "Fluorescence"): T = E[light],
 * the light's spectrum; at vertex j the kind's rule as the walk from the
 * light end applies it to the light arriving (vertex_apply, eye 0, the
 * vertex's light sample and hit left out): the splat is that rule on c_j T
 * with the record's camera argument (light) read as the one of the ray it
 * sends on (lobe), and T becomes the rule on T, what the vertex sends along
 * its sampled ray. At a fluorescent vertex both are M T, M = diag(D) + F:
 * the light's wavelength absorbed, the re-emitted one splatted and carried
 * on. Returns 0, nothing splatted, for a subpath without one. */
static int light_flow(const spm_light_path *lp, const lanes *v, const spm_spec_map *map,
                      const path_lanes *pl, int ch, spm_splats *out)
{
    const spm_path *path = &lp->p;
    float T[MAX_LANES], S[MAX_LANES];
    spm_u32 n;
    if (!mixes(path, v, &n))
        return 0;
    spm_ref_fetch(v, path->h.first_emit, T);
    for (spm_u32 j = 0; j < n; j++) {
        spm_vertex vx = path->v[j];
        spm_vertex_ext x = path->x[j];
        int kind = spm_ref_kind_of((int)SPM_VX_KIND(x), vx.ids & 0xFFFFu, v);
        vx.ids |= SPM_NONE << 16; /* no light sample: the light arrives in T */
        x.ids &= 0xFFFFu;         /* no hit */
        if (lp->px[j + 1] != SPM_NO_PIXEL) {
            spm_vertex_ext xc = x;
            xc.lobe = x.light;
            for (int l = 0; l < v->n; l++)
                S[l] = T[l] * vx.c;
            spm_ref_vertex_apply(0, kind, &vx, &xc, v, NULL, S);
            splat(v, map, pl, 0, ch, S, lp->px[j + 1], out);
        }
        spm_ref_vertex_apply(0, kind, &vx, &x, v, NULL, T);
    }
    return 1;
}

/* A light subpath's splats (refcpu.h spm_light_path), read from the light:
 * the light's own, E[first] first_emit_c; then W = 1 and per vertex j its
 * factor as a camera path applies it with the light's emission as the
 * vertex's emitter (vertex_apply, eye 1, into lanes of its own): W picks up
 * the factors of the vertices before and the splat is W f E[light] c_j. A
 * black vertex ends the walk; so does vertex jc, where the subpath committed
 * to a wavelength (committed_splats takes the splats from there). */
static void shade_light_path(const spm_light_path *lp, const lanes *v, const spm_spec_map *map,
                             const path_lanes *pl, int per_path, int ch, spm_u32 jc,
                             spm_splats *out)
{
    float W[MAX_LANES], L[MAX_LANES];
    const spm_path *path = &lp->p;
    if (path->h.first_emit != SPM_NONE && lp->px[0] != SPM_NO_PIXEL) {
        spm_ref_fetch(v, path->h.first_emit, L);
        for (int l = 0; l < v->n; l++)
            L[l] *= path->h.first_emit_c;
        splat(v, map, pl, per_path, ch, L, lp->px[0], out);
    }
    if (v->fluor && light_flow(lp, v, map, pl, ch, out))
        return;
    for (int l = 0; l < v->n; l++)
        W[l] = 1.0f;
    for (spm_u32 j = 0; j < jc; j++) {
        if ((path->v[j].ids & 0xFFFFu) == SPM_NONE)
            return;
        for (int l = 0; l < v->n; l++)
            L[l] = 0.0f;
        spm_ref_vertex_apply(1, (int)SPM_VX_KIND(path->x[j]), &path->v[j], &path->x[j], v, W, L);
        if (lp->px[j + 1] != SPM_NO_PIXEL)
            splat(v, map, pl, per_path, ch, L, lp->px[j + 1], out);
    }
}

/* The splats of a subpath that committed to 1 nm bin b at vertex jc (its
 * first dispersive vertex, 1 / pdf iw): the same walk from the light in one
 * lane, bin b of every colour, whatever the mode, splatting from jc on, each
 * times iw. The splats before jc do not depend on the wavelength: the mode's
 * lanes keep them (docs/METHODS.md "Dispersion"). */
static void committed_splats(const spm_light_path *lp, const spm_shade_table *tab, int ch,
                             spm_u32 jc, spm_u32 b, float iw, spm_splats *out)
{
    const spm_path *path = &lp->p;
    float W = 1.0f, L, w[3];
    int idx = (int)b;
    lanes v = bin_lane(tab, &idx, w);
    for (spm_u32 j = 0; j < path->h.nvert; j++) {
        if ((path->v[j].ids & 0xFFFFu) == SPM_NONE)
            return;
        L = 0.0f;
        spm_ref_vertex_apply(1, (int)SPM_VX_KIND(path->x[j]), &path->v[j], &path->x[j], &v, &W,
                             &L);
        if (j >= jc && lp->px[j + 1] != SPM_NO_PIXEL)
            bin_record(&v, b, L * iw, ch, spm_splats_push(out, lp->px[j + 1]));
    }
}

void spm_ref_shade_splats(const spm_mode_desc *m, const spm_shade_table *tabs,
                          const spm_spec_map *maps, int ch, const spm_trace_params *p,
                          size_t first, const spm_light_path *paths, const uint8_t *levels,
                          size_t n, spm_splats *out)
{
    path_lanes pl;
    for (size_t i = 0; i < n; i++) {
        int slot = spm_mode_slot(m, levels[i]);
        lanes v = table_lanes(&tabs[slot]);
        if (m->per_path) {
            spm_u32 pixel, sample;
            spm_ref_path_key(p, first + i, &pixel, &sample);
            v = hero_path(&tabs[0], spm_rng(p->seed, pixel, sample, SPM_DIM_HERO), &pl);
        }
        spm_u32 b = SPM_NONE, jc = paths[i].p.h.nvert;
        float iw = 0.0f;
        if (tabs[0].nm1)
            jc = commit_vertex(&paths[i].p, &b, &iw);
        shade_light_path(&paths[i], &v, maps ? &maps[slot] : NULL, &pl, m->per_path, ch, jc, out);
        if (jc < paths[i].p.h.nvert)
            committed_splats(&paths[i], &tabs[0], ch, jc, b, iw, out);
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
