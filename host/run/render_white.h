/* render --white: the white the image is balanced to (tonemap.h's white
 * balance), by name, from the scene's brightest emitters, or from a file. */
#ifndef SPM_RENDER_WHITE_H
#define SPM_RENDER_WHITE_H
#include "geometry.h"
#include "scene.h"
#include "tonemap.h"

/* `spec` is D65 (the display's own white: no change), E (equal energy), a
 * CIE illuminant of specmip's spectra/ (A, D50, F1..F12, LED_B1, ...: its
 * illuminant_NAME.csv), `auto` (the emitter colour of the most power over the
 * geometry's triangles, area times luminance, or the scene's background
 * without emitting triangles) or an
 * emission spectrum's CSV file. Sets tm's adaptation from that white to D65
 * and describes it in desc ("A (Bradford to D65)"). 0, or 1 with err. */
int spm_render_white(const char *spec, const spm_scene *s, const spm_geometry *g,
                     spm_tonemap *tm, char *desc, size_t size, spm_error *err);
#endif
