/* The bidirectional integrator's MIS weights (host/cpu/refcpu_bdpt.h
 * spm_ref_bdpt_mis, pbrt-v4's MISWeight with remap0): over random paths
 * x_0 (the lens) .. x_k (a light), their densities per unit area drawn
 * log-uniformly over 1e-3 .. 1e3 from either end, some surface vertices
 * deltas (a mirror, smooth glass: the densities of sampling through them 0)
 * and some lights points, the weights of the strategies (s, t), s + t = k + 1,
 * t >= 1, that can make the path (no joined vertex a delta, s = 0 not at a
 * point light, not (1, 1)) sum to 1. Each strategy's densities are the
 * path's own, cut at s; a weight is independent of how the strategy found
 * the path, so this is the property the estimator needs to be unbiased.
 * Some deltas are dispersive glass: the path is then one wavelength's (the
 * sample's committed bin, shared by both subpaths), and the densities of
 * the vertices sampled through it scale with the bin's index (the
 * refraction's solid-angle factor eta^2 when entering); each path's weights
 * are taken at one of NLAM bins and must sum to 1 there. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include "refcpu_bdpt.h"
#include "testutil.h"

#define NPATHS 20000
#define KMAX 9
#define NLAM 3

static uint64_t rnd(uint64_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return *s;
}

static double uni(uint64_t *s)
{
    return (double)(rnd(s) >> 11) * 0x1.0p-53;
}

/* a random path of k + 1 vertices: cam[i] the density of x_i sampled from
 * the camera's end, lit[i] from the light's; delta[i]; the light a point */
typedef struct {
    int k, point;
    float cam[KMAX + 1], lit[KMAX + 1];
    int delta[KMAX + 1], disp[KMAX + 1];
} path;

static void random_path(uint64_t *s, int k, path *p)
{
    p->k = k;
    p->point = uni(s) < 0.3;
    for (int i = 0; i <= k; i++) {
        p->cam[i] = (float)pow(10.0, 6.0 * uni(s) - 3.0);
        p->lit[i] = (float)pow(10.0, 6.0 * uni(s) - 3.0);
        p->delta[i] = i > 0 && i < k && uni(s) < 0.25;
        p->disp[i] = p->delta[i] && uni(s) < 0.5;
    }
    for (int i = 1; i < k; i++)
        if (p->delta[i]) /* a delta lobe's direction has no density */
            p->cam[i + 1] = 0.0f, p->lit[i - 1] = 0.0f;
}

/* strategy (s, t) can make path p */
static int possible(const path *p, int s, int t)
{
    if (s == 1 && t == 1)
        return 0;
    if (s == 0)
        return !p->point;
    if (t > 1 && p->delta[t - 1])
        return 0;
    return !(s > 1 && p->delta[t]);
}

static float weight(const path *p, int s, int t)
{
    spm_bdpt_pdf z[KMAX + 1], y[KMAX + 1];
    for (int i = 0; i < t; i++)
        z[i] = (spm_bdpt_pdf){p->cam[i], p->lit[i], p->delta[i]};
    for (int i = 0; i < s; i++) {
        int x = p->k - i;
        y[i] = (spm_bdpt_pdf){p->lit[x], p->cam[x], p->delta[x]};
    }
    return spm_ref_bdpt_mis(z, t, y, s, p->point);
}

/* path p at bin l: beyond each dispersive vertex the densities of the
 * vertices sampled through it scaled by eta_l^2 (N-SF11's 1.78 .. 1.82) */
static void at_bin(const path *p, int l, path *q)
{
    *q = *p;
    float eta = 1.78f + 0.02f * (float)l, f = eta * eta;
    for (int i = 1; i < p->k; i++)
        if (p->disp[i]) {
            for (int j = i + 1; j <= p->k; j++)
                q->cam[j] *= f;
            for (int j = 0; j < i; j++)
                q->lit[j] /= f;
        }
}

int main(void)
{
    uint64_t seed = 0x2545F4914F6CDD1Dull;
    int checked = 0, none = 0, bad = 0, with_delta = 0, with_point = 0, with_disp = 0;
    double worst = 0.0;
    for (int n = 0; n < NPATHS; n++) {
        path p0, p;
        random_path(&seed, 1 + (int)(rnd(&seed) % KMAX), &p0);
        at_bin(&p0, n % NLAM, &p);
        double sum = 0.0;
        int ways = 0;
        for (int t = 1; t <= p.k + 1; t++) {
            int s = p.k + 1 - t;
            if (!possible(&p, s, t))
                continue;
            float w = weight(&p, s, t);
            CHECK(w >= 0.0f && w <= 1.0f, "a weight %g outside [0, 1]", (double)w);
            sum += w;
            ways++;
        }
        if (!ways) { /* e.g. a point light seen only through a mirror: no strategy */
            none++;
            continue;
        }
        checked++;
        for (int i = 1; i < p.k; i++)
            with_delta += p.delta[i], with_disp += p.disp[i];
        with_point += p.point;
        worst = fmax(worst, isnan(sum) ? INFINITY : fabs(sum - 1.0));
        /* measured: the float ratios' rounding leaves at most 4e-7 */
        bad += !(fabs(sum - 1.0) < 1e-5);
    }
    printf("%d random paths: weights summed over %d (%d no strategy makes), %d delta vertices "
           "(%d dispersive, at %d bins), %d point lights; worst |sum - 1| %.2g\n",
           NPATHS, checked, none, with_delta, with_disp, NLAM, with_point, worst);
    CHECK(checked > NPATHS / 2 && with_delta > 1000 && with_disp > 500 && with_point > 1000,
          "too few paths checked: %d", checked);
    CHECK(bad == 0, "%d paths whose weights do not sum to 1 (worst %.3g)", bad, worst);
    TEST_END();
}
