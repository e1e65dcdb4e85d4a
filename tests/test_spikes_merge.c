/* The scene-wide spike pattern table (spm_spike_pattern_merge): several
 * spiky lights with different line patterns share at most SPM_MAX_SPIKES
 * lanes, every light keeps its energy, and the choice of lanes does not
 * depend on the units a light's data came in. */
#include "colour.h"
#include "csv.h"
#include "spikes.h"
#include "testutil.h"
#include <stdlib.h>
#include <string.h>

#define NL 6
static const char *files[NL] = {
    "spectra/illuminant_F11.csv",          "spectra/illuminant_F2.csv",
    "spectra/lightsource_nist_mercury.csv", "spectra/illuminant_HP1.csv",
    "spectra/lightsource_nist_metal_halide.csv", "spectra/illuminant_D65.csv",
};

typedef struct {
    spm_spectrum in, smooth, smooth_split;
    spm_spike sp[SPM_MAX_SPIKES];
    int n;
} lamp;

static double energy(const spm_spectrum *s)
{
    double e = 0.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        e += s->nm1[i];
    return e;
}

static void setup(lamp *lp, spm_spike_light *lights, double scale)
{
    for (int l = 0; l < NL; l++) {
        char path[1024];
        spm_error err;
        if (spm_spectrum_load(spm_data_path(files[l], path, sizeof path), NULL,
                              SPM_KIND_EMISSION, &lp[l].in, &err)) {
            fprintf(stderr, "%s\n", err.msg);
            exit(1);
        }
        if (l == 0)
            spm_spectrum_scale(&lp[l].in, scale);
        spm_spike_split(&lp[l].in, &lp[l].smooth, lp[l].sp, SPM_MAX_SPIKES, &lp[l].n, NULL);
        lp[l].smooth_split = lp[l].smooth;
        double xyz[3];
        spm_xyz_emission(&lp[l].in, xyz);
        lights[l] = (spm_spike_light){.in = &lp[l].in, .smooth = &lp[l].smooth,
                                      .spikes = lp[l].sp, .nspikes = lp[l].n,
                                      .luminance = xyz[1]};
    }
}

static int lane_near(const double *wl, int n, double at)
{
    for (int k = 0; k < n; k++)
        if (fabs(wl[k] - at) < 1.0)
            return k;
    return -1;
}

/* Energy kept per light; smooth is the split's smooth part except over the
 * bins of spikes without a lane, where it is the input again. */
static void check_lights(const char *what, const lamp *lp, const spm_spike_light *lights,
                         int nlanes, const double *wl)
{
    for (int k = 0; k < nlanes; k++)
        CHECK(wl[k] > SPM_LAMBDA_MIN && wl[k] < SPM_LAMBDA_MAX && (k == 0 || wl[k] > wl[k - 1]),
              "%s: lane %d at %.2f nm in range and increasing", what, k, wl[k]);
    for (int l = 0; l < NL; l++) {
        double lanes = 0.0, kept = 0.0;
        for (int k = 0; k < nlanes; k++)
            lanes += lights[l].lane_area[k];
        for (int s = 0; s < lp[l].n; s++) {
            const spm_spike *sp = &lp[l].sp[s];
            int as_split = 1, restored = 1;
            for (int i = sp->first; i <= sp->last; i++) {
                as_split &= lp[l].smooth.nm1[i] == lp[l].smooth_split.nm1[i];
                restored &= lp[l].smooth.nm1[i] == lp[l].in.nm1[i];
            }
            CHECK(as_split || restored, "%s: %s spike at %.1f left as split or folded back exactly",
                  what, files[l], sp->wl);
            if (as_split) {
                kept += sp->area;
                /* its lane is the mean of centroids within 1 nm of the first */
                CHECK(lane_near(wl, nlanes, sp->wl) >= 0, "%s: %s spike at %.1f has a lane", what,
                      files[l], sp->wl);
            }
        }
        /* 1e-12 relative: rounding of sums of a few hundred doubles */
        double e = energy(&lp[l].in);
        CHECK(fabs(e - energy(&lp[l].smooth) - lanes) <= 1e-12 * e,
              "%s: %s energy %.17g = smooth %.17g + lanes %.17g", what, files[l], e,
              energy(&lp[l].smooth), lanes);
        CHECK(fabs(lanes - kept) <= 1e-12 * e, "%s: %s lanes %.17g hold its kept spikes %.17g",
              what, files[l], lanes, kept);
    }
}

int main(void)
{
    spm_error err;
    spm_quiet_warnings = 1;
    if (spm_cmf_init(&err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    static lamp lp[NL];
    spm_spike_light lights[NL];
    double wl[SPM_MAX_SPIKES];

    /* All lanes the lights need, or SPM_MAX_SPIKES of them. */
    setup(lp, lights, 1.0);
    int total = 0;
    for (int l = 0; l < NL; l++)
        total += lp[l].n;
    int n = spm_spike_pattern_merge(lights, NL, 1.0, SPM_MAX_SPIKES, wl);
    printf("%d spikes in %d lights -> %d lanes\n", total, NL, n);
    CHECK(n >= 1 && n <= SPM_MAX_SPIKES && n <= total, "%d lanes", n);
    check_lights("16 lanes", lp, lights, n, wl);
    CHECK(lp[5].n == 0, "D65 brings no spike");
    /* F11's 435.9 and F2's 435.8 nm mercury lines share one lane (< 1 nm apart) */
    int hg = lane_near(wl, n, 435.8);
    CHECK(hg >= 0 && lights[0].lane_area[hg] > 0 && lights[1].lane_area[hg] > 0,
          "one 436 nm lane for F11 and F2");

    /* Fewer lanes than lines: the strongest (per luminance) win, the rest
     * fold back into their lights' smooth parts. */
    setup(lp, lights, 1.0);
    int n3 = spm_spike_pattern_merge(lights, NL, 1.0, 3, wl);
    CHECK(n3 == 3, "3 lanes, got %d", n3);
    check_lights("3 lanes", lp, lights, n3, wl);
    double wl3[3];
    memcpy(wl3, wl, sizeof wl3);

    /* A light's units do not change the choice: F11 x 1000 (its luminance
     * scales with it) gives the same lanes and 1000 x its lane areas. */
    double area3[3];
    memcpy(area3, lights[0].lane_area, sizeof area3);
    setup(lp, lights, 1000.0);
    int m3 = spm_spike_pattern_merge(lights, NL, 1.0, 3, wl);
    CHECK(m3 == 3, "3 lanes again");
    for (int k = 0; k < 3 && m3 == 3; k++) {
        CHECK_NEAR(wl[k], wl3[k], 1e-9, "lane wavelength independent of F11's units");
        CHECK_NEAR(lights[0].lane_area[k], 1000.0 * area3[k], 1e-9 * 1000.0 * (area3[k] + 1),
                   "F11 lane area scales with it");
    }
    check_lights("3 lanes, F11 x 1000", lp, lights, m3, wl);

    /* No spiky light at all: no lanes, nothing changes. */
    setup(lp, lights, 1.0);
    int n0 = spm_spike_pattern_merge(lights + 5, 1, 1.0, SPM_MAX_SPIKES, wl);
    CHECK(n0 == 0, "D65 alone: %d lanes", n0);
    TEST_END();
}
