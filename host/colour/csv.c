/* CSV spectra: '#' comment lines, a header of column names, then numeric rows.
 * Every error names the file and the line it was found on. */
#include "csv.h"
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "interrupt.h"

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    char *e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = '\0';
    return s;
}

/* Splits `line` in place at commas; returns the number of fields (up to max). */
static int split(char *line, char **fields, int max)
{
    int n = 0;
    for (char *p = line;;) {
        char *comma = strchr(p, ',');
        if (comma)
            *comma = '\0';
        if (n < max)
            fields[n] = trim(p);
        n++;
        if (!comma)
            return n;
        p = comma + 1;
    }
}

static int count_fields(const char *line)
{
    int n = 1;
    for (; *line; line++)
        n += *line == ',';
    return n;
}

static int is_blank_or_comment(const char *line)
{
    while (isspace((unsigned char)*line))
        line++;
    return *line == '\0' || *line == '#';
}

static int parse_row(spm_csv *c, char *line, int lineno, const char *path, spm_error *err)
{
    int n = count_fields(line);
    if (n != c->ncols) {
        spm_errorf(err, "%s:%d: expected %d columns, found %d", path, lineno, c->ncols, n);
        return 1;
    }
    char **f = spm_xmalloc((size_t)n * sizeof *f);
    split(line, f, n);
    if ((c->nrows & (c->nrows - 1)) == 0) { /* 0 or a power of two: double the room */
        size_t rows = c->nrows ? 2 * c->nrows : 1;
        c->data = spm_xrealloc(c->data, rows * (size_t)n * sizeof *c->data);
        c->line = spm_xrealloc(c->line, rows * sizeof *c->line);
    }
    double *row = c->data + c->nrows * (size_t)n;
    for (int i = 0; i < n; i++) {
        char *end;
        errno = 0;
        row[i] = strtod(f[i], &end);
        if (end == f[i] || *end != '\0') {
            spm_errorf(err, "%s:%d: column %d (%s): '%s' is not a number", path, lineno, i + 1,
                       c->names[i], f[i]);
            free(f);
            return 1;
        }
        if (!isfinite(row[i])) {
            spm_errorf(err, "%s:%d: column %d (%s): '%s' is not a finite number", path, lineno,
                       i + 1, c->names[i], f[i]);
            free(f);
            return 1;
        }
    }
    free(f);
    c->line[c->nrows++] = lineno;
    return 0;
}

/* A finite number (a column may be called "nan" or "inf", never "380"). */
static int is_number(const char *s)
{
    char *end;
    double v = strtod(s, &end);
    return end != s && *end == '\0' && isfinite(v);
}

/* The header: column names, none of them a number (a file whose first row is
 * data has no header, and taking that row as names would drop it silently)
 * and no two alike (a column is chosen by its name). */
static int set_header(spm_csv *c, char *line, int lineno, const char *path, spm_error *err)
{
    c->ncols = count_fields(line);
    char **f = spm_xmalloc((size_t)c->ncols * sizeof *f);
    split(line, f, c->ncols);
    c->names = spm_xmalloc((size_t)c->ncols * sizeof *c->names);
    for (int i = 0; i < c->ncols; i++)
        c->names[i] = spm_xstrdup(f[i]);
    free(f);
    for (int i = 0; i < c->ncols; i++) {
        if (is_number(c->names[i])) {
            spm_errorf(err, "%s:%d: no header row: column %d of the first line that is not a "
                            "comment is the number '%s'; a spectrum file starts with a row of "
                            "column names, such as 'wavelength_nm,value'",
                       path, lineno, i + 1, c->names[i]);
            return 1;
        }
        for (int j = 0; j < i; j++)
            if (strcmp(c->names[i], c->names[j]) == 0) {
                spm_errorf(err, "%s:%d: columns %d and %d are both named '%s'; each column "
                                "needs its own name", path, lineno, j + 1, i + 1, c->names[i]);
                return 1;
            }
    }
    return 0;
}

/* Longest line kept: spectra rows are short, and a longer line (a 100 MB line,
 * binary data) is refused without being held. Comment lines may be longer. */
#define CSV_LINE_MAX 65536

enum { LINE_OK, LINE_EOF, LINE_TOO_LONG, LINE_NUL };

static int is_comment(const char *line)
{
    while (isspace((unsigned char)*line))
        line++;
    return *line == '#';
}

/* Reads one line (without its newline) into buf[CSV_LINE_MAX]. A comment is
 * cut short at the buffer's end and skipped to the line's end; any other line
 * that is too long or holds a NUL byte is refused, its rest left unread. */
static int read_line(FILE *fp, char *buf)
{
    size_t n = 0;
    int c;
    while ((c = getc_unlocked(fp)) != EOF && c != '\n') { /* one reader: no lock per byte */
        if (n + 1 == CSV_LINE_MAX || c == '\0') {
            buf[n] = '\0';
            if (!is_comment(buf))
                return c == '\0' ? LINE_NUL : LINE_TOO_LONG;
            continue;
        }
        buf[n++] = (char)c;
    }
    buf[n] = '\0';
    return c == EOF && n == 0 ? LINE_EOF : LINE_OK;
}

int spm_csv_load(const char *path, spm_csv *out, spm_error *err)
{
    memset(out, 0, sizeof *out);
    FILE *fp = spm_fopen_input(path, "r");
    if (!fp) {
        spm_errorf(err, "%s:0: cannot open: %s", path, strerror(errno));
        return 1;
    }
    /* a directory opens for reading on Linux, and then reads as nothing */
    struct stat st;
    if (fstat(fileno(fp), &st) == 0 && S_ISDIR(st.st_mode)) {
        spm_errorf(err, "%s: is a directory, not a CSV spectrum file", path);
        fclose(fp);
        return 1;
    }
    char *line = spm_xmalloc(CSV_LINE_MAX);
    int lineno = 0, rc = 0, got;
    while ((got = read_line(fp, line)) != LINE_EOF) {
        lineno++;
        spm_test_pause("csv");
        if (spm_stop_requested()) {
            spm_errorf(err, "interrupted while loading %s (line %d)", path, lineno);
            rc = 1;
            break;
        }
        if (got != LINE_OK) {
            spm_errorf(err, "%s:%d: %s", path, lineno,
                       got == LINE_NUL ? "NUL byte in a text line (binary data?)"
                                       : "line longer than 65535 bytes (not a spectrum table)");
            rc = 1;
            break;
        }
        if (is_blank_or_comment(line))
            continue;
        if (!out->names) {
            out->header_line = lineno;
            if (set_header(out, line, lineno, path, err)) {
                rc = 1;
                break;
            }
            if (out->ncols < 2) {
                spm_errorf(err, "%s:%d: header needs a wavelength column and a value column",
                           path, lineno);
                rc = 1;
                break;
            }
            continue;
        }
        if (parse_row(out, line, lineno, path, err)) {
            rc = 1;
            break;
        }
    }
    free(line);
    if (!rc && ferror(fp)) {
        spm_errorf(err, "%s:%d: read error: %s", path, lineno + 1, strerror(errno));
        rc = 1;
    }
    fclose(fp);
    if (!rc && !out->names) {
        spm_errorf(err, "%s:%d: empty file: no header line", path, lineno > 0 ? lineno : 1);
        rc = 1;
    } else if (!rc && out->nrows == 0) {
        spm_errorf(err, "%s:%d: no data rows after the header", path, lineno);
        rc = 1;
    }
    if (rc)
        spm_csv_free(out);
    return rc;
}

void spm_csv_free(spm_csv *c)
{
    for (int i = 0; c->names && i < c->ncols; i++)
        free(c->names[i]);
    free(c->names);
    free(c->data);
    free(c->line);
    memset(c, 0, sizeof *c);
}

int spm_csv_column(const spm_csv *c, const char *name)
{
    for (int i = 1; i < c->ncols; i++)
        if (strcmp(c->names[i], name) == 0)
            return i;
    return -1;
}
