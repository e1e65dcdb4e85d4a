/* The Composite Model's pretest against an independent recomputation from the
 * shade tables mlc renders with, and the lanes' XYZ weights against the spikes
 * they stand for. */
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "geometry.h"
#include "spikes.h"
#include "tables.h"
#include "testutil.h"

/* ΔE00 of test against ref, both scaled so ref has Y = 50, against a D65
 * white of Y = 100 (docs/METHODS.md "Choosing levels"). */
static double de(const double ref[3], const double test[3])
{
    double white[3], r[3], s[3], lr[3], ls[3];
    spm_white_d65(white);
    double f = 50.0 / ref[1];
    for (int i = 0; i < 3; i++) {
        r[i] = ref[i] * f;
        s[i] = test[i] * f;
        white[i] *= 100.0;
    }
    spm_xyz_to_lab(r, white, lr);
    spm_xyz_to_lab(s, white, ls);
    return spm_delta_e_2000(lr, ls);
}

/* XYZ of light e times colour c^k (k = 0: the light alone; e < 0: c alone),
 * from the float tables: truth from the 1 nm rows and weights; composite from
 * mlc's level-0 row of e (its smooth part at 1 nm) and its level-l row of c,
 * in 1 nm bins (a level-l bin covers SPM_TRUTH_BINS / SPM_LEVEL_BINS(l) of
 * them) and the lanes, with the 1 nm weights and the lanes' shade weights. */
static void truth_xyz(const spm_tables *t, int e, int c, int k, double xyz[3])
{
    for (int ch = 0; ch < 3; ch++) {
        double s = 0.0;
        for (int i = 0; i < SPM_TRUTH_BINS; i++) {
            double v = e >= 0 ? t->truth[(size_t)e * SPM_TRUTH_BINS + i] : 1.0;
            for (int j = 0; j < k; j++)
                v *= t->truth[(size_t)c * SPM_TRUTH_BINS + i];
            s += v * t->cmf_truth[ch][i];
        }
        xyz[ch] = s;
    }
}

static void composite_xyz(const spm_tables *t, int e, int c, int k, int l, double xyz[3])
{
    const float *re = &t->mlc_lvl[0][(size_t)e * SPM_MLC_STRIDE(0)];
    const float *rc = &t->mlc_lvl[l][(size_t)c * SPM_MLC_STRIDE(l)];
    int width = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
    for (int ch = 0; ch < 3; ch++) {
        double s = 0.0;
        for (int b = 0; b < SPM_TRUTH_BINS; b++) {
            double v = re[b];
            for (int j = 0; j < k; j++)
                v *= rc[b / width];
            s += v * t->cmf_truth[ch][b];
        }
        for (int q = 0; q < t->nspikes; q++) {
            double v = re[SPM_LEVEL_BINS(0) + q];
            for (int j = 0; j < k; j++)
                v *= rc[SPM_LEVEL_BINS(l) + q];
            s += v * t->spike_cmf[ch][q];
        }
        xyz[ch] = s;
    }
}

/* Context A and B of every colour at every level: the error the pretest
 * reports is the one recomputed from the tables (the worst over the lights
 * for a reflectance; an emission on its own). The tables hold floats, the
 * pretest doubles: a relative 6e-8 per factor, at most 6 factors here, moves
 * Lab by ~1e-4 at most; a wrong model of the lanes or of the reference
 * (5 nm instead of truth, a lane's point value) moves it by 0.05 or more. */
static void recompute(const char *scene)
{
    spm_scene sc;
    spm_geometry g;
    spm_tables t;
    spm_pretest_opts po;
    spm_error err;
    char path[1024];
    spm_pretest_defaults(&po);
    if (spm_scene_load(spm_data_path(scene, path, sizeof path), &sc, &err)) {
        CHECK(0, "%s: %s", scene, err.msg);
        return;
    }
    sc.width = 8, sc.height = 6;
    if (spm_geometry_build(&sc, &g, &err) || spm_tables_build(&sc, &po, &t, &err)) {
        CHECK(0, "%s: %s", scene, err.msg);
        return;
    }
    CHECK(t.nspikes > 0, "%s: no spike lanes", scene);
    const int ks[] = {1, 2, 5};
    int checked = 0;
    for (int c = 0; c < sc.ncolours; c++) {
        int is_light = sc.colours[c].s.kind == SPM_KIND_EMISSION;
        for (int l = 0; l < SPM_NUM_LEVELS; l++) {
            for (size_t ki = 0; ki < sizeof ks / sizeof *ks; ki++) {
                int k = ks[ki];
                double worst = 0.0, ref[3], test[3];
                if (is_light) {
                    /* c on its own, at level l */
                    truth_xyz(&t, c, c, 0, ref);
                    const float *rc = &t.mlc_lvl[l][(size_t)c * SPM_MLC_STRIDE(l)];
                    int width = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
                    for (int ch = 0; ch < 3; ch++) {
                        double s = 0.0;
                        for (int b = 0; b < SPM_TRUTH_BINS; b++)
                            s += rc[b / width] * t.cmf_truth[ch][b];
                        for (int q = 0; q < t.nspikes; q++)
                            s += rc[SPM_LEVEL_BINS(l) + q] * t.spike_cmf[ch][q];
                        test[ch] = s;
                    }
                    worst = de(ref, test);
                } else {
                    for (int e = 0; e < sc.ncolours; e++) {
                        if (sc.colours[e].s.kind != SPM_KIND_EMISSION)
                            continue;
                        truth_xyz(&t, e, c, k, ref);
                        composite_xyz(&t, e, c, k, l, test);
                        if (ref[1] > 0.0 && test[1] > 0.0) {
                            double d = de(ref, test);
                            worst = d > worst ? d : worst;
                        }
                    }
                }
                double got = t.mlc_pretest[c].err_k[k - 1][l];
                CHECK(fabs(got - worst) <= 1e-3, "%s: %s level %d k %d: pretest %.5f, tables %.5f",
                      scene, sc.colours[c].name, l, k, got, worst);
                checked++;
            }
        }
    }
    CHECK(checked > 0, "%s: nothing checked", scene);
    spm_tables_free(&t);
    spm_geometry_free(&g);
    spm_scene_free(&sc);
}

/* One light's lanes on their own give the XYZ of the spikes they stand for
 * (the lane weights are means over the spikes, not the CMFs at their
 * centroids, which miss F11's by 0.1-0.6 % per channel): cornell_spiky's F11
 * alone, its spikes split as the tables split them. Float tables: 1e-5. */
static void lanes_alone(void)
{
    spm_scene sc;
    spm_geometry g;
    spm_tables t;
    spm_pretest_opts po;
    spm_error err;
    char path[1024];
    spm_pretest_defaults(&po);
    if (spm_scene_load(spm_data_path("scenes/cornell_spiky.scene", path, sizeof path), &sc, &err) ||
        (sc.width = 8, sc.height = 6, spm_geometry_build(&sc, &g, &err)) ||
        spm_tables_build(&sc, &po, &t, &err)) {
        CHECK(0, "cornell_spiky: %s", err.msg);
        return;
    }
    int e = -1;
    for (int c = 0; c < sc.ncolours; c++)
        if (sc.colours[c].s.kind == SPM_KIND_EMISSION)
            e = c;
    spm_spectrum smooth;
    spm_spike spikes[SPM_MAX_SPIKES];
    int ns = 0;
    spm_spike_split(&sc.colours[e].s, &smooth, spikes, SPM_MAX_SPIKES, &ns, NULL);
    CHECK(ns == t.nspikes, "F11: %d spikes, %d lanes", ns, t.nspikes);
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    const float *row = &t.mlc_lvl[0][(size_t)e * SPM_MLC_STRIDE(0)];
    for (int ch = 0; ch < 3; ch++) {
        double want = 0.0, got = 0.0;
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            want += (sc.colours[e].s.nm1[i] - smooth.nm1[i]) * w[ch][i];
        for (int q = 0; q < t.nspikes; q++)
            got += row[SPM_LEVEL_BINS(0) + q] * t.spike_cmf[ch][q];
        CHECK(fabs(got - want) <= 1e-5 * fabs(want), "F11 lanes, XYZ channel %d: %.7g, spikes %.7g",
              ch, got, want);
    }
    spm_tables_free(&t);
    spm_geometry_free(&g);
    spm_scene_free(&sc);
}

int main(void)
{
    spm_error err;
    spm_quiet_warnings = 1;
    if (spm_cmf_init(&err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    recompute("scenes/cornell_spiky.scene");
    recompute("scenes/metameric.scene");
    recompute("scenes/narrowline.scene");
    lanes_alone();
    TEST_END();
}
