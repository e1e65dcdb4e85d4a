/* The spectral modes: one descriptor per mode, in one array (spm_modes) that
 * the command line, `bench`, the device-memory check and both backends
 * iterate. A descriptor says what the mode is called, whether each path gets
 * its own level and from which level table, how its shade tables are laid out
 * and filled (plain host data that both backends read, each with its own
 * arithmetic), and which kernel shades it. docs/ADDING_A_MODE.md says how to
 * add one. */
#ifndef SPM_MODES_H
#define SPM_MODES_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "tables.h"

/* The modes, in the order of spm_modes[] (host only: a kernel is compiled for
 * one mode and never asks which). */
enum spm_mode {
    SPM_MODE_TRUTH = 0,
    SPM_MODE_REF = 1,
    SPM_MODE_ML = 2,
    SPM_MODE_MLC = 3,
    SPM_MODE_HERO = 4,
    SPM_MODE_RGB = 5,
    SPM_MODE_COUNT = 6
};

/* One shade table: a row of `stride` floats per colour, of which the first
 * `lanes` are the colour's values in the mode's lanes (bins, spike lanes, RGB
 * channels), the rest zero; and XYZ weights, three rows of `stride` floats
 * (channel ch's weight for lane l at w[ch * stride + l]). The row is padded to
 * whole vectors of `width` floats, the kernel's vector width. A mode whose
 * lanes are drawn per path (hero) has no weight rows (w NULL): its kernel and
 * the reference compute them from `extra` (hero: spm_shared.h SPM_HERO_*). */
typedef struct {
    int lanes, width, stride;
    size_t nextra;  /* floats of extra */
    int ncolours;
    /* Fluorescence (tables.h nfluor): rows holds, after the colours' rows,
     * nfluor blocks of stride x stride floats, block f's row i the
     * fluorescent part of matrix f's column i (input lane i to every output
     * lane: M[o][i] at [i * stride + o]); colour fluor_first + f is matrix
     * f's diagonal. fluor_floats: the blocks' floats (0: none). */
    size_t fluor_floats;
    int nfluor, fluor_first;
    float *rows;    /* ncolours x stride, then the fluorescence blocks */
    float *w;       /* 3 x stride, or NULL */
    float *extra;   /* nextra floats, or NULL */
    /* A scene with dispersive glass (tables.h ndisp): the 1 nm rows of every
     * colour (ncolours x SPM_TRUTH_BINS) and truth's XYZ weights (3 x
     * SPM_TRUTH_BINS), the tables' own (not owned), from which every mode
     * shades a path committed to one wavelength; NULL otherwise. */
    const float *nm1, *nm1_w;
} spm_shade_table;

/* A spectral image's bins from one shade table's lanes (spectral output):
 * bin b = sum over entries e in [row[b], row[b+1]) of lane[lane_of[e]] *
 * fac[e], so that the bins hold the path's bin-average radiance per nm. One
 * array idx: row (nbins + 1 entries), then lane_of (nnz entries). */
typedef struct {
    int nbins, nnz;
    uint32_t *idx;
    float *fac;
} spm_spec_map;

typedef struct spm_mode_desc spm_mode_desc;
struct spm_mode_desc {
    int id;            /* enum spm_mode: its index in spm_modes[] */
    const char *name;  /* as --mode takes it */
    const char *help;  /* one line for the help texts and `specmip modes` */
    /* Levelled: each path is shaded at its own level, the finest its colours
     * need (the level feeler on the level table, kernels/trace.cl and the
     * reference's trace), with one shade table and kernel per level.
     * Otherwise every path is shaded with one table, built at `level`. */
    int levelled;
    int level;
    /* Its level table and tables are the Composite Model's (mlc_lvlk,
     * mlc_lvl): the scene must have them. Others use the pretest's lvlk (the
     * trace stage computes level bytes in every mode; only levelled modes
     * read them). */
    int composite;
    /* Lane wavelengths are drawn per path (hero): the kernel takes the extra
     * arguments SPM_SHADE_PATH_ARGS and the reference draws them likewise. */
    int per_path;
    /* Shade kernel (kernels/shade.cl) and the -D that compiles it; levelled:
     * both with %d for the level, and the define with a second %d for the
     * vectors per colour (stride / width). Unlevelled: the define may have one
     * %d, the vectors per colour. */
    const char *kernel;
    const char *define;
    /* Shade table at level l: layout (lanes, width, stride, nextra) first,
     * then, into the zeroed arrays of that layout, the rows and weights. */
    void (*layout)(const spm_tables *t, int level, spm_shade_table *out);
    void (*fill)(const spm_tables *t, int level, spm_shade_table *out);
    /* Spectral output (a .spectral.exr): the bin widths in nm the mode can
     * write, the first the default (0: it writes none, as rgb); and, for a
     * table mode, how a shade table's lanes at `level` become bins of nm nm
     * (spm_spec_map; called with the map's row and entry counts zero to ask
     * for nnz, then with the arrays to fill). A per-path mode (hero) has
     * none: each lane goes to the bin holding its wavelength, divided by its
     * density, the lane count and the bin width (kernel and reference). */
    int spec_nm[2];
    /* Its lanes are no wavelengths (rgb): a dispersive glass is traced at its
     * n_d and no path commits to a wavelength (docs/METHODS.md "Dispersion"). */
    int one_index;
    void (*spec_map)(const spm_tables *t, int level, int nm, spm_spec_map *out);
};

extern const spm_mode_desc spm_modes[SPM_MODE_COUNT];

/* The descriptor of mode id, or NULL if there is none. */
const spm_mode_desc *spm_mode(int id);
/* -1 if unknown. */
int spm_mode_parse(const char *name);
const char *spm_mode_name(int id); /* "?" if unknown */
/* "truth, ref, ml, ..." (sep between names) into buf; returns buf. */
const char *spm_mode_list(const char *sep, char *buf, size_t size);

/* One line per mode, "NAME  help", indented (the help texts). */
void spm_modes_help(FILE *f, int indent);
/* The modes for scripts: a line per mode, NAME TAB levelled|single TAB help;
 * or (json) an array of {"name", "levelled", "composite", "per_path", "help"}.
 * Mode names and help lines hold no character JSON would need escaped. */
void spm_modes_print(FILE *f, int json);

/* Shade tables (and kernels) a mode has: one per level if levelled, else 1. */
int spm_mode_nslots(const spm_mode_desc *m);
/* The slot that shades a path with level byte `level`: its level if the mode
 * is levelled (clamped to the finest table), else 0. */
int spm_mode_slot(const spm_mode_desc *m, uint8_t level);
/* The level of the tables in slot s. */
int spm_mode_slot_level(const spm_mode_desc *m, int slot);
/* The level table the level feeler reads (tables.h lvlk or mlc_lvlk). */
const uint8_t *spm_mode_lvlk(const spm_mode_desc *m, const spm_tables *t);
/* 0 if the tables have what the mode needs, else err says what is missing. */
int spm_mode_check(const spm_mode_desc *m, const spm_tables *t, spm_error *err);

/* Slot s's kernel name and its build define (without -D). */
void spm_mode_kernel(const spm_mode_desc *m, const spm_tables *t, int slot, char *name,
                     size_t name_size, char *define, size_t define_size);

/* Slot s's shade table, allocated and filled; free with spm_shade_table_free. */
void spm_shade_table_build(const spm_mode_desc *m, const spm_tables *t, int slot,
                           spm_shade_table *out);
void spm_shade_table_free(spm_shade_table *tab);
/* 1 if the mode writes a spectral image of nm-wide bins. */
int spm_mode_spec_ok(const spm_mode_desc *m, int nm);
/* Slot s's lane-to-bin map for nm-wide bins, allocated (a per-path mode: an
 * empty map); free with spm_spec_map_free. */
void spm_spec_map_build(const spm_mode_desc *m, const spm_tables *t, int slot, int nm,
                        spm_spec_map *out);
void spm_spec_map_free(spm_spec_map *map);

/* Bytes of every shade table of the mode (rows, weights, extra): its part of
 * the device memory a render needs. */
size_t spm_mode_footprint(const spm_mode_desc *m, const spm_tables *t);
#endif
