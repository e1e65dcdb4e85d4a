/* PoCL's kernel cache, counted (pocl_cache.h). */
#define _XOPEN_SOURCE 700
#include "pocl_cache.h"
#include <ftw.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

const char *spm_pocl_cache_dir(char *buf, unsigned long size)
{
    const char *d = getenv("POCL_CACHE_DIR"), *x = getenv("XDG_CACHE_HOME"), *h = getenv("HOME");
    if (d && *d)
        snprintf(buf, size, "%s", d);
    else if (x && *x)
        snprintf(buf, size, "%s/pocl/kcache", x);
    else if (h && *h)
        snprintf(buf, size, "%s/.cache/pocl/kcache", h);
    else
        buf[0] = '\0';
    return buf;
}

/* nftw has no context argument: one walk at a time, under walk_mu */
static spm_pocl_cache walk_sum;
static pthread_mutex_t walk_mu = PTHREAD_MUTEX_INITIALIZER;

static int add_file(const char *path, const struct stat *st, int type, struct FTW *f)
{
    /* PoCL compiles into tempfile_* and renames the result into place */
    if (type == FTW_F && strncmp(path + f->base, "tempfile", 8) != 0) {
        walk_sum.files++;
        walk_sum.bytes += (long long)st->st_size;
    }
    return 0;
}

spm_pocl_cache spm_pocl_cache_now(void)
{
    char dir[4096];
    spm_pocl_cache c = {-1, 0};
    struct stat st;
    if (!spm_pocl_cache_dir(dir, sizeof dir)[0] || stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return c;
    pthread_mutex_lock(&walk_mu);
    walk_sum.files = walk_sum.bytes = 0;
    if (nftw(dir, add_file, 16, FTW_PHYS) == 0)
        c = walk_sum;
    pthread_mutex_unlock(&walk_mu);
    return c;
}

int spm_pocl_cache_grew(const spm_pocl_cache *a, const spm_pocl_cache *b)
{
    if (b->files < 0)
        return -1;
    if (a->files < 0) /* the cache directory appeared: PoCL made it to compile */
        return b->files > 0;
    return b->files != a->files || b->bytes != a->bytes;
}
