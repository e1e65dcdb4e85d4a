/* Fluorescence in the spectral tables: each fluorescent material's
 * re-radiation matrix at every level, and the pretest that chooses the level
 * its diagonal colour (the colour the trace stage records at a fluorescent
 * vertex) may use. Part of spm_tables_build. */
#ifndef SPM_FLUOR_TABLES_H
#define SPM_FLUOR_TABLES_H
#include "tables.h"

/* Sets t->nfluor and t->fluor_first from the scene's derived diagonal
 * colours (before the arrays are made). */
void spm_fluor_tables_count(const spm_scene *sc, spm_tables *t);
/* Fills t->fluor[l]: the 1 nm matrix of fluor.h, then at each coarser level
 * the mean over the output bin of the sum over the input bin,
 *   F_l[O][I] = (1 / |O|) sum_{o in O} sum_{i in I} F_0[o][i]   (|O| in nm),
 * so that a vector of bin means maps to a vector of bin means: exact for a
 * light constant within each input bin. And t->fluor_rgb (spm_fluor_rgb). */
void spm_fluor_tables_fill(const spm_scene *sc, const spm_spectrum *d65, spm_tables *t);
/* The matrices' pretest: for every fluorescent material, level l passes
 * when for each light of the scene (its emissions and backgrounds) and each
 * light reflected once by a scene reflectance, the product M_l x_l (and for
 * k >= 2, M_l M_l x_l) is within the threshold of the 1 nm product, in the
 * colour difference of pretest.h; the diagonal colour's entries of lvlk
 * become the finer of theirs and the matrix's (k = 1: one product; k >= 2:
 * the worse of one and two). */
void spm_fluor_pretest(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t,
                       uint8_t *lvlk);
/* ingr[c] = 1 (c < sc->ncolours) for a colour only a fluorescent material
 * takes as its SPEC, ABSORB or EMIT: no path records it (a fluorescent vertex
 * records the diagonal, the matrix carries the rest), so it is no factor of
 * the pretests' products. A colour a non-fluorescent material, an emitter or
 * a background also uses is not one. */
void spm_fluor_ingredients(const spm_scene *sc, unsigned char *ingr);
/* The 3 x 3 re-radiation matrix of rgb mode for fluorescent material f, as
 * M[o][i] (fluorescent part only; the diagonal is the colour's RGB): the
 * matrix that maps the linear sRGB of three band lights, D65 over 380-490,
 * 490-590 and 590-780 nm, to the linear sRGB of what the 1 nm fluorescent
 * part makes of each, Out In^-1 (docs/METHODS.md "Fluorescence"). */
void spm_fluor_rgb(const spm_tables *t, int f, float out[3][3]);
#endif
