/* The camera contract of the CPU reference (host/cpu/refcpu_camera.c; the
 * kernels' twin, kernels/camera.clh, renders the same pixels: cli_camera.sh)
 * against closed forms and Monte Carlo integrals of its own densities:
 *  - a ray's film point (We's) is the one camera_ray was given;
 *  - ∫ pdf_dir d omega = 1 over the sphere from any lens point, and
 *    ∫∫ We cos theta dA_lens d omega = 1 (pbrt-v4's normalisation);
 *  - We = pdf_pos pdf_dir / cos theta at any ray (a light tracer's splat);
 *  - sample_Wi: E[1 / pdf] over the lens is the solid angle the lens disk
 *    subtends, 2 pi (1 - d / sqrt(d^2 + r^2)) on its axis; its density in
 *    area on the lens is pdf_We's pdf_pos;
 *  - the circle of confusion of a point at depth z is D |1/F - 1/z| wide on
 *    the film plane at unit distance (the thin-lens formula);
 *  - the field of view's axis and the orthographic width.
 * Monte Carlo tolerances: 5 standard errors of the estimate, each estimate's
 * standard error itself checked below 1 % (so noise cannot pass a wrong
 * integral). */
#include <math.h>
#include <string.h>
#include "geometry.h"
#include "refcpu_camera.h"
#include "scene.h"
#include "testutil.h"

static unsigned long long rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
    unsigned long long z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return (double)((z ^ (z >> 31)) >> 11) * (1.0 / 9007199254740992.0);
}

static void sphere_dir(float d[3])
{
    double z = 1.0 - 2.0 * rnd(), phi = 2.0 * M_PI * rnd(), r = sqrt(1.0 - z * z);
    d[0] = (float)(r * cos(phi)), d[1] = (float)(r * sin(phi)), d[2] = (float)z;
}

/* A camera from a scene's fields, as the renderer resolves it. */
static spm_camera make(int w, int h, double fov, int axis, double aperture, double focus)
{
    spm_scene s;
    memset(&s, 0, sizeof s);
    float eye[3] = {0.3f, -0.2f, 1.5f}, dir[3] = {0.48f, 0.6f, 0.64f}, up[3] = {0.0f, 0.0f, 1.0f};
    memcpy(s.eye, eye, sizeof eye);
    memcpy(s.dir, dir, sizeof dir);
    /* up normal to dir: up - (up . dir) dir, normalised */
    double k = up[2] * dir[2], n = 0.0, u[3];
    for (int i = 0; i < 3; i++)
        u[i] = up[i] - k * dir[i], n += u[i] * u[i];
    for (int i = 0; i < 3; i++)
        s.up[i] = (float)(u[i] / sqrt(n));
    s.width = w, s.height = h;
    s.fov_deg = (float)fov, s.fov_axis = axis;
    s.aperture = (float)aperture, s.focus = (float)focus;
    return spm_camera_of_scene(&s);
}

typedef struct {
    double sum, sum2;
    long n;
} mc;
static void mc_add(mc *m, double v) { m->sum += v, m->sum2 += v * v, m->n++; }
static void mc_check(const mc *m, double want, const char *what)
{
    double mean = m->sum / m->n, var = m->sum2 / m->n - mean * mean;
    double se = sqrt(var / m->n);
    CHECK(se < 0.01 * want, "%s: standard error %g too large to judge", what, se);
    CHECK(fabs(mean - want) <= 5.0 * se, "%s: %.6g, want %.6g (standard error %.3g)", what, mean,
          want, se);
}

static void test_round_trip(const spm_camera *c, const char *name)
{
    double worst = 0.0;
    for (int i = 0; i < 10000; i++) {
        float cx = (float)(2.0 * rnd() - 1.0), cy = (float)(2.0 * rnd() - 1.0), o[3], d[3], film[2];
        spm_ref_camera_ray(c, cx, cy, (float)rnd(), (float)rnd(), o, d);
        float we = spm_ref_camera_We(c, o, d, film);
        /* the film's y runs up the image, as camera_ray's cy */
        double e = fmax(fabs(film[0] - cx), fabs(film[1] - cy));
        worst = we > 0.0f ? fmax(worst, e) : 1.0;
    }
    /* float rounding: measured below 2e-6 */
    CHECK(worst < 2e-5, "%s: a ray's film point is off by %g from the one it was made for", name,
          worst);
}

static void test_normalisation(const spm_camera *c, const char *name)
{
    mc dir = {0}, we = {0};
    double lens_area = c->lens_radius > 0.0f ? M_PI * c->lens_radius * c->lens_radius : 1.0;
    double worst = 0.0;
    for (int i = 0; i < 2000000; i++) {
        float o[3], d[3], film[2], pp, pd, tmp[3];
        spm_ref_camera_ray(c, 0.0f, 0.0f, (float)rnd(), (float)rnd(), o, tmp); /* a lens point */
        sphere_dir(d);
        spm_ref_camera_pdf_We(c, o, d, &pp, &pd);
        mc_add(&dir, pd * 4.0 * M_PI);
        float w = spm_ref_camera_We(c, o, d, film);
        double cos_t = d[0] * c->dir[0] + d[1] * c->dir[1] + d[2] * c->dir[2];
        mc_add(&we, w * cos_t * 4.0 * M_PI * lens_area);
        if (w > 0.0f)
            worst = fmax(worst, fabs(w - pp * pd / cos_t) / w);
    }
    char what[160];
    snprintf(what, sizeof what, "%s: integral of pdf_dir over the sphere", name);
    mc_check(&dir, 1.0, what);
    snprintf(what, sizeof what, "%s: integral of We cos over lens and sphere", name);
    mc_check(&we, 1.0, what);
    CHECK(worst < 1e-5, "%s: We differs from pdf_pos pdf_dir / cos by %g", name, worst);
}

/* sample_Wi from a point on the lens axis at distance dist: E[1/pdf] is the
 * lens disk's solid angle; each sample's area density is pdf_pos. */
static void test_sample_wi(const spm_camera *c, double dist, const char *name)
{
    float p[3];
    for (int i = 0; i < 3; i++)
        p[i] = c->eye[i] + (float)dist * c->dir[i];
    double r = c->lens_radius;
    mc inv = {0};
    double worst = 0.0;
    int seen = 1;
    for (int i = 0; i < 200000; i++) {
        float wi[3], dd, pdf, film[2], back[3], pp, pd;
        float we = spm_ref_camera_sample_Wi(c, p, (float)rnd(), (float)rnd(), wi, &dd, &pdf, film);
        mc_add(&inv, 1.0 / pdf);
        float lens[3];
        for (int k = 0; k < 3; k++)
            lens[k] = p[k] + dd * wi[k], back[k] = -wi[k];
        spm_ref_camera_pdf_We(c, lens, back, &pp, &pd);
        double cos_l = fabs(wi[0] * c->dir[0] + wi[1] * c->dir[1] + wi[2] * c->dir[2]);
        worst = fmax(worst, fabs(pdf * cos_l / (dd * dd) - pp) / pp);
        seen = seen && we > 0.0f;
    }
    char what[160];
    snprintf(what, sizeof what, "%s: E[1/pdf] of sample_Wi, the lens's solid angle", name);
    mc_check(&inv, 2.0 * M_PI * (1.0 - dist / sqrt(dist * dist + r * r)), what);
    CHECK(seen, "%s: sample_Wi: a lens point does not see a point on the axis", name);
    CHECK(worst < 1e-4, "%s: sample_Wi's density in lens area is off pdf_pos by %g", name, worst);
}

/* The thin-lens circle of confusion: a point at depth z seen through the
 * lens's rim spans D |1/F - 1/z| / tan_half of the film's x (film units
 * of half the image width). */
static void test_confusion(const spm_camera *c, double z, const char *name)
{
    float x[3];
    for (int i = 0; i < 3; i++)
        x[i] = c->eye[i] + (float)z * c->dir[i];
    double lo = 1e9, hi = -1e9;
    for (int i = 0; i < 720; i++) {
        /* the rim: the concentric map's square boundary */
        double t = i / 720.0 * 4.0;
        float lu = t < 1 ? (float)t : t < 2 ? 1.0f : t < 3 ? (float)(3 - t) : 0.0f;
        float lv = t < 1 ? 0.0f : t < 2 ? (float)(t - 1) : t < 3 ? 1.0f : (float)(4 - t);
        float o[3], d[3], tmp[3], film[2];
        spm_ref_camera_ray(c, 0.0f, 0.0f, lu, lv, o, tmp);
        double n = 0.0;
        for (int k = 0; k < 3; k++)
            d[k] = x[k] - o[k], n += (double)d[k] * d[k];
        for (int k = 0; k < 3; k++)
            d[k] = (float)(d[k] / sqrt(n));
        spm_ref_camera_We(c, o, d, film);
        lo = fmin(lo, film[0]), hi = fmax(hi, film[0]);
    }
    double want = 2.0 * c->lens_radius * fabs(1.0 / c->focus - 1.0 / z) / c->tan_half;
    /* float rounding: measured below 1e-6 relative, 6e-7 film units in focus */
    CHECK(fabs((hi - lo) - want) <= 1e-4 * want + 1e-5,
          "%s: depth %g: circle of confusion %g film units, the thin-lens formula %g", name, z,
          hi - lo, want);
}

static void test_axes(void)
{
    /* fov 40 across the height of 128 x 64: the horizontal tan_half is twice tan 20 */
    spm_camera v = make(128, 64, 40, SPM_FOV_VERTICAL, 0, 1);
    CHECK_NEAR(v.tan_half, 2.0 * tan(20.0 * M_PI / 180.0), 1e-6, "vertical fov 40 at 2:1");
    spm_camera hz = make(128, 64, 40, SPM_FOV_HORIZONTAL, 0, 1);
    CHECK_NEAR(hz.tan_half, tan(20.0 * M_PI / 180.0), 1e-6, "horizontal fov 40");
    spm_camera sh = make(64, 128, 40, SPM_FOV_SHORTER, 0, 1);
    CHECK_NEAR(sh.tan_half, tan(20.0 * M_PI / 180.0), 1e-6, "shorter side (the width) fov 40");
    spm_scene s;
    memset(&s, 0, sizeof s);
    s.dir[2] = 1.0f, s.width = 128, s.height = 64, s.fov_axis = SPM_FOV_VERTICAL;
    s.projection = SPM_PROJ_ORTHOGRAPHIC, s.ortho_size = 2.0f;
    spm_camera o = spm_camera_of_scene(&s);
    float org[3], d[3];
    spm_ref_camera_ray(&o, 1.0f, 1.0f, 0.5f, 0.5f, org, d);
    CHECK(o.ortho && fabs(org[0] - 2.0f) < 1e-6 && fabs(org[1] - 1.0f) < 1e-6 && d[2] == 1.0f,
          "orthographic 2 vertical at 2:1: the top corner ray from (%g %g %g) along (%g %g %g)",
          org[0], org[1], org[2], d[0], d[1], d[2]);
    CHECK(spm_ref_camera_We(&o, org, d, (float[2]){0, 0}) == 0.0f,
          "an orthographic camera has no We (a delta)");
}

int main(void)
{
    struct {
        const char *name;
        spm_camera c;
    } cams[] = {
        {"pinhole 60 deg 4:3", make(64, 48, 60, SPM_FOV_HORIZONTAL, 0, 1)},
        {"pinhole 150 deg vertical 1:2", make(32, 64, 150, SPM_FOV_VERTICAL, 0, 1)},
        {"lens D 0.5 F 3, 40 deg 2:1", make(128, 64, 40, SPM_FOV_HORIZONTAL, 0.5, 3)},
        {"lens D 2 F 10, 90 deg shorter 1:1", make(32, 32, 90, SPM_FOV_SHORTER, 2, 10)},
    };
    for (size_t i = 0; i < sizeof cams / sizeof cams[0]; i++) {
        test_round_trip(&cams[i].c, cams[i].name);
        test_normalisation(&cams[i].c, cams[i].name);
        if (cams[i].c.lens_radius > 0.0f) {
            test_sample_wi(&cams[i].c, 2.5, cams[i].name);
            test_confusion(&cams[i].c, 1.5, cams[i].name);
            test_confusion(&cams[i].c, 40.0, cams[i].name);
            test_confusion(&cams[i].c, cams[i].c.focus, cams[i].name); /* in focus: a point */
        }
    }
    test_axes();
    TEST_END();
}
