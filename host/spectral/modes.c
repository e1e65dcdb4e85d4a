/* The spectral modes (modes.h): descriptors and their shade tables. */
#include "modes.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "fluor_tables.h"

static int round_up(int n, int w)
{
    return (n + w - 1) / w * w;
}

/* Copies `n` floats of each of `rows` source rows (src_stride apart) into the
 * table's rows. */
static void copy_rows(float *dst, int dst_stride, const float *src, int src_stride, int rows,
                      int n)
{
    for (int r = 0; r < rows; r++)
        memcpy(&dst[(size_t)r * dst_stride], &src[(size_t)r * src_stride], (size_t)n * sizeof *dst);
}

/* Fluorescence blocks (modes.h) at level l: the level's matrices, column i
 * of matrix f into block row i. */
static void fluor_blocks(const spm_tables *t, int l, spm_shade_table *o)
{
    int n = SPM_LEVEL_BINS(l);
    float *blk = o->rows + (size_t)t->ncolours * (size_t)o->stride;
    for (int f = 0; f < t->nfluor; f++) {
        const float *M = t->fluor[l] + (size_t)f * n * n;
        float *b = blk + (size_t)f * o->stride * o->stride;
        for (int i = 0; i < n; i++)
            for (int r = 0; r < n; r++)
                b[(size_t)i * o->stride + r] = M[(size_t)r * n + i];
    }
}

/* ---- truth, ref, ml: the bins of a level (spm_shared.h: level 0 the 1 nm
 * bins as 25 x float16, then five vectors of 16, 8, 4, 2 floats) ---------- */
static void level_layout(const spm_tables *t, int l, spm_shade_table *o)
{
    (void)t;
    o->lanes = SPM_LEVEL_BINS(l), o->width = SPM_LEVEL_WIDTH(l), o->stride = SPM_LEVEL_BINS(l);
}

static void level_fill(const spm_tables *t, int l, spm_shade_table *o)
{
    int bins = SPM_LEVEL_BINS(l);
    copy_rows(o->rows, o->stride, t->lvl[l], bins, t->ncolours, bins);
    copy_rows(o->w, o->stride, &t->cmf_lvl[l][0][0], SPM_TRUTH_BINS, 3, bins);
    fluor_blocks(t, l, o);
}

/* ---- mlc: a level's smooth bins, then the scene's spike lanes weighted by
 * the CMFs at the spike wavelengths, padded to whole vectors --------------- */
static void mlc_layout(const spm_tables *t, int l, spm_shade_table *o)
{
    o->lanes = SPM_LEVEL_BINS(l) + t->nspikes, o->width = SPM_LEVEL_WIDTH(l);
    o->stride = round_up(o->lanes, o->width);
}

/* A spike lane through a matrix: what the matrix's diagonal keeps of it
 * stays a spike (its colour row's spike lane is the diagonal at the spike's
 * wavelength); what it absorbs is re-emitted into the smooth bins, block row
 * bins + k holding the mean over each output bin of the 1 nm column at the
 * spike's wavelength (a spike lane carries energy, per nm times nm; the
 * column is per 1 nm bin, so per nm). */
static void mlc_fluor_spikes(const spm_tables *t, int l, spm_shade_table *o)
{
    int bins = SPM_LEVEL_BINS(l), w = SPM_TRUTH_BINS / bins;
    float *blk = o->rows + (size_t)t->ncolours * (size_t)o->stride;
    for (int f = 0; f < t->nfluor; f++) {
        const float *M0 = t->fluor[0] + (size_t)f * SPM_TRUTH_BINS * SPM_TRUTH_BINS;
        float *b = blk + (size_t)f * o->stride * o->stride;
        for (int k = 0; k < t->nspikes; k++) {
            int j = (int)(t->spike_wl[k] - (float)SPM_LAMBDA_MIN);
            j = j < 0 ? 0 : j >= SPM_TRUTH_BINS ? SPM_TRUTH_BINS - 1 : j;
            for (int r = 0; r < SPM_TRUTH_BINS; r++)
                b[(size_t)(bins + k) * o->stride + r / w] += M0[(size_t)r * SPM_TRUTH_BINS + j] / (float)w;
        }
    }
}

static void mlc_fill(const spm_tables *t, int l, spm_shade_table *o)
{
    int bins = SPM_LEVEL_BINS(l);
    copy_rows(o->rows, o->stride, t->mlc_lvl[l], SPM_MLC_STRIDE(l), t->ncolours, o->lanes);
    for (int ch = 0; ch < 3; ch++) {
        memcpy(&o->w[ch * o->stride], t->cmf_lvl[l][ch], (size_t)bins * sizeof *o->w);
        memcpy(&o->w[ch * o->stride + bins], t->spike_cmf[ch], (size_t)t->nspikes * sizeof *o->w);
    }
    fluor_blocks(t, l, o);
    mlc_fluor_spikes(t, l, o);
}

/* ---- hero: truth's 1 nm rows, read at four wavelengths drawn per path ----- */
static void hero_layout(const spm_tables *t, int level, spm_shade_table *o)
{
    (void)t, (void)level;
    o->lanes = SPM_TRUTH_BINS, o->width = 4, o->stride = SPM_TRUTH_BINS;
    o->nextra = SPM_HERO_FLOATS;
}

static void hero_fill(const spm_tables *t, int level, spm_shade_table *o)
{
    (void)level;
    copy_rows(o->rows, o->stride, t->truth, SPM_TRUTH_BINS, t->ncolours, SPM_TRUTH_BINS);
    o->extra[SPM_HERO_T0] = t->hero_t0;
    o->extra[SPM_HERO_DT] = t->hero_dt;
    o->extra[SPM_HERO_PDFK] = t->hero_pdfk;
    memcpy(o->extra + SPM_HERO_EDGE, t->hero_edge, sizeof t->hero_edge);
    memcpy(o->extra + SPM_HERO_INDEX, t->hero_index, sizeof t->hero_index);
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        for (int ch = 0; ch < 3; ch++)
            o->extra[SPM_HERO_CMF + 4 * i + ch] = t->cmf_truth[ch][i];
}

/* ---- rgb: three components; XYZ by the colour module's sRGB matrix -------- */
static void rgb_layout(const spm_tables *t, int level, spm_shade_table *o)
{
    (void)t, (void)level;
    o->lanes = 3, o->width = 4, o->stride = 4;
}

static void rgb_fill(const spm_tables *t, int level, spm_shade_table *o)
{
    (void)level;
    copy_rows(o->rows, o->stride, t->rgb, 4, t->ncolours, 3);
    for (int c = 0; c < 3; c++) {
        double rgb[3] = {c == 0, c == 1, c == 2}, xyz[3];
        spm_linear_srgb_to_xyz(rgb, xyz);
        for (int ch = 0; ch < 3; ch++)
            o->w[ch * o->stride + c] = (float)xyz[ch];
    }
    float *blk = o->rows + (size_t)t->ncolours * (size_t)o->stride;
    for (int f = 0; f < t->nfluor; f++) {
        float m3[3][3];
        spm_fluor_rgb(t, f, m3);
        for (int i = 0; i < 3; i++)
            for (int r = 0; r < 3; r++)
                blk[(size_t)f * 16 + (size_t)i * 4 + r] = m3[r][i];
    }
}

/* ---- spectral output: lane-to-bin maps (modes.h spm_spec_map) ------------ */
/* Adds an entry (lane, fac) to the bin being filled; counts only while the
 * arrays are not there yet. */
static void map_put(spm_spec_map *o, int lane, float fac)
{
    if (o->idx) {
        o->idx[o->nbins + 1 + o->nnz] = (uint32_t)lane;
        o->fac[o->nnz] = fac;
    }
    o->nnz++;
}

static void map_row(spm_spec_map *o, int b)
{
    if (o->idx)
        o->idx[b] = (uint32_t)o->nnz;
}

/* Output bin b of nm nm from a level-l row: the mean of the level's bins it
 * holds (level 0's nm lanes), or the mean of the level's bin that holds it
 * (area-preserving). */
static void put_level_bin(spm_spec_map *o, int l, int nm, int b)
{
    int lnm = (SPM_LAMBDA_MAX - SPM_LAMBDA_MIN) / SPM_LEVEL_BINS(l);
    if (lnm < nm)
        for (int j = 0; j < nm / lnm; j++)
            map_put(o, b * (nm / lnm) + j, (float)lnm / (float)nm);
    else
        map_put(o, b * nm / lnm, 1.0f);
}

/* truth, ref, ml: the level's bins. */
static void level_spec(const spm_tables *t, int l, int nm, spm_spec_map *o)
{
    (void)t;
    o->nnz = 0;
    for (int b = 0; b < o->nbins; b++) {
        map_row(o, b);
        put_level_bin(o, l, nm, b);
    }
    map_row(o, o->nbins);
}

/* mlc: the smooth bins as ml; a spike lane carries the spike's energy (per
 * nm times nm), which goes whole into the 5 nm bin holding its wavelength. */
static void mlc_spec(const spm_tables *t, int l, int nm, spm_spec_map *o)
{
    o->nnz = 0;
    for (int b = 0; b < o->nbins; b++) {
        map_row(o, b);
        put_level_bin(o, l, nm, b);
        for (int k = 0; k < t->nspikes; k++) {
            int sb = (int)((t->spike_wl[k] - (float)SPM_LAMBDA_MIN) / (float)nm);
            sb = sb < 0 ? 0 : sb >= o->nbins ? o->nbins - 1 : sb;
            if (sb == b)
                map_put(o, SPM_LEVEL_BINS(l) + k, 1.0f / (float)nm);
        }
    }
    map_row(o, o->nbins);
}

const spm_mode_desc spm_modes[SPM_MODE_COUNT] = {
    [SPM_MODE_TRUTH] = {.id = SPM_MODE_TRUTH, .name = "truth", .help = "1 nm bins (ground truth)",
                        .kernel = "spm_shade_l0", .define = "SPM_SHADE_L0_NV=%d",
                        .layout = level_layout, .fill = level_fill, .spec_nm = {5, 1},
                        .spec_map = level_spec},
    [SPM_MODE_REF] = {.id = SPM_MODE_REF, .name = "ref", .help = "5 nm bins",
                      .level = SPM_REF_LEVEL, .kernel = "spm_shade_l1",
                      .define = "SPM_SHADE_L1_NV=%d", .layout = level_layout, .fill = level_fill,
                      .spec_nm = {5, 0}, .spec_map = level_spec},
    [SPM_MODE_ML] = {.id = SPM_MODE_ML, .name = "ml",
                     .help = "Spectral Mipmapping: 1-40 nm bins, a level per path", .levelled = 1,
                     .kernel = "spm_shade_l%d", .define = "SPM_SHADE_L%d_NV=%d",
                     .layout = level_layout, .fill = level_fill, .spec_nm = {5, 0},
                     .spec_map = level_spec},
    [SPM_MODE_MLC] = {.id = SPM_MODE_MLC, .name = "mlc", .help = "ml + Composite Model spike lanes",
                      .levelled = 1, .composite = 1, .kernel = "spm_shade_l%d",
                      .define = "SPM_SHADE_L%d_NV=%d", .layout = mlc_layout, .fill = mlc_fill,
                      .spec_nm = {5, 0}, .spec_map = mlc_spec},
    [SPM_MODE_HERO] = {.id = SPM_MODE_HERO, .name = "hero", .help = "4 hero wavelengths a path",
                       .per_path = 1, .kernel = "spm_shade_hero", .define = "SPM_SHADE_HERO",
                       .layout = hero_layout, .fill = hero_fill, .spec_nm = {5, 0}},
    [SPM_MODE_RGB] = {.id = SPM_MODE_RGB, .name = "rgb", .help = "three components (linear sRGB)",
                      .kernel = "spm_shade_rgb", .define = "SPM_SHADE_RGB", .layout = rgb_layout,
                      .fill = rgb_fill, .one_index = 1},
};

const spm_mode_desc *spm_mode(int id)
{
    return id >= 0 && id < SPM_MODE_COUNT ? &spm_modes[id] : NULL;
}

int spm_mode_parse(const char *name)
{
    for (int m = 0; m < SPM_MODE_COUNT; m++)
        if (!strcmp(name, spm_modes[m].name))
            return m;
    return -1;
}

const char *spm_mode_name(int id)
{
    const spm_mode_desc *m = spm_mode(id);
    return m ? m->name : "?";
}

const char *spm_mode_list(const char *sep, char *buf, size_t size)
{
    size_t n = 0;
    buf[0] = '\0';
    for (int m = 0; m < SPM_MODE_COUNT && n < size; m++)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", m ? sep : "", spm_modes[m].name);
    return buf;
}

int spm_mode_nslots(const spm_mode_desc *m)
{
    return m->levelled ? SPM_NUM_LEVELS : 1;
}

int spm_mode_slot(const spm_mode_desc *m, uint8_t level)
{
    if (!m->levelled)
        return 0;
    int l = (int)(level & SPM_LEVEL_MASK);
    return l < SPM_NUM_LEVELS ? l : SPM_NUM_LEVELS - 1;
}

int spm_mode_slot_level(const spm_mode_desc *m, int slot)
{
    return m->levelled ? slot : m->level;
}

const uint8_t *spm_mode_lvlk(const spm_mode_desc *m, const spm_tables *t)
{
    return m->composite ? t->mlc_lvlk : t->lvlk;
}

int spm_mode_check(const spm_mode_desc *m, const spm_tables *t, spm_error *err)
{
    if (m->per_path && t->nfluor) {
        spm_errorf(err, "%s mode cannot render fluorescent materials (a wavelength drawn per "
                        "path has no way to another wavelength); use truth, ref, ml, mlc or rgb",
                   m->name);
        return 1;
    }
    if (m->levelled && !t->levels_done[m->composite != 0]) {
        spm_errorf(err, "%s mode reads levels its pretest has not given (spm_tables_levels)",
                   m->name);
        return 1;
    }
    if (m->composite && !t->mlc_lvlk) {
        spm_errorf(err, "%s mode needs the Composite Model tables", m->name);
        return 1;
    }
    return 0;
}

void spm_mode_kernel(const spm_mode_desc *m, const spm_tables *t, int slot, char *name,
                     size_t name_size, char *define, size_t define_size)
{
    spm_shade_table lo = {0};
    m->layout(t, spm_mode_slot_level(m, slot), &lo);
    int nv = lo.stride / lo.width;
    if (m->levelled) {
        snprintf(name, name_size, m->kernel, slot);
        snprintf(define, define_size, m->define, slot, nv);
    } else {
        snprintf(name, name_size, "%s", m->kernel);
        snprintf(define, define_size, m->define, nv);
    }
}

void spm_shade_table_build(const spm_mode_desc *m, const spm_tables *t, int slot,
                           spm_shade_table *o)
{
    int level = spm_mode_slot_level(m, slot);
    memset(o, 0, sizeof *o);
    m->layout(t, level, o);
    o->ncolours = t->ncolours;
    o->nfluor = t->nfluor;
    o->fluor_first = t->fluor_first;
    o->fluor_floats = m->per_path ? 0 : (size_t)t->nfluor * (size_t)o->stride * (size_t)o->stride;
    o->rows = spm_xcalloc((size_t)t->ncolours * (size_t)o->stride + o->fluor_floats + 1,
                          sizeof *o->rows);
    if (!m->per_path)
        o->w = spm_xcalloc(3 * (size_t)o->stride, sizeof *o->w);
    if (o->nextra)
        o->extra = spm_xcalloc(o->nextra, sizeof *o->extra);
    m->fill(t, level, o);
    if (t->ndisp) {
        o->nm1 = t->truth;
        o->nm1_w = &t->cmf_truth[0][0];
    }
}

void spm_shade_table_free(spm_shade_table *tab)
{
    free(tab->rows);
    free(tab->w);
    free(tab->extra);
    memset(tab, 0, sizeof *tab);
}

size_t spm_mode_footprint(const spm_mode_desc *m, const spm_tables *t)
{
    size_t floats = 0;
    for (int s = 0; s < spm_mode_nslots(m); s++) {
        spm_shade_table lo = {0};
        m->layout(t, spm_mode_slot_level(m, s), &lo);
        floats += ((size_t)t->ncolours + (m->per_path ? 0 : 3)) * (size_t)lo.stride + lo.nextra;
        if (!m->per_path) /* the fluorescence blocks (modes.h) */
            floats += (size_t)t->nfluor * (size_t)lo.stride * (size_t)lo.stride;
    }
    return floats * sizeof(float);
}

void spm_modes_help(FILE *f, int indent)
{
    for (int m = 0; m < SPM_MODE_COUNT; m++)
        fprintf(f, "%*s%-6s %s\n", indent, "", spm_modes[m].name, spm_modes[m].help);
}

void spm_modes_print(FILE *f, int json)
{
    if (json)
        fprintf(f, "[");
    for (int i = 0; i < SPM_MODE_COUNT; i++) {
        const spm_mode_desc *m = &spm_modes[i];
        if (json)
            fprintf(f,
                    "%s\n  {\"name\": \"%s\", \"levelled\": %s, \"composite\": %s, "
                    "\"per_path\": %s, \"help\": \"%s\"}",
                    i ? "," : "", m->name, m->levelled ? "true" : "false",
                    m->composite ? "true" : "false", m->per_path ? "true" : "false", m->help);
        else
            fprintf(f, "%s\t%s\t%s\n", m->name, m->levelled ? "levelled" : "single", m->help);
    }
    if (json)
        fprintf(f, "\n]\n");
}

int spm_mode_spec_ok(const spm_mode_desc *m, int nm)
{
    return nm > 0 && (m->spec_nm[0] == nm || m->spec_nm[1] == nm);
}

void spm_spec_map_build(const spm_mode_desc *m, const spm_tables *t, int slot, int nm,
                        spm_spec_map *o)
{
    memset(o, 0, sizeof *o);
    o->nbins = (SPM_LAMBDA_MAX - SPM_LAMBDA_MIN) / nm;
    if (!m->spec_map)
        return;
    int level = spm_mode_slot_level(m, slot);
    m->spec_map(t, level, nm, o);
    o->idx = spm_xcalloc((size_t)o->nbins + 1 + (size_t)o->nnz, sizeof *o->idx);
    o->fac = spm_xcalloc((size_t)o->nnz + 1, sizeof *o->fac);
    m->spec_map(t, level, nm, o);
}

void spm_spec_map_free(spm_spec_map *map)
{
    free(map->idx);
    free(map->fac);
    memset(map, 0, sizeof *map);
}
