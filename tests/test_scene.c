/* Good scenes: MiniLight's own Cornell box, the default scene (and its file),
 * and a scene using every statement of the format. */
#include "colour.h"
#include "csv.h"
#include "rgb2spec.h"
#include "scene.h"
#include "testutil.h"
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *data(const char *rel)
{
    static char buf[8][4096];
    static int next;
    next = (next + 1) % 8;
    return spm_data_path(rel, buf[next], sizeof buf[next]);
}

static void chromaticity(const spm_spectrum *s, double *x, double *y, double *Y)
{
    double xyz[3];
    spm_xyz_emission(s, xyz);
    double sum = xyz[0] + xyz[1] + xyz[2];
    *x = xyz[0] / sum;
    *y = xyz[1] / sum;
    *Y = xyz[1];
}

static void reflectance_rgb(const spm_spectrum *r, double rgb[3])
{
    spm_error err;
    double xyz[3];
    spm_xyz_reflectance(r, spm_d65(&err), xyz);
    for (int k = 0; k < 3; k++)
        xyz[k] /= 100.0;
    spm_xyz_to_linear_srgb(xyz, rgb);
}

static int count_emitting_tris(const spm_scene *s)
{
    int n = 0;
    for (int t = 0; t < s->ntris; t++)
        n += s->materials[s->tris[t].material].emit >= 0;
    return n;
}

/* Every index in range: what the renderer relies on. */
static void check_consistent(const spm_scene *s, const char *what)
{
    int ok = s->bg_up < s->ncolours && s->bg_down < s->ncolours;
    for (int m = 0; m < s->nmaterials; m++)
        ok &= s->materials[m].refl < s->ncolours && s->materials[m].emit < s->ncolours &&
              s->materials[m].refl >= -1 && s->materials[m].emit >= -1;
    for (int t = 0; t < s->ntris; t++)
        ok &= s->tris[t].material >= 0 && s->tris[t].material < s->nmaterials;
    for (int c = 0; c < s->ncolours; c++)
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            ok &= s->colours[c].s.nm1[i] >= 0 &&
                  (s->colours[c].s.kind == SPM_KIND_EMISSION || s->colours[c].s.nm1[i] <= 1);
    CHECK(ok, "%s: indices in range, reflectances within [0, 1]", what);
}

static void test_minilight(void)
{
    spm_scene s;
    spm_error err;
    const char *path = data("tests/data/scenes/cornellbox.ml.txt");
    CHECK(spm_scene_load(path, &s, &err) == 0, "MiniLight Cornell box: %s", err.msg);
    check_consistent(&s, "MiniLight box");
    /* Numbers from the file itself. */
    CHECK(s.ntris == 32, "32 triangles, got %d", s.ntris);
    CHECK(s.width == 391 && s.height == 391, "image %dx%d", s.width, s.height);
    CHECK(s.spp == 100, "iterations -> spp %d", s.spp);
    CHECK_NEAR(s.eye[0], 0.278, 1e-6, "eye x");
    CHECK_NEAR(s.eye[1], 0.275, 1e-6, "eye y");
    CHECK_NEAR(s.eye[2], -0.789, 1e-6, "eye z");
    CHECK(s.dir[0] == 0 && s.dir[1] == 0 && s.dir[2] == 1, "direction");
    CHECK(s.fov_deg == 40, "fov %g", s.fov_deg);
    /* Sharing: grey, red, green reflectances, one light, sky and sky x ground. */
    CHECK(s.ncolours == 6, "6 colours, got %d", s.ncolours);
    CHECK(s.nmaterials == 4, "4 materials (grey, red, green, light), got %d", s.nmaterials);
    CHECK(count_emitting_tris(&s) == 2, "2 emitting triangles");
    CHECK(s.tris[4].line == 19 && s.tris[31].line == 61, "source lines %d %d", s.tris[4].line,
          s.tris[31].line);
    CHECK(s.tris[0].p[2][2] == 0.559f, "vertex copied");

    /* The white light is D65 with luminance 1000 (MiniLight's RGB luminance). */
    int light = s.materials[s.tris[10].material].emit;
    CHECK(light >= 0, "the ceiling light emits");
    if (light >= 0) {
        double x, y, Y, wx, wy, wY;
        spm_spectrum d65 = *spm_d65(&err);
        chromaticity(&s.colours[light].s, &x, &y, &Y);
        chromaticity(&d65, &wx, &wy, &wY);
        /* MiniLight's luminance of RGB 1000: 1000 to the sRGB matrix' 7 digits */
        CHECK_NEAR(Y, 1000.0, 1e-3, "light luminance");
        CHECK_NEAR(x, wx, 1e-9, "light x = D65 x");
        CHECK_NEAR(y, wy, 1e-9, "light y = D65 y");
        CHECK(s.colours[light].s.kind == SPM_KIND_EMISSION, "light is an emission");
    }
    /* The red wall (lines 19-20) maps back to its RGB; 3e-3 in rgb is ~0.1 ΔE00,
     * the fit's target. */
    int red = s.materials[s.tris[4].material].refl;
    double rgb[3], want[3] = {0.7, 0.2, 0.2};
    reflectance_rgb(&s.colours[red].s, rgb);
    for (int k = 0; k < 3; k++)
        CHECK_NEAR(rgb[k], want[k], 3e-3, "red wall rgb");
    int grey = s.materials[s.tris[0].material].refl;
    CHECK(s.colours[grey].s.nm1[0] == 0.7 && s.colours[grey].s.nm1[399] == 0.7, "grey 0.7");

    /* Sky: luminance of its RGB; ground: sky x the ground reflectance spectrum. */
    double sky[3] = {0.0906, 0.0943, 0.1151}, ground[3] = {0.1, 0.09, 0.07}, xyz[3];
    CHECK(s.bg_up >= 0 && s.bg_down >= 0, "background up and down");
    if (s.bg_up >= 0 && s.bg_down >= 0) {
        double x, y, Y;
        spm_linear_srgb_to_xyz(sky, xyz);
        chromaticity(&s.colours[s.bg_up].s, &x, &y, &Y);
        CHECK_NEAR(Y, xyz[1], 1e-9 * xyz[1], "sky luminance");
        spm_spectrum g, prod = s.colours[s.bg_up].s;
        CHECK(spm_rgb_to_reflectance(ground, &g, NULL, &err) == 0, "%s", err.msg);
        spm_spectrum_multiply(&prod, &g);
        CHECK(memcmp(prod.nm1, s.colours[s.bg_down].s.nm1, sizeof prod.nm1) == 0,
              "bg_down = sky x ground");
    }
    spm_scene_free(&s);
    CHECK(s.colours == NULL && s.ntris == 0, "freed");
}

static int same_scene(const spm_scene *a, const spm_scene *b)
{
    int same = a->ntris == b->ntris && a->ncolours == b->ncolours &&
               a->nmaterials == b->nmaterials && a->width == b->width &&
               a->height == b->height && a->spp == b->spp && a->bg_up == b->bg_up &&
               a->bg_down == b->bg_down && a->fov_deg == b->fov_deg &&
               !memcmp(a->eye, b->eye, sizeof a->eye) && !memcmp(a->dir, b->dir, sizeof a->dir);
    for (int i = 0; same && i < a->ntris; i++)
        same = !memcmp(a->tris[i].p, b->tris[i].p, sizeof a->tris[i].p) &&
               a->tris[i].material == b->tris[i].material;
    for (int i = 0; same && i < a->nmaterials; i++)
        same = a->materials[i].refl == b->materials[i].refl &&
               a->materials[i].emit == b->materials[i].emit;
    for (int i = 0; same && i < a->ncolours; i++)
        same = !memcmp(a->colours[i].s.nm1, b->colours[i].s.nm1, sizeof a->colours[i].s.nm1);
    return same;
}

static void test_default(void)
{
    spm_scene s, f;
    spm_error err;
    char cwd[4096];
    CHECK(getcwd(cwd, sizeof cwd) != NULL, "getcwd");
    CHECK(chdir("/") == 0, "chdir /"); /* the default must not depend on the directory */
    CHECK(spm_scene_default(&s, &err) == 0, "default scene: %s", err.msg);
    CHECK(chdir(cwd) == 0, "chdir back");
    CHECK(strcmp(s.path, "<default>") == 0, "path %s", s.path);
    check_consistent(&s, "default");
    CHECK(spm_scene_load(data("scenes/cornell.scene"), &f, &err) == 0, "cornell.scene: %s",
          err.msg);
    CHECK(same_scene(&s, &f), "the default is scenes/cornell.scene");
    /* 16 quads: 5 walls, the light, 2 boxes of 5 faces. */
    CHECK(s.ntris == 32, "32 triangles, got %d", s.ntris);
    CHECK(s.width == 256 && s.height == 256, "256x256");
    CHECK(s.ncolours == 6 && s.nmaterials == 6, "6 colours %d, 6 materials %d", s.ncolours,
          s.nmaterials);
    CHECK(s.bg_up < 0 && s.bg_down < 0, "no background");
    CHECK(count_emitting_tris(&s) == 2, "the light is 2 triangles");
    /* Same geometry and camera as MiniLight's box. */
    spm_scene ml;
    CHECK(spm_scene_load(data("tests/data/scenes/cornellbox.ml.txt"), &ml, &err) == 0, "%s",
          err.msg);
    CHECK(!memcmp(s.eye, ml.eye, sizeof s.eye) && !memcmp(s.dir, ml.dir, sizeof s.dir) &&
              s.fov_deg == ml.fov_deg, "MiniLight's camera");
    double area_s = 0, area_ml = 0;
    for (int pass = 0; pass < 2; pass++) {
        const spm_scene *sc = pass ? &ml : &s;
        for (int t = 0; t < sc->ntris; t++) {
            double e1[3], e2[3];
            for (int k = 0; k < 3; k++) {
                e1[k] = sc->tris[t].p[1][k] - sc->tris[t].p[0][k];
                e2[k] = sc->tris[t].p[2][k] - sc->tris[t].p[0][k];
            }
            double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                           e1[0] * e2[1] - e1[1] * e2[0]};
            double a = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
            *(pass ? &area_ml : &area_s) += a;
            /* Emitters emit from the front face: the light must face down. */
            if (sc->materials[sc->tris[t].material].emit >= 0)
                CHECK(c[1] < 0, "light triangle %d faces down", t);
        }
    }
    CHECK_NEAR(area_s, area_ml, 1e-6 * area_ml, "same total area as MiniLight's box");
    spm_scene_free(&ml);

    /* The light: equal energy, luminance 1000. The red wall: the ColorChecker's red. */
    int light = s.materials[s.tris[10].material].emit, red = s.materials[s.tris[4].material].refl;
    double x, y, Y;
    chromaticity(&s.colours[light].s, &x, &y, &Y);
    CHECK_NEAR(Y, 1000.0, 1e-9 * 1000, "light luminance");
    CHECK(s.colours[light].s.nm1[0] == s.colours[light].s.nm1[250], "light is equal-energy");
    spm_spectrum cc;
    CHECK(spm_spectrum_load(data("spectra/colorchecker_n_ohta.csv"), "red",
                            SPM_KIND_REFLECTANCE, &cc, &err) == 0, "%s", err.msg);
    CHECK(!memcmp(cc.nm1, s.colours[red].s.nm1, sizeof cc.nm1), "red wall = ColorChecker red");
    spm_scene_free(&s);
    spm_scene_free(&f);
}

static void test_features(void)
{
    spm_scene s;
    spm_error err;
    spm_quiet_warnings = 1; /* ramp.csv's partial coverage, the unused spectrum */
    int rc = spm_scene_load(data("tests/data/scenes/features.scene"), &s, &err);
    spm_quiet_warnings = 0;
    CHECK(rc == 0, "features.scene: %s", err.msg);
    if (rc)
        return;
    check_consistent(&s, "features");
    CHECK(s.width == 64 && s.height == 48 && s.spp == 16, "image and spp");
    CHECK_NEAR(s.fov_deg, 55, 0, "fov");
    CHECK_NEAR(s.dir[1], -1 / sqrt(5.0), 1e-7, "direction normalised");
    CHECK(s.ntris == 2 + 3 + 2 + 1, "quads are two triangles: %d", s.ntris);
    CHECK(s.tris[0].line == 28 && s.tris[1].line == 28 && s.tris[2].line == 29, "lines");
    /* half and same share one material; unused is dropped. */
    CHECK(s.tris[2].material == s.tris[3].material, "identical materials shared");
    CHECK(s.nmaterials == 5, "5 materials used, got %d", s.nmaterials);
    int half = s.materials[s.tris[2].material].refl;
    CHECK(s.colours[half].s.nm1[123] == 0.5, "equal x 0.5");
    int ramp = s.materials[s.tris[4].material].refl;
    /* ramp.csv: 0.2 at 400 nm to 0.8 at 700; bin [549, 550] has mean 0.2 + 0.6 * 149.5/300;
     * extended by its end values outside 400-700. */
    CHECK_NEAR(s.colours[ramp].s.nm1[169], 0.2 + 0.6 * 149.5 / 300, 1e-12, "ramp at 549.5 nm");
    CHECK_NEAR(s.colours[ramp].s.nm1[0], 0.2, 1e-12, "ramp extended at 380 nm");
    CHECK_NEAR(s.colours[ramp].s.nm1[399], 0.8, 1e-12, "ramp extended at 780 nm");
    const spm_scene_material *lamp = &s.materials[s.tris[5].material];
    double x, y, Y;
    chromaticity(&s.colours[lamp->emit].s, &x, &y, &Y);
    CHECK_NEAR(Y, 25.0, 1e-9 * 25, "lamp luminance = its scale");
    /* A 2856 K blackbody is CIE illuminant A: x, y = 0.44757, 0.40744 (data README);
     * the cut to 380-780 nm moves it by < 1e-3. */
    CHECK_NEAR(x, 0.44757, 1e-3, "2856 K x");
    CHECK_NEAR(y, 0.40744, 1e-3, "2856 K y");
    CHECK_NEAR(s.colours[lamp->refl].s.nm1[120], 0.9 - 0.7 * 0.5 / 50, 1e-12,
               "inline bump at 500.5 nm");
    CHECK(s.materials[s.tris[7].material].refl == -1 &&
              s.materials[s.tris[7].material].emit == -1, "a material without clauses is black");
    CHECK(s.bg_up >= 0 && s.bg_down >= 0 && s.bg_up != s.bg_down, "background up and down");
    chromaticity(&s.colours[s.bg_up].s, &x, &y, &Y);
    CHECK_NEAR(Y, 2.0, 1e-9 * 2, "sky luminance");
    chromaticity(&s.colours[s.bg_down].s, &x, &y, &Y);
    CHECK_NEAR(Y, 0.25, 1e-9 * 0.25, "ground luminance");
    spm_scene_free(&s);

    CHECK(spm_scene_load(data("tests/data/scenes/sky_only.scene"), &s, &err) == 0,
          "a scene lit only by its background is valid: %s", err.msg);
    CHECK(s.bg_up >= 0 && s.bg_down < 0 && count_emitting_tris(&s) == 0, "sky only");
    spm_scene_free(&s);
}

int main(void)
{
    spm_error err;
    CHECK(spm_cmf_init(&err) == 0, "CMF: %s", err.msg);
    test_minilight();
    test_default();
    test_features();
    TEST_END();
}
