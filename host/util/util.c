#include "util.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

int spm_quiet_warnings = 0;
int spm_quiet_notes = 0;

void spm_errorf(spm_error *err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    if (err)
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
}

/* One line on stderr: the prefix, the message, a newline. */
static void say(const char *prefix, const char *fmt, va_list ap)
{
    fputs(prefix, stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}

void spm_warnf(const char *fmt, ...)
{
    if (spm_quiet_warnings)
        return;
    va_list ap;
    va_start(ap, fmt);
    say("specmip: warning: ", fmt, ap);
    va_end(ap);
}

void spm_notef(const char *fmt, ...)
{
    if (spm_quiet_notes || spm_quiet_warnings)
        return;
    va_list ap;
    va_start(ap, fmt);
    say("specmip: ", fmt, ap);
    va_end(ap);
}

static void *check(void *p, size_t n)
{
    if (!p && n) {
        fprintf(stderr, "specmip: out of memory (%zu bytes)\n", n);
        exit(SPM_EXIT_RUNTIME);
    }
    return p;
}

void *spm_xmalloc(size_t n) { return check(malloc(n ? n : 1), n); }
void *spm_xcalloc(size_t c, size_t s) { return check(calloc(c ? c : 1, s ? s : 1), c * s); }
void *spm_xrealloc(void *p, size_t n) { return check(realloc(p, n ? n : 1), n); }
char *spm_xstrdup(const char *s) { return strcpy(spm_xmalloc(strlen(s) + 1), s); }

uint64_t spm_fnv1a64(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

double spm_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

const char *spm_input_files_refused;

FILE *spm_fopen_input(const char *path, const char *mode)
{
    if (spm_input_files_refused) {
        fprintf(stderr, "specmip: test hook: %s refuses to open %s\n", spm_input_files_refused,
                path);
        errno = EACCES;
        return NULL;
    }
    return fopen(path, mode);
}

const char *spm_data_path(const char *rel, char *buf, size_t bufsize)
{
    const char *root = getenv("SPECMIP_DATA");
    snprintf(buf, bufsize, "%s/%s", root && *root ? root : SPM_SOURCE_DIR, rel);
    return buf;
}

int spm_make_dirs(const char *dir, char *failed, size_t size)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", dir);
    for (char *c = buf + 1;; c++) {
        int end = !*c;
        if (*c == '/' || end) {
            *c = '\0';
            if (mkdir(buf, 0777) && errno != EEXIST) {
                if (failed)
                    snprintf(failed, size, "%s", buf);
                return -1;
            }
            if (end)
                return 0;
            *c = '/';
        }
    }
}
