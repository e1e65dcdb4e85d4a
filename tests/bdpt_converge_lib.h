/* What the bidirectional convergence tests share (test_bdpt_converge.c,
 * test_bdpt_lights.c): K independent renders of each integrator on the CPU
 * reference, bdpt's per pixel and channel mean against the path and the
 * light tracer's within their joint standard error measured from the K
 * renders, and the image's totals too. */
#ifndef SPM_BDPT_CONVERGE_LIB_H
#define SPM_BDPT_CONVERGE_LIB_H
#include <math.h>
#include "integrator_testlib.h"

#define SIDE 16
#define K 32      /* independent renders of each integrator */
#define SPP 48    /* samples per pixel of each */
#define Z_MAX 5.5 /* per pixel and channel, Student's t with K - 1 = 31 degrees:
                     two-sided 5e-6, 0.8 % over the 2 x 768 values (measured: worst
                     4.1; 16 renders of 96 spp saw a light tracer's pixel on the
                     floor under the gold boxes at 6.4, its rare large splats
                     missing from the spread of so few renders) */

typedef it_scene scene;

enum { NP = 3 * SIDE * SIDE };

/* the mean m and its variance v per pixel channel of K renders */
static int moments(const scene *s, int mode, int integrator, double *m, double *v)
{
    static double y[NP];
    for (int i = 0; i < NP; i++)
        m[i] = v[i] = 0.0;
    for (spm_u32 k = 0; k < K; k++) {
        if (it_render_xyz(s, mode, integrator, 7919u * (spm_u32)(integrator + 1) + k, SPP, y))
            return 1;
        for (int i = 0; i < NP; i++)
            m[i] += y[i], v[i] += y[i] * y[i];
    }
    for (int i = 0; i < NP; i++) {
        m[i] /= K;
        v[i] = fmax(0.0, v[i] / K - m[i] * m[i]) / (K - 1);
    }
    return 0;
}

/* pixels 0: the image's totals alone (an integrator whose K renders do not
 * measure its own spread per pixel, see frosted_lamp) */
static void compare(const char *scene_name, const char *other, const double *mb,
                    const double *vb, const double *mo, const double *vo, int pixels)
{
    double worst = 0.0, tot[3][2] = {{0}}, var[3][2] = {{0}}, se[2] = {0.0, 0.0};
    int bad = 0;
    for (int i = 0; i < NP; i++) {
        double z = (mb[i] - mo[i]) / sqrt(vb[i] + vo[i] + 1e-30);
        worst = fmax(worst, isnan(z) ? INFINITY : fabs(z));
        bad += !(fabs(z) <= Z_MAX);
        tot[i % 3][0] += mb[i], var[i % 3][0] += vb[i];
        tot[i % 3][1] += mo[i], var[i % 3][1] += vo[i];
        se[0] += mb[i] > 0.0 ? sqrt(vb[i]) / mb[i] / NP : 0.0;
        se[1] += mo[i] > 0.0 ? sqrt(vo[i]) / mo[i] / NP : 0.0;
    }
    printf("%s %dx%d, %d renders of %d spp: bdpt against %s, worst |z| %.2f; mean relative "
           "standard error bdpt %.2f %%, %s %.2f %%\n",
           scene_name, SIDE, SIDE, K, SPP, other, worst, 100.0 * se[0], other, 100.0 * se[1]);
    for (int c = 0; c < 3; c++) {
        double zt = (tot[c][0] - tot[c][1]) / sqrt(var[c][0] + var[c][1]);
        printf("  %c over the image: bdpt %.5f %s %.5f (%+.3f %%, z %.2f)\n", "XYZ"[c],
               tot[c][0] / (NP / 3), other, tot[c][1] / (NP / 3),
               100.0 * (tot[c][0] / tot[c][1] - 1.0), zt);
        CHECK(tot[c][0] > 0.0 && tot[c][1] > 0.0, "%s: nothing rendered", scene_name);
        CHECK(fabs(zt) <= 4.0, "%s: the image's %c differs from %s's by %.2f standard errors",
              scene_name, "XYZ"[c], other, zt);
    }
    CHECK(!pixels || bad == 0, "%s: %d pixel channels differ from %s's beyond %.1f standard "
                               "errors (worst %.2f)", scene_name, bad, other, Z_MAX, worst);
}

/* bdpt against the light tracer, and (vs_path) against the path tracer: 1
 * per pixel and over the image, 2 over the image alone; in mode (the fluorescent scenes in rgb: its 3 x 3 matrices cost what a plain
 * vertex does, where ml's up to 400 x 400 took the sanitizer build minutes) */
static void converge_mode(const char *path, const char *name, int vs_path, int mode)
{
    static double m[3][NP], v[3][NP];
    scene s;
    if (it_load(&s, path, SIDE))
        return;
    for (int i = vs_path ? 0 : 1; i < 3; i++)
        if (moments(&s, mode, i, m[i], v[i]))
            return;
    if (vs_path)
        compare(name, "path", m[SPM_INTEGRATOR_BDPT], v[SPM_INTEGRATOR_BDPT],
                m[SPM_INTEGRATOR_PATH], v[SPM_INTEGRATOR_PATH], vs_path == 1);
    compare(name, "light", m[SPM_INTEGRATOR_BDPT], v[SPM_INTEGRATOR_BDPT],
            m[SPM_INTEGRATOR_LIGHT], v[SPM_INTEGRATOR_LIGHT], 1);
    it_free(&s);
}

static void converge(const char *path, const char *name, int vs_path)
{
    converge_mode(path, name, vs_path, SPM_MODE_ML);
}

#endif
