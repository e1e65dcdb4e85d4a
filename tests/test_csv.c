/* The CSV loader: comments, CRLF, column choice, and one error per bad input
 * file naming the file and the line that its first comment line announces. */
#include "spectrum.h"
#include "testutil.h"
#include <dirent.h>
#include <stdlib.h>
#include <string.h>

static const char *data(const char *rel)
{
    static char buf[4096];
    return spm_data_path(rel, buf, sizeof buf);
}

static void test_good_files(void)
{
    spm_error err = {{0}};
    spm_csv c;
    const char *p = data("tests/data/spectra/partial_irregular_crlf.csv");
    int rc = spm_csv_load(p, &c, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (!rc) {
        CHECK(c.ncols == 2 && strcmp(c.names[1], "value") == 0, "header trimmed: '%s'",
              c.names[1]);
        CHECK(c.nrows == 5, "comment and blank lines skipped: %zu rows", c.nrows);
        CHECK(c.nrows == 5 && c.line[2] == 7 && c.data[2 * 2] == 512.0, "row 3 is line %d",
              c.line[2]);
        CHECK(c.header_line == 2, "header at line %d", c.header_line);
        spm_csv_free(&c);
    }

    p = data("tests/data/spectra/two_columns.csv");
    spm_spectrum s;
    rc = spm_spectrum_load(p, NULL, SPM_KIND_REFLECTANCE, &s, &err);
    CHECK(rc != 0 && strstr(err.msg, "two_columns.csv:2:") != NULL,
          "several columns need a name: %s", err.msg);
    rc = spm_spectrum_load(p, "nope", SPM_KIND_REFLECTANCE, &s, &err);
    CHECK(rc != 0 && strstr(err.msg, "nope") != NULL, "unknown column: %s", err.msg);
    rc = spm_spectrum_load(p, "ramp", SPM_KIND_REFLECTANCE, &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    /* ramp: 0 at 380, 1 at 780, linear, so truth bin i holds (i + 0.5) / 400. */
    CHECK_NEAR(s.nm1[0], 0.5 / 400.0, 1e-12, "ramp first bin");
    CHECK_NEAR(s.nm1[399], 399.5 / 400.0, 1e-12, "ramp last bin");

    rc = spm_spectrum_load(data("tests/data/spectra/does_not_exist.csv"), NULL,
                           SPM_KIND_REFLECTANCE, &s, &err);
    CHECK(rc != 0 && strstr(err.msg, "does_not_exist.csv:0:") != NULL, "%s", err.msg);
}

/* "... line N ..." in the first line of a bad file: the line the error must name. */
static int expected_line(const char *path)
{
    FILE *f = fopen(path, "r");
    char first[512] = "";
    if (!f)
        return -1;
    if (!fgets(first, sizeof first, f))
        first[0] = '\0';
    fclose(f);
    const char *at = strstr(first, "line ");
    return first[0] == '#' && at ? atoi(at + 5) : -1;
}

static void test_bad_files(void)
{
    const char *dir = data("tests/bad-inputs");
    char dirpath[4096];
    snprintf(dirpath, sizeof dirpath, "%s", dir);
    DIR *d = opendir(dirpath);
    CHECK(d != NULL, "cannot open %s", dirpath);
    if (!d)
        return;
    int files = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        size_t len = strlen(e->d_name);
        if (len < 5 || strcmp(e->d_name + len - 4, ".csv") != 0)
            continue;
        char path[8192], want[600];
        snprintf(path, sizeof path, "%s/%s", dirpath, e->d_name);
        int line = expected_line(path);
        CHECK(line > 0, "%s: first line must be '# ... line N ...'", path);
        snprintf(want, sizeof want, "%s:%d:", e->d_name, line);
        spm_error err = {{0}};
        spm_spectrum s;
        int rc = spm_spectrum_load(path, NULL, SPM_KIND_REFLECTANCE, &s, &err);
        CHECK(rc != 0, "%s was accepted", path);
        CHECK(strstr(err.msg, want) != NULL, "message '%s' lacks '%s'", err.msg, want);
        files++;
    }
    closedir(d);
    CHECK(files >= 7, "only %d bad input files found", files);
}

int main(void)
{
    spm_quiet_warnings = 1;
    test_good_files();
    test_bad_files();
    TEST_END();
}
