/* The saved film (film_file.h). */
#include "film_file.h"
#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "film_spectral.h"
#include "image_io.h"
#include "interrupt.h"

#define MAGIC_LINE "specmip film 1\n"
#define HEADER_MAX 65536

void spm_film_print_add(spm_film_print *p, int compared, const char *key, const char *fmt, ...)
{
    if (p->n >= SPM_FILM_ITEMS)
        return;
    spm_film_item *it = &p->item[p->n++];
    snprintf(it->key, sizeof it->key, "%s", key);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(it->value, sizeof it->value, fmt, ap);
    va_end(ap);
    for (char *c = it->value; *c; c++)
        if (*c == '\n' || *c == '\r')
            *c = '?';
    it->compared = compared;
}

const char *spm_film_print_get(const spm_film_print *p, const char *key)
{
    for (int i = 0; i < p->n; i++)
        if (!strcmp(p->item[i].key, key))
            return p->item[i].value;
    return NULL;
}

int spm_film_print_diff(const spm_film_print *saved, const spm_film_print *now, const char *last,
                        char *msg, size_t size)
{
    int ndiff = 0;
    size_t at = 0;
    msg[0] = 0;
    for (int round = 0; round < 2 && !(round == 1 && ndiff); round++)
        for (int i = 0; i < now->n; i++) {
            const spm_film_item *it = &now->item[i];
            int is_last = last && !strcmp(it->key, last);
            if (!it->compared || is_last != (round == 1))
                continue;
            const char *was = spm_film_print_get(saved, it->key);
            if (was && !strcmp(was, it->value))
                continue;
            int w = snprintf(msg + at, at < size ? size - at : 0, "%s%s %s (this render: %s)",
                             ndiff ? "; " : "", it->key, was ? was : "not recorded", it->value);
            at += w > 0 ? (size_t)w : 0;
            ndiff++;
        }
    return ndiff;
}

/* ---- writing ---- */

typedef struct {
    FILE *f;
    uint64_t hash;
    int ok, errnum;
} out_file;

static void put(out_file *o, const void *p, size_t n)
{
    if (!o->ok)
        return;
    o->hash = spm_fnv1a64(o->hash, p, n);
    if (fwrite(p, 1, n, o->f) != n) {
        o->ok = 0;
        o->errnum = errno;
    }
}

static void put_text(out_file *o, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put_text(out_file *o, const char *fmt, ...)
{
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    put(o, line, n < (int)sizeof line ? (size_t)n : sizeof line - 1);
}

static void put_film(out_file *o, const spm_film *f, const spm_film_print *p, int pass_spp)
{
    put_text(o, MAGIC_LINE);
    put_text(o, "width=%d\nheight=%d\nsamples=%lld\nnonfinite=%lld\npass_spp=%d\n", f->width,
             f->height, f->samples, f->nonfinite, pass_spp);
    for (int i = 0; i < p->n; i++)
        put_text(o, "%s.%s=%s\n", p->item[i].compared ? "match" : "info", p->item[i].key,
                 p->item[i].value);
    put_text(o, "layer=xyz f64 3\n");
    if (f->nspec)
        put_text(o, "layer=spectral f64 %d\n", f->nspec);
    put_text(o, "end\n");
    size_t npix = (size_t)f->width * f->height;
    put(o, f->sum, npix * 3 * sizeof *f->sum);
    if (f->nspec)
        put(o, f->spec, npix * (size_t)f->nspec * sizeof *f->spec);
    uint64_t h = o->hash;
    put(o, &h, sizeof h);
}

int spm_film_save(const char *path, const spm_film *f, const spm_film_print *p, int pass_spp,
                  spm_error *err)
{
    char *target = spm_image_target(path, err);
    if (!target)
        return 1;
    int slot = -1, errnum = 0;
    char *tmp = spm_temp_create(target, ".film", &slot, &errnum);
    if (!tmp) {
        spm_errorf(err, "%s: cannot create a temporary file next to it: %s", path,
                   strerror(errnum));
        free(target);
        return 1;
    }
    spm_test_pause("film");
    out_file o = {fopen(tmp, "wb"), SPM_FNV1A64_BASIS, 1, 0};
    if (!o.f) {
        o.ok = 0;
        o.errnum = errno;
    } else {
        put_film(&o, f, p, pass_spp);
        /* on the disk before it replaces the previous film */
        if (o.ok && (fflush(o.f) || fsync(fileno(o.f)))) {
            o.ok = 0;
            o.errnum = errno;
        }
        if (fclose(o.f) && o.ok) {
            o.ok = 0;
            o.errnum = errno;
        }
    }
    if (o.ok && rename(tmp, target)) {
        o.ok = 0;
        o.errnum = errno;
    }
    if (!o.ok)
        unlink(tmp);
    spm_temp_unregister(slot);
    if (!o.ok)
        spm_errorf(err, "%s: cannot write the film: %s (the previous film, if any, is kept)",
                   path, strerror(o.errnum));
    free(tmp);
    free(target);
    return !o.ok;
}

/* ---- reading ---- */

/* One header line into the film or the print; 0, or 1 with err filled. */
static int header_line(const char *path, char *line, spm_film *f, spm_film_print *p, int *pass_spp,
                       int *nspec, int *have_xyz, spm_error *err)
{
    char *eq = strchr(line, '=');
    if (!eq) {
        spm_errorf(err, "%s: not a specmip film (header line '%.60s')", path, line);
        return 1;
    }
    *eq = 0;
    const char *key = line, *val = eq + 1;
    char type[16];
    int ch;
    if (!strncmp(key, "match.", 6) || !strncmp(key, "info.", 5)) {
        int compared = key[0] == 'm';
        spm_film_print_add(p, compared, key + (compared ? 6 : 5), "%s", val);
        return 0;
    }
    if (!strcmp(key, "layer")) {
        char name[32];
        if (sscanf(val, "%31s %15s %d", name, type, &ch) == 3 && !strcmp(type, "f64")) {
            if (!strcmp(name, "xyz") && ch == 3) {
                *have_xyz = 1;
                return 0;
            }
            if (!strcmp(name, "spectral") && ch > 0 && ch <= 400) {
                *nspec = ch;
                return 0;
            }
        }
        spm_errorf(err, "%s: holds a layer '%s' this specmip does not read", path, val);
        return 1;
    }
    char *end;
    long long v = strtoll(val, &end, 10);
    if (!*val || *end || v < 0) {
        spm_errorf(err, "%s: header: '%s=%.60s' is not a number", path, key, val);
        return 1;
    }
    if (!strcmp(key, "width") && v <= 1 << 20)
        f->width = (int)v;
    else if (!strcmp(key, "height") && v <= 1 << 20)
        f->height = (int)v;
    else if (!strcmp(key, "samples") && v <= 1 << 30)
        f->samples = v;
    else if (!strcmp(key, "nonfinite"))
        f->nonfinite = v;
    else if (!strcmp(key, "pass_spp") && v >= 1 && v <= 1 << 30)
        *pass_spp = (int)v;
    else {
        spm_errorf(err, "%s: header: unknown or out of range '%s=%.60s'", path, key, val);
        return 1;
    }
    return 0;
}

/* The header from buf[0..n): its length in *len. 0, or 1 with err filled. */
static int read_header(const char *path, char *buf, size_t n, size_t *len, spm_film *f,
                       spm_film_print *p, int *pass_spp, int *nspec, spm_error *err)
{
    size_t m = strlen(MAGIC_LINE);
    if (n < m || memcmp(buf, MAGIC_LINE, m)) {
        spm_errorf(err, "%s: not a specmip film (it does not begin '%.14s')", path, MAGIC_LINE);
        return 1;
    }
    int have_xyz = 0;
    for (size_t at = m;;) {
        char *nl = memchr(buf + at, '\n', n - at);
        if (!nl) {
            spm_errorf(err, "%s: truncated in its header", path);
            return 1;
        }
        *nl = 0;
        if (!strcmp(buf + at, "end")) {
            *len = (size_t)(nl - buf) + 1;
            break;
        }
        if (header_line(path, buf + at, f, p, pass_spp, nspec, &have_xyz, err))
            return 1;
        at = (size_t)(nl - buf) + 1;
    }
    if (!have_xyz || f->width < 1 || f->height < 1 || *pass_spp < 1) {
        spm_errorf(err, "%s: header without %s", path,
                   !have_xyz ? "the xyz layer" : *pass_spp < 1 ? "pass_spp" : "its size");
        return 1;
    }
    return 0;
}

/* Reads n bytes into dst, hashing them; 0 when the file ends first. */
static int get(FILE *in, void *dst, size_t n, uint64_t *h)
{
    if (fread(dst, 1, n, in) != n)
        return 0;
    *h = spm_fnv1a64(*h, dst, n);
    return 1;
}

int spm_film_load(const char *path, spm_film *f, spm_film_print *p, int *pass_spp,
                  spm_error *err)
{
    memset(f, 0, sizeof *f);
    memset(p, 0, sizeof *p);
    *pass_spp = 0;
    FILE *in = fopen(path, "rb");
    struct stat st;
    if (!in || fstat(fileno(in), &st)) {
        spm_errorf(err, "%s: cannot open the film: %s", path, strerror(errno));
        if (in)
            fclose(in);
        return 1;
    }
    char *buf = spm_xmalloc(HEADER_MAX + 1);
    size_t n = fread(buf, 1, HEADER_MAX, in), len = 0;
    buf[n] = 0;
    char *raw = spm_xmalloc(n + 1); /* read_header cuts buf into lines; the checksum reads this */
    memcpy(raw, buf, n + 1);
    spm_film h;
    memset(&h, 0, sizeof h);
    int nspec = 0, rc = read_header(path, buf, n, &len, &h, p, pass_spp, &nspec, err);
    size_t npix = (size_t)h.width * (size_t)h.height;
    unsigned long long want = len + npix * (3 + (size_t)nspec) * sizeof(double) + sizeof(uint64_t);
    if (!rc && (unsigned long long)st.st_size != want) {
        spm_errorf(err, "%s: %s: %lld bytes where its header describes %llu", path,
                   (unsigned long long)st.st_size < want ? "truncated"
                                                         : "has bytes beyond the film",
                   (long long)st.st_size, want);
        rc = 1;
    }
    if (!rc && (spm_film_init(f, h.width, h.height, err) ||
                (nspec && spm_film_spectral_init(f, nspec, err))))
        rc = 1;
    if (!rc) {
        uint64_t hash = spm_fnv1a64(SPM_FNV1A64_BASIS, raw, len), stored = 0;
        fseek(in, (long)len, SEEK_SET);
        int whole = get(in, f->sum, npix * 3 * sizeof *f->sum, &hash) &&
                    (!nspec || get(in, f->spec, npix * (size_t)nspec * sizeof *f->spec, &hash));
        uint64_t computed = hash;
        whole = whole && get(in, &stored, sizeof stored, &hash);
        if (!whole || stored != computed) {
            spm_errorf(err, "%s: %s", path,
                       whole ? "corrupt: its checksum does not match its contents"
                             : "truncated while it was read");
            rc = 1;
        }
        f->samples = h.samples;
        f->nonfinite = h.nonfinite;
    }
    free(raw);
    free(buf);
    fclose(in);
    if (rc)
        spm_film_free(f);
    return rc;
}
