/* White balance from the command line (render_white.h). */
#include "render_white.h"
#include "colour.h"
#include "csv.h"
#include "lights.h"
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

/* The emission colour of the scene's most powerful emitter: per colour, the
 * area of its emitting triangles times its luminance Y, and the power over pi
 * of the `light` statements' lights; the background when no light emits. -1
 * when nothing emits. */
static int brightest(const spm_scene *s, const spm_geometry *g)
{
    double *power = spm_xcalloc((size_t)s->ncolours + 1, sizeof *power);
    for (int t = 0; t < g->ntris; t++) {
        int c = s->materials[g->tris[t].material].emit;
        if (c >= 0) {
            double xyz[3];
            spm_xyz_emission(&s->colours[c].s, xyz);
            power[c] += g->tris[t].area * xyz[1];
        }
    }
    for (int i = 0; i < s->nlights; i++) /* in the same unit (lights.h spm_light_power) */
        power[s->lights[i].colour] += spm_light_power(s, &s->lights[i]);
    int best = -1;
    for (int c = 0; c < s->ncolours; c++)
        if (power[c] > 0 && (best < 0 || power[c] > power[best]))
            best = c;
    free(power);
    return best >= 0 ? best : s->bg_up >= 0 ? s->bg_up : s->bg_down;
}

/* The white's XYZ and its name in desc; 0, or 1 with err. */
static int white_xyz(const char *spec, const spm_scene *s, const spm_geometry *g, double xyz[3],
                     char *desc, size_t size, spm_error *err)
{
    spm_spectrum sp;
    char file[1024], rel[256];
    if (!strcasecmp(spec, "E")) {
        spm_spectrum_constant(1.0, SPM_KIND_EMISSION, &sp);
        snprintf(desc, size, "E");
    } else if (!strcasecmp(spec, "auto")) {
        int c = brightest(s, g);
        if (c < 0) {
            spm_errorf(err, "--white auto: the scene has no emitter and no background");
            return 1;
        }
        sp = s->colours[c].s;
        snprintf(desc, size, "auto: %s", s->colours[c].name);
    } else {
        snprintf(rel, sizeof rel, "spectra/illuminant_%s.csv", spec);
        int named = !strchr(spec, '/') && strlen(spec) < 64 &&
                    access(spm_data_path(rel, file, sizeof file), R_OK) == 0;
        if (!named)
            snprintf(file, sizeof file, "%s", spec);
        spm_error inner;
        if (spm_spectrum_load(file, NULL, SPM_KIND_EMISSION, &sp, &inner)) {
            spm_errorf(err, "--white %s: not D65, E, auto, an illuminant of spectra/ (A, D50, "
                            "F1..F12, ...) or a readable spectrum file: %s", spec, inner.msg);
            return 1;
        }
        snprintf(desc, size, "%s", spec);
    }
    spm_xyz_emission(&sp, xyz);
    if (!(xyz[1] > 0) || !isfinite(xyz[0] + xyz[1] + xyz[2])) {
        spm_errorf(err, "--white %s: that white has no luminance", spec);
        return 1;
    }
    return 0;
}

int spm_render_white(const char *spec, const spm_scene *s, const spm_geometry *g,
                     spm_tonemap *tm, char *desc, size_t size, spm_error *err)
{
    tm->adapt = 0;
    if (!strcasecmp(spec, "D65")) {
        snprintf(desc, size, "D65 (the display's white: unchanged)");
        return 0;
    }
    double src[3], dst[3];
    char name[128];
    const spm_spectrum *d65 = spm_d65(err);
    if (!d65 || white_xyz(spec, s, g, src, name, sizeof name, err))
        return 1;
    spm_xyz_emission(d65, dst);
    spm_cat_bradford(src, dst, tm->cat);
    tm->adapt = 1;
    snprintf(desc, size, "%s (Bradford to D65)", name);
    return 0;
}
