/* A physically based daylight sky and its sun: `background sky elevation E
 * turbidity T [azimuth A] [scale S] [sky F] [sun F]` (docs/SCENE_FORMAT.md,
 * docs/METHODS.md "Sun and sky").
 *
 * The sky is Preetham, Shirley and Smits' model (SIGGRAPH 1999): luminance
 * Y and chromaticity x, y of each direction from Perez et al.'s five-
 * parameter distribution fitted to the turbidity, and its spectrum the CIE
 * daylight of that chromaticity, S0 + M1 S1 + M2 S2 (spectra/
 * cie_daylight_basis.csv). It is baked into an environment map (envmap.h)
 * whose palette is made of daylight spectra, not lifted RGB: the texels are
 * binned by (M1, M2) and each bin's colour is the basis spectrum of its
 * texels' luminance-weighted mean (M1, M2).
 *
 * The sun is a light of its own kind (include/spm_lights.h SUN): a disc of
 * SPM_SUN_HALF_DEG, its radiance the extraterrestrial solar spectrum
 * (spectra/solar_astm_g173.csv) through Rayleigh and aerosol transmittance
 * along the relative air mass of its zenith angle (Preetham et al.'s
 * appendix). Both in kcd/m^2 (Preetham's unit for Y) times scale, the sky
 * also times its 'sky' factor, the sun its 'sun' factor. */
#ifndef SPM_SCENE_SKY_H
#define SPM_SCENE_SKY_H
#include "scene.h"
#include "scene_lexer.h"

/* the sun's angular radius: half of its mean apparent diameter, 0.533 deg */
#define SPM_SUN_HALF_DEG 0.2665
/* the baked map: w x h texels (1.4 deg a texel) */
#define SPM_SKY_W 256
#define SPM_SKY_H 128
/* (M1, M2) bins per axis of the palette (docs/METHODS.md: its chromaticity
 * error) */
#define SPM_SKY_GRID 32

/* The model's parameters, kept by the scene until its palette is made. */
typedef struct spm_sky_s {
    double elevation, azimuth; /* of the sun, degrees */
    double turbidity;
    double scale;              /* both's factor */
    double sky, sun;           /* the sky's own factor, the sun's */
} spm_sky;

/* The statement after 'background': lx on 'sky'. Sets s->env (a map whose
 * texels the palette step fills) and keeps the model in s->env->sky. */
int spm_sky_statement(spm_scene *s, spm_lexer *lx, spm_error *err);
/* The map's palette of daylight spectra and its texels, then the sun's
 * colour and its light (appended to s->lights), once the scene's colours
 * are pruned; nothing for a scene without a sky. */
int spm_sky_palette(spm_scene *s, spm_error *err);

/* The model, for tests and the palette: the sun's unit direction w from
 * elevation and azimuth (degrees; azimuth as the map's u: 0 toward -z, 90
 * toward +x, +y up); the sky's Y (kcd/m^2) and x, y toward unit d (y < 0:
 * 0); the sun's spectral radiance (W m^-2 sr^-1 nm^-1) at 1 nm, 380..780. */
void spm_sky_sun_dir(double elevation, double azimuth, double w[3]);
void spm_sky_eval(const spm_sky *k, const double d[3], double *Y, double *x, double *y);
int spm_sky_sun_radiance(const spm_sky *k, double L[401], spm_error *err);
#endif
