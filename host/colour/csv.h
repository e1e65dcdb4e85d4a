/* CSV tables of spectra: first column wavelength in nm, one or more value columns.
 * Lines starting with '#' are comments (provenance lines); the first
 * non-comment line is the header of column names. */
#ifndef SPM_CSV_H
#define SPM_CSV_H
#include <stddef.h>
#include "util.h"

typedef struct {
    int ncols;        /* including the wavelength column */
    char **names;     /* ncols names */
    size_t nrows;
    double *data;     /* nrows * ncols, row-major */
    int *line;        /* source line number of each row */
    int header_line;  /* source line number of the header */
} spm_csv;

/* Errors name file and line: "path:LINE: problem". Returns 0 or fills err. */
int spm_csv_load(const char *path, spm_csv *out, spm_error *err);
void spm_csv_free(spm_csv *csv);

/* Index of the value column called `name` (1..ncols-1), or -1. */
int spm_csv_column(const spm_csv *csv, const char *name);
#endif
