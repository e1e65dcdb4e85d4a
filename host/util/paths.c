/* The rule for files a scene references (paths.h). The folders are set before
 * a scene loads and only read while it loads. */
#include "paths.h"
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_ALLOWED 64

static char root[SPM_PATH_MAX];
static char allowed[MAX_ALLOWED][SPM_PATH_MAX];
static int nallowed;

/* Appends the components of `rel` to the absolute, canonical `base` (which
 * holds SPM_PATH_MAX bytes), "." dropped and ".." taking one off. */
static int append_lexical(char *base, const char *rel)
{
    const char *s = rel;
    while (*s) {
        while (*s == '/')
            s++;
        size_t n = strcspn(s, "/");
        if (n == 0)
            break;
        if (n == 2 && s[0] == '.' && s[1] == '.') {
            char *slash = strrchr(base, '/');
            slash[slash == base ? 1 : 0] = '\0';
        } else if (!(n == 1 && s[0] == '.')) {
            size_t len = strlen(base);
            int sep = len > 1;
            if (len + sep + n + 1 > SPM_PATH_MAX)
                return 1;
            if (sep)
                base[len++] = '/';
            memcpy(base + len, s, n);
            base[len + n] = '\0';
        }
        s += n;
    }
    return 0;
}

/* `path` made absolute and canonical into out (SPM_PATH_MAX bytes): the
 * longest part of it that exists through realpath (links followed), the rest,
 * which does not exist and so holds no link, appended lexically. */
static int canonical(const char *path, char *out)
{
    char abs[2 * SPM_PATH_MAX];
    if (path[0] == '/') {
        if (strlen(path) >= sizeof abs)
            return 1;
        strcpy(abs, path);
    } else {
        char cwd[SPM_PATH_MAX];
        if (!getcwd(cwd, sizeof cwd) ||
            snprintf(abs, sizeof abs, "%s/%s", cwd, path) >= (int)sizeof abs)
            return 1;
    }
    char real[PATH_MAX];
    if (realpath(abs, real)) {
        if (strlen(real) >= SPM_PATH_MAX)
            return 1;
        strcpy(out, real);
        return 0;
    }
    /* the deepest folder above it that resolves, then the rest as written */
    size_t cut = strlen(abs);
    for (;;) {
        while (cut > 0 && abs[cut - 1] != '/')
            cut--;
        while (cut > 1 && abs[cut - 1] == '/')
            cut--;
        char head[2 * SPM_PATH_MAX];
        memcpy(head, abs, cut ? cut : 1);
        head[cut ? cut : 1] = '\0';
        if (realpath(head, real) || cut <= 1) {
            if (cut <= 1)
                strcpy(real, "/");
            if (strlen(real) >= SPM_PATH_MAX)
                return 1;
            strcpy(out, real);
            return append_lexical(out, abs + cut);
        }
    }
}

static int under(const char *path, const char *dir)
{
    size_t n = strlen(dir);
    if (n == 1 && dir[0] == '/')
        return 1;
    return strncmp(path, dir, n) == 0 && (path[n] == '\0' || path[n] == '/');
}

const char *spm_path_dir(const char *file, char *buf, size_t size)
{
    const char *slash = strrchr(file, '/');
    if (!slash)
        snprintf(buf, size, ".");
    else if (slash == file)
        snprintf(buf, size, "/");
    else
        snprintf(buf, size, "%.*s", (int)(slash - file), file);
    return buf;
}

int spm_paths_set_root(const char *file, spm_file *top, spm_error *err)
{
    char dir[SPM_PATH_MAX];
    if (strlen(file) >= SPM_PATH_MAX || canonical(spm_path_dir(file, dir, sizeof dir), root) ||
        canonical(file, top->path)) {
        root[0] = '\0';
        spm_errorf(err, "%s: the path is too long to resolve", file);
        return 1;
    }
    snprintf(top->shown, sizeof top->shown, "%s", file);
    return 0;
}

int spm_paths_allow(const char *dir, spm_error *err)
{
    char real[PATH_MAX];
    if (nallowed == MAX_ALLOWED) {
        spm_errorf(err, "--allow-path %s: at most %d folders may be allowed", dir, MAX_ALLOWED);
        return 1;
    }
    if (!realpath(dir, real) || strlen(real) >= SPM_PATH_MAX) {
        spm_errorf(err, "--allow-path %s: %s", dir, strerror(errno ? errno : ENAMETOOLONG));
        return 1;
    }
    char probe[PATH_MAX + 3];
    snprintf(probe, sizeof probe, "%s/.", real);
    if (access(probe, F_OK) != 0) {
        spm_errorf(err, "--allow-path %s: not a folder", dir);
        return 1;
    }
    strcpy(allowed[nallowed++], real);
    return 0;
}

void spm_paths_clear_allowed(void)
{
    nallowed = 0;
}

/* Whether a canonical path is in the project's own data (spectra/, scenes/). */
static int in_data(const char *path)
{
    static const char *const folders[] = {"spectra", "scenes"};
    for (size_t i = 0; i < sizeof folders / sizeof folders[0]; i++) {
        char buf[SPM_PATH_MAX], real[SPM_PATH_MAX];
        if (canonical(spm_data_path(folders[i], buf, sizeof buf), real) == 0 && under(path, real))
            return 1;
    }
    return 0;
}

/* `joined` checked, `shown` (the reference as written) named in the error. */
static int check(const char *joined, const char *shown, const char *where, spm_file *out,
                 spm_error *err)
{
    char cwd[SPM_PATH_MAX];
    const char *top = root[0] ? root : getcwd(cwd, sizeof cwd) ? cwd : "/nonexistent";
    if (strlen(joined) >= SPM_PATH_MAX || canonical(joined, out->path)) {
        spm_errorf(err, "%s: '%s': the path is too long to resolve", where, shown);
        return 1;
    }
    snprintf(out->shown, sizeof out->shown, "%s", joined);
    if (under(out->path, top) || in_data(out->path))
        return 0;
    for (int i = 0; i < nallowed; i++)
        if (under(out->path, allowed[i]))
            return 0;
    char dir[SPM_PATH_MAX];
    spm_errorf(err, "%s: '%s' leads outside the scene's folder %s (to %s): a scene may read "
                    "only below its own folder; to allow this, add --allow-path %s",
               where, shown, top, out->path, spm_path_dir(out->path, dir, sizeof dir));
    return 1;
}

int spm_path_check_joined(const char *path, const char *where, spm_file *out, spm_error *err)
{
    return check(path, path, where, out, err);
}

int spm_path_check(const char *dir, const char *ref, const char *where, spm_file *out,
                   spm_error *err)
{
    char joined[2 * SPM_PATH_MAX];
    if (ref[0] == '\0') {
        spm_errorf(err, "%s: an empty file name", where);
        return 1;
    }
    if (ref[0] == '/')
        snprintf(joined, sizeof joined, "%s", ref);
    else if (snprintf(joined, sizeof joined, "%s/%s", dir, ref) >= SPM_PATH_MAX) {
        spm_errorf(err, "%s: '%s': the path is too long", where, ref);
        return 1;
    }
    return check(joined, ref, where, out, err);
}

FILE *spm_path_fopen(const spm_file *p, const char *mode)
{
    return spm_fopen_input(p->path, mode);
}

static int hex(int c)
{
    return c >= '0' && c <= '9' ? c - '0'
           : c >= 'a' && c <= 'f' ? c - 'a' + 10
           : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                  : -1;
}

int spm_uri_decode(const char *uri, char *out, size_t size)
{
    size_t n = 0;
    for (const char *s = uri; *s; s++) {
        int c = (unsigned char)*s;
        if (c == '%') {
            int hi = hex((unsigned char)s[1]), lo = hi < 0 ? -1 : hex((unsigned char)s[2]);
            if (hi < 0 || lo < 0 || (hi | lo) == 0)
                return 1;
            c = hi * 16 + lo;
            s += 2;
        }
        if (n + 1 >= size)
            return 1;
        out[n++] = (char)c;
    }
    out[n] = '\0';
    return 0;
}
