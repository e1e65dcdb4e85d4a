/* Colours given as RGB (MiniLight's reflectivity and emitivity, a mesh file's
 * materials), lifted to spectra once per distinct value. */
#include "scene_build.h"
#include "rgb2spec.h"
#include <stdio.h>

int spm_sb_rgb_colour(spm_scene_builder *b, spm_names *fits, const double rgb[3], spm_kind kind,
                      const char *where, spm_error *err)
{
    if (rgb[0] <= 0 && rgb[1] <= 0 && rgb[2] <= 0)
        return -1;
    char key[128], name[SPM_NAME_MAX];
    snprintf(key, sizeof key, "%d %a %a %a", (int)kind, rgb[0], rgb[1], rgb[2]);
    int c = spm_names_get(fits, key);
    if (c >= 0)
        return c;
    spm_spectrum sp;
    spm_error inner;
    double de;
    int rc = kind == SPM_KIND_EMISSION ? spm_rgb_to_emission(rgb, &sp, &de, &inner)
                                       : spm_rgb_to_reflectance(rgb, &sp, &de, &inner);
    if (rc) {
        spm_errorf(err, "%s: %s", where, inner.msg);
        return -2;
    }
    /* Beyond ~1 ΔE00 the RGB is outside what a reflectance (shape) can show. */
    if (de > 1.0)
        spm_warnf("%s: RGB (%g %g %g) is matched by a spectrum only to ΔE00 %.2g", where,
                  rgb[0], rgb[1], rgb[2], de);
    snprintf(name, sizeof name, "%s(%.6g,%.6g,%.6g)", kind == SPM_KIND_EMISSION ? "emit" : "rgb",
             rgb[0], rgb[1], rgb[2]);
    c = spm_sb_colour(b, name, &sp, where, err);
    if (c < 0)
        return -2;
    spm_names_put(fits, key, c);
    return c;
}
