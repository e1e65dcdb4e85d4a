/* Pretests (docs/METHODS.md "Choosing levels"): a spectrum's own sampling error at
 * each level against level 0, the 1 nm truth, measured in products where every
 * other factor stays at 1 nm, both products scaled by the factor that takes the
 * 1 nm one to Y = 50, against a D65 white of Y = 100. */
#include "pretest.h"
#include "colour.h"
#include "interrupt.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define NORM_Y 50.0
#define WHITE_Y 100.0

typedef double bins_t[SPM_TRUTH_BINS];

void spm_pretest_defaults(spm_pretest_opts *o)
{
    o->metric = SPM_METRIC_DE00;
    o->threshold = 2.0;
    o->seed = 1;
    o->nsequences = 64;
    o->coarsest_level = SPM_DEFAULT_COARSEST;
}

/* splitmix64: small, deterministic, independent of the platform's rand(). */
static uint64_t next_u64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

int spm_pretest_pick(uint64_t *state, int n) { return (int)(next_u64(state) % (uint64_t)n); }

uint64_t spm_pretest_seq_state(const spm_pretest_opts *o, int self)
{
    return (uint64_t)o->seed * 0x100000001B3ULL + (uint64_t)self;
}

/* The spectrum at `level`, held at 1 nm (each bin repeated over its nm). */
static void at_level(const spm_spectrum *s, int level, bins_t out)
{
    double bins[SPM_TRUTH_BINS];
    int w = SPM_TRUTH_BINS / SPM_LEVEL_BINS(level);
    spm_spectrum_level(s, level, bins);
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        out[b] = bins[b / w];
}

/* Colour difference of two products, both scaled by one factor: the one that
 * takes the 1 nm (level-0) product to Y = 50. So a darkening chain cannot hide a hue
 * error, and a level's luminance error counts too: scaling each product to its
 * own Y hid it, yet it shows in the pixel (a long chain's R^k at a coarse
 * level is darker or brighter than at level 0, and so is its share of the
 * pixel's sum over path lengths). A product without luminance at level 0
 * cannot be seen: no error. */
static void xyz_1nm(const bins_t p, double xyz[3])
{
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    /* the three sums in one pass, each in the order of the bins (the same
     * doubles as three passes; three chains of additions overlap) */
    double x = 0.0, y = 0.0, z = 0.0;
    for (int b = 0; b < SPM_TRUTH_BINS; b++) {
        x += p[b] * w[0][b];
        y += p[b] * w[1][b];
        z += p[b] * w[2][b];
    }
    xyz[0] = x, xyz[1] = y, xyz[2] = z;
}

double spm_pretest_xyz_error(const double ref[3], const double test[3], spm_metric metric)
{
    double xr[3], xt[3], white[3], lr[3], lt[3];
    if (!(ref[1] > 0.0))
        return 0.0;
    if (!(test[1] > 0.0))
        return WHITE_Y; /* the level lost all luminance: as far from it as black from white */
    spm_white_d65(white);
    double f = NORM_Y / ref[1];
    for (int k = 0; k < 3; k++) {
        xr[k] = ref[k] * f;
        xt[k] = test[k] * f;
        white[k] *= WHITE_Y;
    }
    spm_xyz_to_lab(xr, white, lr);
    spm_xyz_to_lab(xt, white, lt);
    return metric == SPM_METRIC_DEAB ? spm_delta_e_ab(lr, lt) : spm_delta_e_2000(lr, lt);
}

/* The error of s * factor against s0 * factor at each level l >= 1 (s at
 * slv[l]), e[l]: the level-0 product and its XYZ computed once for all. */
static void context_errors(const bins_t s0, const bins_t *slv, const bins_t factor,
                           spm_metric metric, double e[SPM_NUM_LEVELS])
{
    bins_t p0, pl;
    double x0[3], xl[3];
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        p0[b] = factor[b] * s0[b];
    xyz_1nm(p0, x0);
    for (int l = 1; l < SPM_NUM_LEVELS; l++) {
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            pl[b] = factor[b] * slv[l][b];
        xyz_1nm(pl, xl);
        e[l] = spm_pretest_xyz_error(x0, xl, metric);
    }
}

static double maxd(double a, double b) { return a > b ? a : b; }

/* The set split by kind, at level 0 (1 nm). */
typedef struct {
    bins_t *lights, *refl;
    int *refl_index;
    int nlights, nrefl;
} set_t;

static void split_set(const spm_spectrum *const *sp, int n, const unsigned char *skip, set_t *set)
{
    set->lights = spm_xcalloc((size_t)n + 1, sizeof *set->lights);
    set->refl = spm_xcalloc((size_t)n + 1, sizeof *set->refl);
    set->refl_index = spm_xcalloc((size_t)n + 1, sizeof *set->refl_index);
    set->nlights = set->nrefl = 0;
    for (int i = 0; i < n; i++) {
        if (skip && skip[i])
            continue; /* judged, but no factor of another's products */
        if (sp[i]->kind == SPM_KIND_EMISSION) {
            at_level(sp[i], 0, set->lights[set->nlights++]);
        } else {
            set->refl_index[set->nrefl] = i;
            at_level(sp[i], 0, set->refl[set->nrefl++]);
        }
    }
    if (set->nlights == 0) { /* an equal-energy light stands in */
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            set->lights[0][b] = 1.0;
        set->nlights = 1;
    }
}

/* Context C: products of 1..SPM_PRETEST_SEQ_OTHERS other reflectances of the set,
 * times a random light (for a reflectance) or alone (the emission is s); the
 * worst error at each level l >= 1 in worst[l]. */
static void sequence_errors(const set_t *set, int self, int seed, int is_light, const bins_t s0,
                            const bins_t *slv, const spm_pretest_opts *o,
                            double worst[SPM_NUM_LEVELS])
{
    memset(worst, 0, SPM_NUM_LEVELS * sizeof *worst);
    int others = set->nrefl - (is_light ? 0 : 1);
    if (others <= 0)
        return;
    uint64_t state = spm_pretest_seq_state(o, seed);
    for (int q = 0; q < o->nsequences; q++) {
        bins_t f;
        if (is_light)
            for (int b = 0; b < SPM_TRUTH_BINS; b++)
                f[b] = 1.0;
        else
            memcpy(f, set->lights[spm_pretest_pick(&state, set->nlights)], sizeof f);
        int m = 1 + spm_pretest_pick(&state, SPM_PRETEST_SEQ_OTHERS);
        for (int j = 0; j < m; j++) {
            int r = spm_pretest_pick(&state, set->nrefl);
            if (!is_light && set->refl_index[r] == self)
                r = (r + 1) % set->nrefl; /* another spectrum: s itself is not "other" */
            for (int b = 0; b < SPM_TRUTH_BINS; b++)
                f[b] *= set->refl[r][b];
        }
        double e[SPM_NUM_LEVELS];
        context_errors(s0, slv, f, o->metric, e);
        for (int l = 1; l < SPM_NUM_LEVELS; l++)
            worst[l] = maxd(worst[l], e[l]);
    }
}

/* The contexts of a spectrum given at 1 nm (s0) and as each level renders it
 * (slv[l], held at 1 nm; slv[0] unused). */
static void run_given(const double *s0, const bins_t *slv, int is_light, int self, int seed,
                      const set_t *set, const spm_pretest_opts *o, spm_pretest_result *res)
{
    double err_ac[SPM_NUM_LEVELS] = {0};
    bins_t one;
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        one[b] = 1.0;
    memset(res, 0, sizeof *res);
    /* A and B: s^k under each light, the powers built up one k at a time;
     * an emission ends the product, so for it every k is context A (s on
     * its own). */
    if (is_light) {
        double e[SPM_NUM_LEVELS];
        context_errors(s0, slv, one, o->metric, e);
        for (int k = 1; k <= SPM_PRETEST_KMAX; k++)
            for (int l = 1; l < SPM_NUM_LEVELS; l++)
                res->err_k[k - 1][l] = e[l];
    } else {
        for (int li = 0; li < set->nlights; li++) {
            bins_t p0, pl[SPM_NUM_LEVELS];
            memcpy(p0, set->lights[li], sizeof p0);
            for (int l = 1; l < SPM_NUM_LEVELS; l++)
                memcpy(pl[l], set->lights[li], sizeof pl[l]);
            for (int k = 1; k <= SPM_PRETEST_KMAX; k++) {
                double x0[3], xl[3];
                for (int b = 0; b < SPM_TRUTH_BINS; b++)
                    p0[b] *= s0[b];
                xyz_1nm(p0, x0);
                for (int l = 1; l < SPM_NUM_LEVELS; l++) {
                    for (int b = 0; b < SPM_TRUTH_BINS; b++)
                        pl[l][b] *= slv[l][b];
                    xyz_1nm(pl[l], xl);
                    double e = spm_pretest_xyz_error(x0, xl, o->metric);
                    res->err_k[k - 1][l] = li ? maxd(res->err_k[k - 1][l], e) : e;
                }
            }
        }
    }
    double err_c[SPM_NUM_LEVELS];
    sequence_errors(set, self, seed, is_light, s0, slv, o, err_c);
    for (int l = 1; l < SPM_NUM_LEVELS; l++)
        err_ac[l] = maxd(res->err_k[0][l], err_c[l]);
    /* a context fails a level whose error exceeds the threshold */
    unsigned char fail_ac[SPM_NUM_LEVELS], fail_k[SPM_PRETEST_KMAX][SPM_NUM_LEVELS];
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        fail_ac[l] = !(err_ac[l] <= o->threshold);
        for (int k = 0; k < SPM_PRETEST_KMAX; k++)
            fail_k[k][l] = !(res->err_k[k][l] <= o->threshold);
    }
    spm_pretest_fold(fail_ac, fail_k, err_ac, o->coarsest_level, res);
}

void spm_pretest_fold(const unsigned char fail_ac[SPM_NUM_LEVELS],
                      const unsigned char fail_k[SPM_PRETEST_KMAX][SPM_NUM_LEVELS],
                      const double err_ac[SPM_NUM_LEVELS], int coarsest,
                      spm_pretest_result *res)
{
    unsigned char upto[SPM_NUM_LEVELS]; /* failed by A, C or B with at most k occurrences */
    memcpy(upto, fail_ac, sizeof upto);
    for (int k = 0; k < SPM_PRETEST_KMAX; k++) {
        int best = 0;
        for (int l = 1; l < SPM_NUM_LEVELS; l++) {
            upto[l] |= fail_k[k][l];
            if (l <= coarsest && !upto[l])
                best = l;
        }
        res->level_k[k] = best;
    }
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        res->err[l] = err_ac[l];
        for (int k = 0; k < SPM_PRETEST_KMAX; k++)
            res->err[l] = maxd(res->err[l], res->err_k[k][l]);
    }
    res->level = res->level_k[SPM_PRETEST_KMAX - 1];
}

static void run_one(const spm_spectrum *s, int self, int seed, const set_t *set,
                    const spm_pretest_opts *o, spm_pretest_result *res)
{
    bins_t s0, slv[SPM_NUM_LEVELS];
    at_level(s, 0, s0);
    for (int l = 1; l < SPM_NUM_LEVELS; l++)
        at_level(s, l, slv[l]);
    run_given(s0, slv, s->kind == SPM_KIND_EMISSION, self, seed, set, o, res);
}

void spm_pretest_given(const spm_spectrum *const *spectra, int n, const double *f0,
                       const double (*fl)[SPM_TRUTH_BINS], int self, const spm_pretest_opts *o,
                       spm_pretest_result *res)
{
    set_t set;
    split_set(spectra, n, NULL, &set);
    run_given(f0, fl, 0, self, self, &set, o, res);
    free(set.lights);
    free(set.refl);
    free(set.refl_index);
}

int spm_pretest_run(const spm_spectrum *const *spectra, int n, const spm_pretest_opts *o,
                    spm_pretest_result *results)
{
    return spm_pretest_run_skip(spectra, n, NULL, o, results);
}

int spm_pretest_run_skip(const spm_spectrum *const *spectra, int n, const unsigned char *skip,
                         const spm_pretest_opts *o, spm_pretest_result *results)
{
    set_t set;
    split_set(spectra, n, skip, &set);
    /* context C's generator is seeded by a spectrum's place among the factors
     * (a skipped one's after them all), so a skipped spectrum changes no other's
     * sequences: the others' results are those of a run without it */
    int i = 0, skipped = 0;
    for (; i < n; i++) {
        spm_test_pause("pretest");
        if (spm_stop_requested())
            break;
        int seed = skip && skip[i] ? n + skipped++ : i - skipped;
        run_one(spectra[i], i, seed, &set, o, &results[i]);
    }
    free(set.lights);
    free(set.refl);
    free(set.refl_index);
    return i;
}

/* Context B's columns in the table: every k up to 8, then a few longer chains. */
static const int print_k[] = {1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 24, 32, 48, SPM_PRETEST_KMAX};
#define NPRINT_K ((int)(sizeof print_k / sizeof print_k[0]))

void spm_pretest_print(FILE *f, const char *const *names, const spm_pretest_result *r, int n,
                       const spm_pretest_opts *o)
{
    fprintf(f, "pretest: metric %s, threshold %g, seed %u, %d sequences, coarsest level %d\n",
            o->metric == SPM_METRIC_DEAB ? "dEab" : "dE00", o->threshold, o->seed,
            o->nsequences, o->coarsest_level);
    fprintf(f, "%-24s %5s %4s %8s", "spectrum", "level", "bins", "worst");
    for (int i = 0; i < NPRINT_K; i++) {
        char h[16];
        snprintf(h, sizeof h, "B k=%d", print_k[i]);
        fprintf(f, " %8s", h);
    }
    fputc('\n', f);
    for (int i = 0; i < n; i++) {
        for (int l = 1; l < SPM_NUM_LEVELS; l++) {
            fprintf(f, "%-24s %5d %4d %8.3f", names[i], l, SPM_LEVEL_BINS(l), r[i].err[l]);
            for (int j = 0; j < NPRINT_K; j++)
                fprintf(f, " %8.3f", r[i].err_k[print_k[j] - 1][l]);
            fputc('\n', f);
        }
        /* per k as runs of equal levels: "k 1: 2, k 2-8: 1, k 9-64: 0" */
        fprintf(f, "%-24s chosen level %d; per k:", names[i], r[i].level);
        for (int k = 0; k < SPM_PRETEST_KMAX;) {
            int e = k;
            while (e + 1 < SPM_PRETEST_KMAX && r[i].level_k[e + 1] == r[i].level_k[k])
                e++;
            if (e > k)
                fprintf(f, "%s k %d-%d: %d", k ? "," : "", k + 1, e + 1, r[i].level_k[k]);
            else
                fprintf(f, "%s k %d: %d", k ? "," : "", k + 1, r[i].level_k[k]);
            k = e + 1;
        }
        fputc('\n', f);
    }
}
