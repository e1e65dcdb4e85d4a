/* Spectral images out: a film's per-pixel spectrum as an OpenEXR file in the
 * layout of Fichet, Pacanowski and Wilkie, "An OpenEXR Layout for Spectral
 * Images" (JCGT 10(3), 2021), as colour-science reads it
 * (colour.read_spectral_image_Fichet2021):
 *   channels S0.<centre>nm, the bin centre with a comma for the decimal
 *     point (S0.382,5nm), holding the bin's mean spectral radiance in
 *     W.m^-2.sr^-1.nm^-1; R, G, B a linear sRGB preview (as the .exr output);
 *   header spectralLayoutVersion "1.0", emissiveUnits "W.m^-2.sr^-1".
 * Radiance is absolute on the convention that a scene's luminance (an
 * emission scale) is in cd/m^2: Y = 683 lm/W * integral of the radiance
 * times y-bar over 380-780 nm, so the bins are specmip's per-nm values
 * times 1 / (683 * the integral of y-bar, spm_cmf_y_integral). */
#ifndef SPM_SPECTRAL_EXR_H
#define SPM_SPECTRAL_EXR_H
#include "film.h"
#include "image_io.h"

/* 1 if the file name asks for a spectral image: it ends in .spectral.exr
 * (any case). */
int spm_spectral_path(const char *path);
/* The name of bin b of nbins over 380-780 nm: "S0.382,5nm" (5 nm bins). */
void spm_spectral_channel_name(int b, int nbins, char *buf, size_t size);
/* Writes the film's spectrum (it must have one) and preview, with attrs
 * added to the header. 0, or fills err. */
int spm_spectral_exr_write(const char *path, const spm_film *film, const spm_image_attr *attrs,
                           int nattrs, spm_error *err);
#endif
