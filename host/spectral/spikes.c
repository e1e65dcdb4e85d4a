/* Composite Model: two-pass Gaussian spike detector on the 1 nm truth bins and
 * the scene-wide spike pattern table (thesis 6.2.2; docs/METHODS.md "Modes"). */
#include "spikes.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define N SPM_TRUTH_BINS

void spm_spike_defaults(spm_spike_opts *o)
{
    /* A 5 nm-sampled line is a ~10 nm triangle at 1 nm: a 5 nm blur flattens
     * it to well under half its height, while a broad peak (an LED's 20 nm
     * wide pump or phosphor band) keeps most of it and stays unmarked. */
    o->sigma1_nm = 5.0;
    o->sigma2_nm = 5.0;
    /* Pass 1: 30 % above the local blurred level. Measured peak excess at 1 nm:
     * D65 7 %, the CIE LED pumps and phosphors 11-23 %, the weakest F-series
     * mercury line (F6 at 546 nm) 35 %. And 5 % of the mean, so that ripples
     * of a near-zero stretch are not lines. */
    o->rel1 = 0.3;
    o->abs1 = 0.05;
    /* Pass 2 only extends a line found by pass 1, so its thresholds are low. */
    o->rel2 = 0.05;
    o->abs2 = 0.01;
    /* A strong line's feet reach ~15 nm either side at 5 nm sampling. */
    o->max_width_nm = 40.0;
    /* Below 0.1 % of the energy a lane costs more than it carries. */
    o->min_fraction = 1e-3;
}

/* Gaussian blur with the kernel renormalised where it leaves the domain, so a
 * constant stays constant up to the ends. */
static void blur(const double *in, double *out, double sigma)
{
    int r = (int)ceil(3.0 * sigma);
    double *k = malloc((size_t)(r + 1) * sizeof *k);
    for (int d = 0; d <= r; d++)
        k[d] = exp(-0.5 * (d / sigma) * (d / sigma));
    for (int i = 0; i < N; i++) {
        double s = 0.0, w = 0.0;
        for (int j = i - r; j <= i + r; j++) {
            if (j < 0 || j >= N)
                continue;
            double kk = k[abs(j - i)];
            s += kk * in[j];
            w += kk;
        }
        out[i] = s / w;
    }
    free(k);
}

/* Value at bin i of the line joining the unmarked neighbours of run [a, z]
 * (the one neighbour's value when the run touches an end of the domain). */
static double base_at(const double *v, int a, int z, int i)
{
    if (a == 0)
        return v[z + 1];
    if (z == N - 1)
        return v[a - 1];
    double t = (double)(i - (a - 1)) / (double)(z + 1 - (a - 1));
    return v[a - 1] + t * (v[z + 1] - v[a - 1]);
}

/* End of the marked run starting at a (inclusive). */
static int run_end(const unsigned char *mark, int a)
{
    int z = a;
    while (z + 1 < N && mark[z + 1])
        z++;
    return z;
}

/* Start of the marked run ending at z (inclusive). */
static int run_start(const unsigned char *mark, int z)
{
    int a = z;
    while (a > 0 && mark[a - 1])
        a--;
    return a;
}

static int excess_above(double v, double b, double rel, double abs_min)
{
    double e = v - b;
    return e > rel * b && e > abs_min;
}

/* The input with every marked run replaced by the line between its unmarked
 * neighbours. Returns 0 when nothing is left unmarked to stand on. */
static int remove_runs(const double *in, const unsigned char *mark, double *clean)
{
    memcpy(clean, in, N * sizeof *clean);
    for (int a = 0; a < N; a++) {
        if (!mark[a])
            continue;
        int z = run_end(mark, a);
        if (a == 0 && z == N - 1)
            return 0;
        for (int i = a; i <= z; i++)
            clean[i] = base_at(in, a, z, i);
        a = z;
    }
    return 1;
}

/* Marks line bins. Pass 1: bins far above the blurred input. Pass 2: with the
 * marked runs removed and the rest blurred again, the bins next to a run that
 * still stand above that curve are its foothills. A 5 nm-sampled line is a
 * 10-20 nm triangle at 1 nm, whose removal leaves a raised plateau between
 * its flanks; so pass 2 repeats, one bin per side at a time, until no run
 * grows: each repeat lowers the plateau, and growth stops where the flank
 * turns convex (it then lies below its blur), i.e. at the line's foot. */
static void detect(const double *in, double mean, const spm_spike_opts *o, unsigned char *mark)
{
    double b[N], clean[N];
    blur(in, b, o->sigma1_nm);
    for (int i = 0; i < N; i++)
        mark[i] = (unsigned char)excess_above(in[i], b[i], o->rel1, o->abs1 * mean);
    for (int a = 0; a < N; a++) {
        if (!mark[a])
            continue;
        int z = run_end(mark, a);
        if (z - a + 1 > o->max_width_nm) /* a broad band, not a line */
            memset(mark + a, 0, (size_t)(z - a + 1));
        a = z;
    }
    double abs2 = o->abs2 * mean;
    for (int grown = 1; grown;) {
        if (!remove_runs(in, mark, clean))
            return;
        blur(clean, b, o->sigma2_nm);
        unsigned char next[N];
        memcpy(next, mark, sizeof next);
        grown = 0;
        for (int i = 0; i < N; i++) {
            if (mark[i])
                continue;
            if (!((i > 0 && mark[i - 1]) || (i + 1 < N && mark[i + 1])))
                continue;
            /* width of the run this bin would make (this round's growth included) */
            next[i] = 1;
            int width = run_end(next, i) - run_start(next, i) + 1;
            next[i] = 0;
            if (width <= o->max_width_nm && excess_above(in[i], b[i], o->rel2, abs2)) {
                next[i] = 1;
                grown = 1;
            }
        }
        memcpy(mark, next, sizeof next);
    }
}

static int by_area_desc(const void *pa, const void *pb)
{
    const spm_spike *a = pa, *b = pb;
    return (a->area < b->area) - (a->area > b->area);
}

static int by_wl(const void *pa, const void *pb)
{
    const spm_spike *a = pa, *b = pb;
    return (a->wl > b->wl) - (a->wl < b->wl);
}

/* Spike part of run [a, z]: what stands above its base line. */
static spm_spike measure(const double *in, int a, int z)
{
    spm_spike s = {0.0, 0.0, a, z};
    double m = 0.0;
    for (int i = a; i <= z; i++) {
        double p = in[i] - base_at(in, a, z, i);
        if (p > 0.0) {
            s.area += p;
            m += p * (SPM_LAMBDA_MIN + i + 0.5);
        }
    }
    if (s.area > 0.0)
        s.wl = m / s.area;
    return s;
}

int spm_spike_split(const spm_spectrum *in_s, spm_spectrum *smooth, spm_spike *spikes,
                    int max_spikes, int *nspikes, const spm_spike_opts *opts)
{
    spm_spike_opts defaults;
    if (!opts) {
        spm_spike_defaults(&defaults);
        opts = &defaults;
    }
    double in[N], total = 0.0;
    memcpy(in, in_s->nm1, sizeof in);
    for (int i = 0; i < N; i++)
        total += in[i];
    *smooth = *in_s;
    *nspikes = 0;
    if (!(total > 0.0))
        return 0;

    unsigned char mark[N];
    detect(in, total / N, opts, mark);
    spm_spike cand[N / 2 + 1];
    int ncand = 0;
    for (int a = 0; a < N; a++) {
        if (!mark[a])
            continue;
        int z = run_end(mark, a);
        if (a > 0 || z < N - 1) {
            spm_spike s = measure(in, a, z);
            if (s.area > opts->min_fraction * total)
                cand[ncand++] = s;
        }
        a = z;
    }
    qsort(cand, (size_t)ncand, sizeof *cand, by_area_desc);
    int keep = ncand < max_spikes ? ncand : (max_spikes > 0 ? max_spikes : 0);
    for (int k = 0; k < keep; k++) {
        spm_spike *s = &cand[k];
        /* Recompute the area from what smooth actually loses, so that the
         * energy balance holds to rounding of the very sums a caller makes. */
        s->area = 0.0;
        for (int i = s->first; i <= s->last; i++) {
            double b = base_at(in, s->first, s->last, i);
            smooth->nm1[i] = in[i] < b ? in[i] : b;
            s->area += in[i] - smooth->nm1[i];
        }
    }
    qsort(cand, (size_t)keep, sizeof *cand, by_wl);
    memcpy(spikes, cand, (size_t)keep * sizeof *cand);
    *nspikes = keep;
    return ncand - keep;
}

/* ---- scene-wide pattern table ------------------------------------------- */

typedef struct {
    double wl, w;   /* centroid and rank weight (area / luminance) */
    int light, spike;
    int cluster;
} entry;

typedef struct {
    double wl, score;
    int lane;       /* -1: no lane */
} cluster;

static int entry_by_wl(const void *pa, const void *pb)
{
    const entry *a = pa, *b = pb;
    return (a->wl > b->wl) - (a->wl < b->wl);
}

/* Decreasing score; equal scores by wavelength, so the choice is deterministic. */
static int cluster_by_score(const void *pa, const void *pb)
{
    const cluster *a = *(const cluster *const *)pa, *b = *(const cluster *const *)pb;
    if (a->score != b->score)
        return (a->score < b->score) - (a->score > b->score);
    return (a->wl > b->wl) - (a->wl < b->wl);
}

static int cluster_by_wl(const void *pa, const void *pb)
{
    const cluster *a = *(const cluster *const *)pa, *b = *(const cluster *const *)pb;
    return (a->wl > b->wl) - (a->wl < b->wl);
}

/* A light's rank normaliser: its luminance, or its energy when it has none. */
static double light_norm(const spm_spike_light *l)
{
    if (l->luminance > 0.0)
        return l->luminance;
    double e = 0.0;
    for (int i = 0; i < N; i++)
        e += l->in->nm1[i];
    return e > 0.0 ? e : 1.0;
}

int spm_spike_pattern_merge(spm_spike_light *lights, int nlights, double merge_nm, int max_lanes,
                            double lane_wl[SPM_MAX_SPIKES])
{
    if (max_lanes > SPM_MAX_SPIKES)
        max_lanes = SPM_MAX_SPIKES;
    int n = 0;
    for (int l = 0; l < nlights; l++)
        n += lights[l].nspikes;
    entry *e = malloc((size_t)(n > 0 ? n : 1) * sizeof *e);
    cluster *c = malloc((size_t)(n > 0 ? n : 1) * sizeof *c);
    cluster **order = malloc((size_t)(n > 0 ? n : 1) * sizeof *order);
    n = 0;
    for (int l = 0; l < nlights; l++) {
        double norm = light_norm(&lights[l]);
        for (int k = 0; k < lights[l].nspikes; k++)
            e[n++] = (entry){lights[l].spikes[k].wl, lights[l].spikes[k].area / norm, l, k, -1};
    }
    qsort(e, (size_t)n, sizeof *e, entry_by_wl);

    /* Clusters: runs of entries within merge_nm of the run's first centroid
     * (measured from the first, so a chain cannot drift). */
    int nc = 0;
    for (int j = 0; j < n;) {
        double first = e[j].wl, sw = 0.0, swl = 0.0, sum_wl = 0.0;
        int k = j;
        for (; k < n && e[k].wl - first < merge_nm; k++) {
            e[k].cluster = nc;
            sw += e[k].w;
            swl += e[k].w * e[k].wl;
            sum_wl += e[k].wl;
        }
        c[nc] = (cluster){sw > 0.0 ? swl / sw : sum_wl / (k - j), sw, -1};
        order[nc] = &c[nc];
        nc++;
        j = k;
    }
    qsort(order, (size_t)nc, sizeof *order, cluster_by_score);
    int nlanes = nc < max_lanes ? nc : (max_lanes > 0 ? max_lanes : 0);
    qsort(order, (size_t)nlanes, sizeof *order, cluster_by_wl);
    for (int k = 0; k < nlanes; k++) {
        order[k]->lane = k;
        lane_wl[k] = order[k]->wl;
    }

    for (int l = 0; l < nlights; l++) {
        memset(lights[l].lane_area, 0, sizeof lights[l].lane_area);
        for (int k = 0; k < SPM_MAX_SPIKES; k++)
            lights[l].spike_lane[k] = -1;
        lights[l].norm = light_norm(&lights[l]);
    }
    for (int j = 0; j < n; j++) {
        spm_spike_light *L = &lights[e[j].light];
        const spm_spike *s = &L->spikes[e[j].spike];
        int lane = c[e[j].cluster].lane;
        L->spike_lane[e[j].spike] = lane;
        if (lane >= 0) {
            L->lane_area[lane] += s->area;
        } else {
            /* No lane: the spike goes back where it came from, exactly. */
            for (int i = s->first; i <= s->last; i++)
                L->smooth->nm1[i] = L->in->nm1[i];
        }
    }
    free(order);
    free(c);
    free(e);
    return nlanes;
}
