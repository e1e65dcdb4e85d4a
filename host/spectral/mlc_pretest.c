/* The Composite Model's pretest (mlc_pretest.h). A product is held as a vector
 * of 1 nm values followed by the lanes, so truth and every composite level
 * share one arithmetic: multiply lane by lane, then XYZ = the sum of value x
 * weight (truth's 1 nm weights, then the lanes' CMFs). A level's smooth bins
 * are held as their 1 nm repetitions: a level weight is the sum of the 1 nm
 * weights it covers, so this is the sum the shade kernel computes. Truth has
 * its whole spectrum in the 1 nm part and nothing in the lanes. A conductor's
 * eta and k are no factor of a product: they leave the set, and the pair is
 * judged by its Fresnel as the shade stage computes it, F per 1 nm value or
 * bin and per lane from that value's or lane's eta and k, against F of the
 * 1 nm eta and k, at the conductor pretest's cosines (conductor_pretest.c),
 * the worst kept. A dielectric's absorption sigma likewise: by its
 * transmittance exp(-sigma d) per 1 nm value or bin and per lane, as the
 * shade stage computes it from sigma's row, against exp of the 1 nm sigma,
 * at the dielectric pretest's lengths (dielectric_pretest.c). */
#include "mlc_pretest.h"
#include "colour.h"
#include "interrupt.h"
#include "materials.h"
#include "tables.h"
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define V (SPM_TRUTH_BINS + SPM_MAX_SPIKES)

typedef double vec_t[V];

typedef struct {
    int n, nlanes;
    vec_t w[3];       /* XYZ weights */
    vec_t *truth;     /* per colour */
    vec_t *comp0;     /* per colour, composite at level 0 */
    int *lights, nlights, *refl, nrefl; /* refl: the reflectances but optical constants */
    vec_t one;        /* the equal-energy light standing in when there is none */
} ctx_t;

static double maxd(double a, double b) { return a > b ? a : b; }

static void composite(const spm_mlc_colour *c, int nlanes, int level, vec_t out)
{
    double bins[SPM_TRUTH_BINS];
    spm_spectrum_level(c->smooth, level, bins);
    int width = SPM_TRUTH_BINS / SPM_LEVEL_BINS(level);
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        out[i] = bins[i / width];
    for (int k = 0; k < SPM_MAX_SPIKES; k++)
        out[SPM_TRUTH_BINS + k] = k < nlanes ? c->lane[k] : 0.0;
}

static void truth_of(const spm_mlc_colour *c, vec_t out)
{
    memcpy(out, c->full->nm1, sizeof c->full->nm1);
    for (int k = 0; k < SPM_MAX_SPIKES; k++)
        out[SPM_TRUTH_BINS + k] = 0.0;
}

static void mul(vec_t a, const vec_t b)
{
    for (int i = 0; i < V; i++)
        a[i] *= b[i];
}

/* the three sums in one pass, each in the order of the values (the same
 * doubles as three passes; three chains of additions overlap) */
static void xyz_of(const ctx_t *cx, const vec_t p, double xyz[3])
{
    double x = 0.0, y = 0.0, z = 0.0;
    for (int i = 0; i < V; i++) {
        x += p[i] * cx->w[0][i];
        y += p[i] * cx->w[1][i];
        z += p[i] * cx->w[2][i];
    }
    xyz[0] = x, xyz[1] = y, xyz[2] = z;
}

/* A level's error in one product (e: against truth; own: against level 0 in
 * composite form) and whether it passes: under the threshold against truth,
 * or, where level 0 itself is not (the lanes' own error: a lane holds one mean
 * per colour, so a product of means stands for the mean of a product, and no
 * level of the smooth part removes that), its own sampling error under the
 * threshold: a finer level would cost without reaching truth. */
static void judge(const double e[SPM_NUM_LEVELS], const double own[SPM_NUM_LEVELS],
                  const spm_pretest_opts *o, double worst[SPM_NUM_LEVELS],
                  unsigned char fail[SPM_NUM_LEVELS])
{
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        worst[l] = maxd(worst[l], e[l]);
        if (l > 0 && e[l] > o->threshold && (e[0] <= o->threshold || own[l] > o->threshold))
            fail[l] = 1;
    }
}

/* Product errors at every level: pr the truth product, pt[l] the test ones. */
static void errors(const ctx_t *cx, const vec_t pr, vec_t *pt, spm_metric metric,
                   double e[SPM_NUM_LEVELS], double own[SPM_NUM_LEVELS])
{
    double xr[3], xt[SPM_NUM_LEVELS][3]; /* each product's XYZ once */
    xyz_of(cx, pr, xr);
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        xyz_of(cx, pt[l], xt[l]);
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        e[l] = spm_pretest_xyz_error(xr, xt[l], metric);
        own[l] = l ? spm_pretest_xyz_error(xt[0], xt[l], metric) : 0.0;
    }
}

/* Context C: s times 1..SPM_PRETEST_SEQ_OTHERS other reflectances (and a random light
 * when s is a reflectance), s at each level, the others at level 0. */
static void sequences(const ctx_t *cx, int self, int seed, int is_light, const vec_t s_truth,
                      vec_t *s_test, const spm_pretest_opts *o, double worst[SPM_NUM_LEVELS],
                      unsigned char fail[SPM_NUM_LEVELS])
{
    int in_set = 0; /* a light or a conductor's Fresnel is none of the reflectances */
    for (int r = 0; r < cx->nrefl; r++)
        in_set |= cx->refl[r] == self;
    int others = cx->nrefl - in_set;
    if (others <= 0)
        return;
    uint64_t state = spm_pretest_seq_state(o, seed);
    for (int q = 0; q < o->nsequences; q++) {
        vec_t pr, f, pt[SPM_NUM_LEVELS];
        memcpy(pr, s_truth, sizeof pr);
        memcpy(f, cx->one, sizeof f);
        for (int i = SPM_TRUTH_BINS; i < V; i++)
            f[i] = 1.0;
        if (!is_light) {
            int li = spm_pretest_pick(&state, cx->nlights ? cx->nlights : 1);
            mul(pr, cx->nlights ? cx->truth[cx->lights[li]] : cx->one);
            mul(f, cx->nlights ? cx->comp0[cx->lights[li]] : cx->one);
        }
        int m = 1 + spm_pretest_pick(&state, SPM_PRETEST_SEQ_OTHERS);
        for (int j = 0; j < m; j++) {
            int r = spm_pretest_pick(&state, cx->nrefl);
            if (!is_light && cx->refl[r] == self)
                r = (r + 1) % cx->nrefl;
            mul(pr, cx->truth[cx->refl[r]]);
            mul(f, cx->comp0[cx->refl[r]]);
        }
        double e[SPM_NUM_LEVELS], own[SPM_NUM_LEVELS];
        for (int l = 0; l < SPM_NUM_LEVELS; l++) {
            memcpy(pt[l], f, sizeof f);
            mul(pt[l], s_test[l]);
        }
        errors(cx, pr, pt, o->metric, e, own);
        judge(e, own, o, worst, fail);
    }
}

/* One factor s (truth s_truth, level l s_test[l]) in every context; seed
 * seeds its context C. */
static void run_factor(const ctx_t *cx, int is_light, int self, int seed, const double *s_truth,
                       vec_t *s_test, const spm_pretest_opts *o, spm_pretest_result *res)
{
    memset(res, 0, sizeof *res);
    /* A and C together (fail_ac), B per k (fail_k): the general pretest's contexts */
    double worst_ac[SPM_NUM_LEVELS] = {0};
    unsigned char fail_ac[SPM_NUM_LEVELS] = {0}, fail_k[SPM_PRETEST_KMAX][SPM_NUM_LEVELS];
    memset(fail_k, 0, sizeof fail_k);
    if (is_light) { /* an emission ends the product: every k is s on its own */
        double e[SPM_NUM_LEVELS], own[SPM_NUM_LEVELS];
        errors(cx, s_truth, s_test, o->metric, e, own);
        for (int k = 0; k < SPM_PRETEST_KMAX; k++)
            judge(e, own, o, res->err_k[k], fail_k[k]);
    } else {
        int nl = cx->nlights ? cx->nlights : 1;
        for (int li = 0; li < nl; li++) {
            vec_t pr, pt[SPM_NUM_LEVELS];
            memcpy(pr, cx->nlights ? cx->truth[cx->lights[li]] : cx->one, sizeof pr);
            for (int l = 0; l < SPM_NUM_LEVELS; l++)
                memcpy(pt[l], cx->nlights ? cx->comp0[cx->lights[li]] : cx->one, sizeof pr);
            for (int k = 0; k < SPM_PRETEST_KMAX; k++) {
                mul(pr, s_truth);
                for (int l = 0; l < SPM_NUM_LEVELS; l++)
                    mul(pt[l], s_test[l]);
                double e[SPM_NUM_LEVELS], own[SPM_NUM_LEVELS];
                errors(cx, pr, pt, o->metric, e, own);
                judge(e, own, o, res->err_k[k], fail_k[k]);
            }
        }
    }
    memcpy(worst_ac, res->err_k[0], sizeof worst_ac);
    memcpy(fail_ac, fail_k[0], sizeof fail_ac);
    sequences(cx, self, seed, is_light, s_truth, s_test, o, worst_ac, fail_ac);
    spm_pretest_fold(fail_ac, fail_k, worst_ac, o->coarsest_level, res);
}

static void run_one(const ctx_t *cx, const spm_mlc_colour *c, int self, int seed,
                    const spm_pretest_opts *o, spm_pretest_result *res)
{
    vec_t s_test[SPM_NUM_LEVELS];
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        composite(c, cx->nlanes, l, s_test[l]);
    run_factor(cx, c->full->kind == SPM_KIND_EMISSION, self, seed, cx->truth[self], s_test, o,
               res);
}

/* A conductor of eta colour ce and k colour ck (self: its context C seed): at
 * each cosine, truth F(eta, k) per 1 nm value; level l F of eta's and k's
 * level-l composites value by value (the smooth bins held at 1 nm, then the
 * lanes: the shade stage's F per lane from the lane's eta and k). */
static void run_conductor(const ctx_t *cx, const spm_mlc_colour *ce, const spm_mlc_colour *ck,
                          int self, const spm_pretest_opts *o, spm_pretest_result *res)
{
    vec_t ft, ve[SPM_NUM_LEVELS], vk[SPM_NUM_LEVELS], ftest[SPM_NUM_LEVELS];
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        composite(ce, cx->nlanes, l, ve[l]);
        composite(ck, cx->nlanes, l, vk[l]);
    }
    for (int a = 0; a < SPM_CONDUCTOR_NCOS; a++) {
        double c = spm_conductor_cosines[a];
        for (int i = 0; i < V; i++)
            ft[i] = i < SPM_TRUTH_BINS ? spm_conductor_fresnel(ce->full->nm1[i], ck->full->nm1[i], c)
                                       : 0.0;
        for (int l = 0; l < SPM_NUM_LEVELS; l++)
            for (int i = 0; i < V; i++)
                ftest[l][i] = i < SPM_TRUTH_BINS + cx->nlanes
                                  ? spm_conductor_fresnel(ve[l][i], vk[l][i], c)
                                  : 0.0;
        spm_pretest_result r;
        run_factor(cx, 0, self, self, ft, ftest, o, &r);
        spm_conductor_pretest_merge(res, &r, a == 0);
    }
}

/* A dielectric of absorption colour cs and longest segment inside dmax: at
 * each length d, truth exp(-sigma d) per 1 nm value; level l exp of sigma's
 * level-l composite value by value (the smooth bins held at 1 nm, then the
 * lanes: the shade stage's exp per lane of the lane's sigma). */
static void run_dielectric(const ctx_t *cx, const spm_mlc_colour *cs, double dmax, int self,
                           const spm_pretest_opts *o, spm_pretest_result *res)
{
    vec_t ft, vs[SPM_NUM_LEVELS], ftest[SPM_NUM_LEVELS];
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        composite(cs, cx->nlanes, l, vs[l]);
    for (int a = 0; a < SPM_DIELECTRIC_NLEN; a++) {
        double d = spm_dielectric_fractions[a] * dmax;
        for (int i = 0; i < V; i++)
            ft[i] = i < SPM_TRUTH_BINS ? exp(-cs->full->nm1[i] * d) : 0.0;
        for (int l = 0; l < SPM_NUM_LEVELS; l++)
            for (int i = 0; i < V; i++)
                ftest[l][i] = i < SPM_TRUTH_BINS + cx->nlanes ? exp(-vs[l][i] * d) : 0.0;
        spm_pretest_result r;
        run_factor(cx, 0, self, self, ft, ftest, o, &r);
        spm_conductor_pretest_merge(res, &r, a == 0);
    }
}

/* An optical colour c's result r: the first that uses it takes r, a later one
 * the finer level of the two. */
static void optical_result(unsigned char *optical, int c, const spm_pretest_result *r,
                           spm_pretest_result *results)
{
    if (optical[c] == 1) {
        results[c] = *r, optical[c] = 2;
        return;
    }
    for (int k = 0; k < SPM_PRETEST_KMAX; k++)
        results[c].level_k[k] = r->level_k[k] < results[c].level_k[k] ? r->level_k[k]
                                                                       : results[c].level_k[k];
    results[c].level = r->level < results[c].level ? r->level : results[c].level;
}

int spm_mlc_pretest_run(const spm_mlc_colour *cols, int n, int nlanes,
                        const double lane_cmf[3][SPM_MAX_SPIKES], const int (*conductors)[2],
                        int nconductors, const int *dielectrics, const double *diel_len,
                        int ndielectrics, const spm_pretest_opts *o, spm_pretest_result *results)
{
    ctx_t *cx = spm_xcalloc(1, sizeof *cx);
    cx->n = n;
    cx->nlanes = nlanes;
    const double (*wt)[SPM_TRUTH_BINS] = spm_cmf_truth();
    for (int ch = 0; ch < 3; ch++) {
        memcpy(cx->w[ch], wt[ch], sizeof wt[ch]);
        for (int k = 0; k < SPM_MAX_SPIKES; k++)
            cx->w[ch][SPM_TRUTH_BINS + k] = k < nlanes ? lane_cmf[ch][k] : 0.0;
    }
    for (int i = 0; i < V; i++)
        cx->one[i] = i < SPM_TRUTH_BINS ? 1.0 : 0.0;
    cx->truth = spm_xcalloc((size_t)n + 1, sizeof *cx->truth);
    cx->comp0 = spm_xcalloc((size_t)n + 1, sizeof *cx->comp0);
    cx->lights = spm_xcalloc((size_t)n + 1, sizeof *cx->lights);
    cx->refl = spm_xcalloc((size_t)n + 1, sizeof *cx->refl);
    /* optical[c]: 1 for a conductor's eta or k or a dielectric's sigma, 2 once
     * a result is in */
    unsigned char *optical = spm_xcalloc((size_t)n + 1, 1);
    for (int j = 0; j < nconductors; j++)
        optical[conductors[j][0]] = optical[conductors[j][1]] = 1;
    for (int j = 0; j < ndielectrics; j++)
        optical[dielectrics[j]] = 1;
    for (int i = 0; i < n; i++) {
        truth_of(&cols[i], cx->truth[i]);
        composite(&cols[i], nlanes, 0, cx->comp0[i]);
        if (cols[i].no_factor)
            continue;
        if (cols[i].full->kind == SPM_KIND_EMISSION)
            cx->lights[cx->nlights++] = i;
        else if (!optical[i])
            cx->refl[cx->nrefl++] = i;
    }
    /* context C seeded by the colour's place among the factors (as the general
     * pretest: a colour that is no factor changes no other's sequences) */
    int i = 0, skipped = 0;
    for (; i < n; i++) {
        spm_test_pause("pretest");
        if (spm_stop_requested())
            break;
        int seed = cols[i].no_factor ? n + skipped++ : i - skipped;
        if (!optical[i])
            run_one(cx, &cols[i], i, seed, o, &results[i]);
    }
    /* a colour two materials share takes the finer level of the two */
    for (int j = 0; j < nconductors && i == n && !spm_stop_requested(); j++) {
        spm_pretest_result r;
        run_conductor(cx, &cols[conductors[j][0]], &cols[conductors[j][1]], n + j, o, &r);
        for (int q = 0; q < 2; q++)
            optical_result(optical, conductors[j][q], &r, results);
    }
    for (int j = 0; j < ndielectrics && i == n && !spm_stop_requested(); j++) {
        spm_pretest_result r;
        run_dielectric(cx, &cols[dielectrics[j]], diel_len[j], n + nconductors + j, o, &r);
        optical_result(optical, dielectrics[j], &r, results);
    }
    free(optical);
    free(cx->truth);
    free(cx->comp0);
    free(cx->lights);
    free(cx->refl);
    free(cx);
    return i;
}
