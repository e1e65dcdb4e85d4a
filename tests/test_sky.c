/* The daylight sky and its sun (host/scene/sky.h) against the model's
 * published formulas and tables evaluated independently, in Python, by
 * tests/sky_model.py: this program loads skies of several elevations,
 * turbidities and azimuths, asks what an escaping ray meets (the CPU
 * reference's light_escape) along the centre directions of a spread of
 * texels and along the sun's own direction, and writes each answer (the
 * luminance and the CIE 1931 xy of the colour it gets; the sun's direction,
 * luminance and xy) to sky_dump.txt; the script recomputes them from
 * Preetham et al.'s formulas, spectra/cie_daylight_basis.csv,
 * spectra/solar_astm_g173.csv and the CMFs, and judges. Here: the sun is an
 * entry of its own before the map, and a sky of scale 0 leaves the map black. */
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "envmap_testlib.h"
#include "geometry.h"
#include "refcpu_lights.h"
#include "sky.h"
#include "testutil.h"

static const struct {
    double elevation, turbidity, azimuth;
} skies[] = {{10.0, 2.0, 0.0}, {30.0, 3.0, 70.0}, {60.0, 6.0, -120.0}, {85.0, 9.0, 200.0}};

static int load(const char *line, spm_scene *s, spm_geometry *g)
{
    return envmap_test_scene("sky_test.scene", line, s, g);
}

/* what an escaping ray along d meets: its luminance and xy into the dump */
static void dump_escape(FILE *out, const spm_scene *s, const spm_geometry *g, const double d[3])
{
    spm_trace_params p;
    memset(&p, 0, sizeof p);
    p.bg_up = p.bg_down = SPM_NONE;
    float fd[3] = {(float)d[0], (float)d[1], (float)d[2]}, scale, pdf;
    spm_ref_key k = {7u, 3u, 0u}; /* at a texel's centre the bilinear draw has one texel */
    spm_u32 c = spm_ref_light_escape(g, &p, fd, &k, 1u, &scale, &pdf);
    double xyz[3] = {0.0, 0.0, 0.0};
    if (c != SPM_NONE)
        spm_xyz_emission(&s->colours[c].s, xyz);
    double sum = xyz[0] + xyz[1] + xyz[2];
    fprintf(out, " %.9g %.9g %.9g", c != SPM_NONE ? scale * xyz[1] : 0.0,
            sum > 0.0 ? xyz[0] / sum : 0.0, sum > 0.0 ? xyz[1] / sum : 0.0);
}

/* one sky: its texels (i, j) along their centres' directions, then the sun */
static void dump_sky(FILE *out, int k)
{
    char line[256];
    snprintf(line, sizeof line, "background sky elevation %g turbidity %g azimuth %g",
             skies[k].elevation, skies[k].turbidity, skies[k].azimuth);
    spm_scene s;
    spm_geometry g;
    if (load(line, &s, &g)) {
        CHECK(0, "'%s' loads", line);
        return;
    }
    int n = (int)g.nemitters;
    CHECK(n == 2 && g.emitters[0].kind == SPM_LIGHT_SUN && g.emitters[1].kind == SPM_LIGHT_ENVMAP,
          "the selection: the sun, then the map (%d entries)", n);
    const spm_scene_envmap *e = s.env;
    printf("sky %d: %d palette colours, u'v' error max %.4f, mean %.4f\n", k, e->ncolours,
           e->duv_max, e->duv_mean);
    fprintf(out, "sky %g %g %g %d %d %.9g %d\n", skies[k].elevation, skies[k].turbidity,
            skies[k].azimuth, e->w, e->h, e->duv_max, e->ncolours);
    for (int j = 1; j < e->h / 2; j += 7)
        for (int i = 3; i < e->w; i += 29) {
            double th = M_PI * (j + 0.5) / e->h, ph = 2.0 * M_PI * (i + 0.5) / e->w;
            double d[3] = {sin(th) * sin(ph), cos(th), -sin(th) * cos(ph)};
            fprintf(out, "texel %d %d", i, j);
            dump_escape(out, &s, &g, d);
            fputc('\n', out);
        }
    const spm_emitter *sun = &g.emitters[0];
    double w[3] = {sun->p[SPM_LIGHT_P_DIR], sun->p[SPM_LIGHT_P_DIR + 1], sun->p[SPM_LIGHT_P_DIR + 2]};
    fprintf(out, "sun %.9g %.9g %.9g", w[0], w[1], w[2]);
    dump_escape(out, &s, &g, w);
    fputc('\n', out);
    spm_geometry_free(&g);
    spm_scene_free(&s);
}

int main(void)
{
    FILE *out = fopen("sky_dump.txt", "w");
    CHECK(out != NULL, "cannot write sky_dump.txt");
    if (!out)
        TEST_END();
    for (int k = 0; k < (int)(sizeof skies / sizeof skies[0]); k++)
        dump_sky(out, k);
    fclose(out);

    /* scale 0: a black map (not in the selection) and no sun */
    spm_scene s;
    spm_geometry g;
    if (load("background sky elevation 40 turbidity 3 scale 0", &s, &g) == 0) {
        CHECK(g.nemitters == 0, "a black sky lights nothing (%u entries)", g.nemitters);
        spm_geometry_free(&g);
        spm_scene_free(&s);
    }
    /* the independent evaluation */
    const char *data = getenv("SPECMIP_DATA");
    CHECK(data != NULL, "SPECMIP_DATA is not set (ctest sets it)");
    if (data) {
        char cmd[4096];
        snprintf(cmd, sizeof cmd, "python3 '%s/tests/sky_model.py' '%s' sky_dump.txt", data, data);
        int rc = system(cmd);
        CHECK(rc == 0, "tests/sky_model.py: the sky or the sun differs from the model (status %d)",
              rc);
    }
    TEST_END();
}
