/* The Composite Model's pretest against an independent recomputation from the
 * shade tables mlc renders with, and the lanes' XYZ weights against the spikes
 * they stand for. */
#include <complex.h>
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

/* The complex Fresnel reflectance, unpolarised (Snell's law in complex form;
 * an independent formula from the one the renderer uses). */
static double fresnel_complex(double eta, double k, double c)
{
    double complex n = eta + I * k;
    double complex ct = csqrt(1.0 - (1.0 - c * c) / (n * n));
    double complex rs = (c - n * ct) / (c + n * ct), rp = (n * c - ct) / (n * c + ct);
    return 0.5 * (creal(rs * conj(rs)) + creal(rp * conj(rp)));
}

/* XYZ of light e times the Fresnel of eta colour ce and k colour ck at cosine
 * c, both from the float tables: truth from the 1 nm rows; level l from e's
 * level-0 composite row and F of ce's and ck's level-l rows value by value
 * (each smooth bin over its 1 nm bins, then each lane from the lane's eta
 * and k, as the shade stage computes it). as_refl: the composite product
 * with eta's row itself as the factor, as a reflectance would be judged. */
static void fresnel_xyz(const spm_tables *t, int e, int ce, int ck, double c, int l, int truth,
                        int as_refl, double xyz[3])
{
    const float *re = &t->mlc_lvl[0][(size_t)e * SPM_MLC_STRIDE(0)];
    const float *r1 = &t->mlc_lvl[l][(size_t)ce * SPM_MLC_STRIDE(l)];
    const float *r2 = &t->mlc_lvl[l][(size_t)ck * SPM_MLC_STRIDE(l)];
    int width = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
    for (int ch = 0; ch < 3; ch++) {
        double s = 0.0;
        for (int b = 0; b < SPM_TRUTH_BINS; b++) {
            double f;
            if (truth)
                f = fresnel_complex(t->truth[(size_t)ce * SPM_TRUTH_BINS + b],
                                    t->truth[(size_t)ck * SPM_TRUTH_BINS + b], c);
            else
                f = as_refl ? r1[b / width] : fresnel_complex(r1[b / width], r2[b / width], c);
            s += (truth ? t->truth[(size_t)e * SPM_TRUTH_BINS + b] : re[b]) * f *
                 t->cmf_truth[ch][b];
        }
        for (int q = 0; q < t->nspikes && !truth; q++) {
            double f1 = r1[SPM_LEVEL_BINS(l) + q], f2 = r2[SPM_LEVEL_BINS(l) + q];
            s += re[SPM_LEVEL_BINS(0) + q] * (as_refl ? f1 : fresnel_complex(f1, f2, c)) *
                 t->spike_cmf[ch][q];
        }
        xyz[ch] = s;
    }
}

/* A conductor's eta and k are judged by the Fresnel the shade stage computes
 * from them, not as reflectances: context A's error (one occurrence, the
 * worst over the scene's lights and the six cosines) of each conductor's eta
 * and k colour, recomputed from the float tables with the complex Fresnel,
 * is the pretest's (tolerance as recompute()'s, the Fresnel adding a few
 * float roundings of eta and k). The same error with eta taken as a
 * reflectance must differ somewhere (by more than 0.05), so the check tells
 * the two judgements apart. A colour that two conductors of different pairs
 * share is left out (it takes the finer level, and the first pair's errors);
 * the smooth and the rough metal of one pair are one check each. */
static void conductor_fresnel(const char *scene)
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
    const double cosines[] = {1.0, 0.8, 0.6, 0.4, 0.2, 0.05};
    int checked = 0;
    double apart = 0.0, off = 0.0;
    for (int m = 0; m < sc.nmaterials; m++) {
        const spm_scene_material *mt = &sc.materials[m];
        if (mt->type != SPM_MAT_CONDUCTOR)
            continue;
        int shared = 0;
        for (int o = 0; o < sc.nmaterials; o++)
            shared |= sc.materials[o].type == SPM_MAT_CONDUCTOR &&
                      (sc.materials[o].refl == mt->refl) != (sc.materials[o].col2 == mt->col2);
        if (shared)
            continue;
        for (int l = 0; l < SPM_NUM_LEVELS; l++) {
            double worst = 0.0, worst_refl = 0.0;
            for (int e = 0; e < sc.ncolours; e++) {
                if (sc.colours[e].s.kind != SPM_KIND_EMISSION)
                    continue;
                for (int a = 0; a < 6; a++) {
                    double ref[3], test[3];
                    fresnel_xyz(&t, e, mt->refl, mt->col2, cosines[a], l, 1, 0, ref);
                    fresnel_xyz(&t, e, mt->refl, mt->col2, cosines[a], l, 0, 0, test);
                    if (ref[1] > 0.0 && test[1] > 0.0)
                        worst = fmax(worst, de(ref, test));
                }
                double ref[3], test[3];
                truth_xyz(&t, e, mt->refl, 1, ref);
                fresnel_xyz(&t, e, mt->refl, mt->col2, 1.0, l, 0, 1, test);
                if (ref[1] > 0.0 && test[1] > 0.0)
                    worst_refl = fmax(worst_refl, de(ref, test));
            }
            for (int q = 0; q < 2; q++) {
                int c = q ? mt->col2 : mt->refl;
                double got = t.mlc_pretest[c].err_k[0][l];
                off = fmax(off, fabs(got - worst));
                CHECK(fabs(got - worst) <= 1e-3, "%s: %s level %d: pretest %.5f, Fresnel %.5f", scene,
                      sc.colours[c].name, l, got, worst);
                checked++;
            }
            apart = fmax(apart, fabs(worst - worst_refl));
        }
    }
    printf("%s: %d conductor colour levels checked (pretest against tables: %.2g at most); "
           "Fresnel and reflectance judgements differ by up to %.3f\n", scene, checked, off, apart);
    CHECK(checked > 0, "%s: no conductor checked", scene);
    CHECK(apart > 0.05, "%s: Fresnel and reflectance judgements too alike (%g)", scene, apart);
    spm_tables_free(&t);
    spm_geometry_free(&g);
    spm_scene_free(&sc);
}

/* XYZ of light e times the transmittance exp(-sigma d) of sigma colour cs
 * over length d, from the float tables: truth from the 1 nm rows; level l
 * from e's level-0 composite row and exp of cs's level-l row value by value
 * (each smooth bin over its 1 nm bins, then each lane from the lane's
 * sigma, as the shade stage computes it). as_refl: the composite product
 * with sigma's row itself as the factor, as a reflectance would be judged
 * (truth likewise with the 1 nm sigma). */
static void transmit_xyz(const spm_tables *t, int e, int cs, double d, int l, int truth,
                         int as_refl, double xyz[3])
{
    const float *re = &t->mlc_lvl[0][(size_t)e * SPM_MLC_STRIDE(0)];
    const float *rs = &t->mlc_lvl[l][(size_t)cs * SPM_MLC_STRIDE(l)];
    int width = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
    for (int ch = 0; ch < 3; ch++) {
        double s = 0.0;
        for (int b = 0; b < SPM_TRUTH_BINS; b++) {
            double sg = truth ? t->truth[(size_t)cs * SPM_TRUTH_BINS + b] : rs[b / width];
            s += (truth ? t->truth[(size_t)e * SPM_TRUTH_BINS + b] : re[b]) *
                 (as_refl ? sg : exp(-sg * d)) * t->cmf_truth[ch][b];
        }
        for (int q = 0; q < t->nspikes && !truth; q++) {
            double sg = rs[SPM_LEVEL_BINS(l) + q];
            s += re[SPM_LEVEL_BINS(0) + q] * (as_refl ? sg : exp(-sg * d)) * t->spike_cmf[ch][q];
        }
        xyz[ch] = s;
    }
}

/* A dielectric's absorption sigma is judged by the transmittance the shade
 * stage computes from it, not as a reflectance: context A's error (one
 * occurrence, the worst over the scene's lights and the lengths dmax / 32,
 * dmax / 16, ..., dmax, dmax the diagonal of the material's bounding box,
 * recomputed here) of each sigma colour, recomputed from the float tables,
 * is the pretest's (tolerance as recompute()'s: exp adds a relative float
 * rounding of sigma d, below 1e-6 here). The same error with sigma taken as
 * a reflectance must differ somewhere by more than 0.05, so the check tells
 * the two judgements apart. scene: a bundled scene, or (spiky) glass.scene
 * lit by F11, written here, whose lanes the transmittance passes too. */
static void dielectric_transmittance(const char *scene, int spiky)
{
    spm_scene sc;
    spm_geometry g;
    spm_tables t;
    spm_pretest_opts po;
    spm_error err;
    char path[1024], tmp[] = "/tmp/specmip-mlcdiel-XXXXXX";
    spm_pretest_defaults(&po);
    spm_data_path(scene, path, sizeof path);
    if (spiky) {
        if (!mkdtemp(tmp)) {
            CHECK(0, "mkdtemp");
            return;
        }
        char cmd[3000];
        snprintf(cmd, sizeof cmd,
                 "sed -e '/^spectrum equal/a spectrum f11 file illuminant_F11.csv' "
                 "-e 's/emit equal 1000/emit f11 1000/' '%s' > %s/spiky.scene && "
                 "cp \"$(dirname '%s')/materials_sphere.ply\" %s/",
                 path, tmp, path, tmp);
        CHECK(system(cmd) == 0, "%s", cmd);
        snprintf(path, sizeof path, "%s/spiky.scene", tmp);
    }
    int rc = spm_scene_load(path, &sc, &err);
    if (spiky) {
        char cmd[200];
        snprintf(cmd, sizeof cmd, "rm -rf %s", tmp);
        CHECK(system(cmd) == 0, "%s", cmd);
    }
    if (rc) {
        CHECK(0, "%s: %s", scene, err.msg);
        return;
    }
    sc.width = 8, sc.height = 6;
    if (spm_geometry_build(&sc, &g, &err) || spm_tables_build(&sc, &po, &t, &err)) {
        CHECK(0, "%s: %s", scene, err.msg);
        return;
    }
    CHECK(!spiky || t.nspikes > 0, "%s, F11: no spike lanes", scene);
    int checked = 0;
    double apart = 0.0, off = 0.0;
    for (int m = 0; m < sc.nmaterials; m++) {
        const spm_scene_material *mt = &sc.materials[m];
        if (mt->type != SPM_MAT_DIELECTRIC || mt->col2 < 0)
            continue;
        /* the longest segment inside: the diagonal of the material's box */
        double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        for (int i = 0; i < sc.ntris; i++)
            for (int v = 0; sc.tris[i].material == m && v < 3; v++)
                for (int k = 0; k < 3; k++) {
                    lo[k] = fmin(lo[k], sc.tris[i].p[v][k]);
                    hi[k] = fmax(hi[k], sc.tris[i].p[v][k]);
                }
        double dmax = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
        int shared = 0;
        for (int o = 0; o < sc.nmaterials; o++)
            shared |= o != m && sc.materials[o].type == SPM_MAT_DIELECTRIC &&
                      sc.materials[o].col2 == mt->col2;
        if (shared)
            continue;
        for (int l = 0; l < SPM_NUM_LEVELS; l++) {
            double worst = 0.0, worst_refl = 0.0;
            for (int e = 0; e < sc.ncolours; e++) {
                if (sc.colours[e].s.kind != SPM_KIND_EMISSION)
                    continue;
                for (double d = dmax / 32; d <= dmax * 1.0000001; d *= 2) {
                    double ref[3], test[3];
                    transmit_xyz(&t, e, mt->col2, d, l, 1, 0, ref);
                    transmit_xyz(&t, e, mt->col2, d, l, 0, 0, test);
                    if (ref[1] > 0.0 && test[1] > 0.0)
                        worst = fmax(worst, de(ref, test));
                }
                double ref[3], test[3];
                transmit_xyz(&t, e, mt->col2, 0, l, 1, 1, ref);
                transmit_xyz(&t, e, mt->col2, 0, l, 0, 1, test);
                if (ref[1] > 0.0 && test[1] > 0.0)
                    worst_refl = fmax(worst_refl, de(ref, test));
            }
            double got = t.mlc_pretest[mt->col2].err_k[0][l];
            off = fmax(off, fabs(got - worst));
            CHECK(fabs(got - worst) <= 1e-3, "%s: %s level %d: pretest %.5f, transmittance %.5f",
                  scene, sc.colours[mt->col2].name, l, got, worst);
            checked++;
            apart = fmax(apart, fabs(worst - worst_refl));
        }
    }
    printf("%s%s: %d absorption colour levels checked (pretest against tables: %.2g at most); "
           "transmittance and reflectance judgements differ by up to %.3f\n", scene,
           spiky ? " under F11" : "", checked, off, apart);
    CHECK(checked > 0, "%s: no dielectric checked", scene);
    CHECK(apart > 0.05, "%s: transmittance and reflectance judgements too alike (%g)", scene, apart);
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
    conductor_fresnel("scenes/metals.scene");
    conductor_fresnel("scenes/copper_sodium.scene");
    dielectric_transmittance("scenes/glass.scene", 0);
    dielectric_transmittance("scenes/glass_deep.scene", 0);
    dielectric_transmittance("scenes/glass.scene", 1);
    TEST_END();
}
