/* Writing a film or XYZ image in the format its extension names. */
#include "output.h"
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>
#include "colour.h"
#include "image_io.h"
#include "interrupt.h"

typedef enum { OUT_UNKNOWN, OUT_FLOAT, OUT_DISPLAY } out_kind;

static const struct {
    const char *ext;
    out_kind kind;
} formats[] = {
    {".exr", OUT_FLOAT}, {".tif", OUT_FLOAT}, {".tiff", OUT_FLOAT},
    {".hdr", OUT_FLOAT}, /* Radiance RGBE: no negative values */
    {".png", OUT_DISPLAY}, {".ppm", OUT_DISPLAY}, {".jpg", OUT_DISPLAY}, {".jpeg", OUT_DISPLAY},
};

static out_kind kind_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash : path, '.');
    if (dot)
        for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++)
            if (!strcasecmp(dot, formats[i].ext))
                return formats[i].kind;
    return OUT_UNKNOWN;
}

int spm_output_check(const char *path, spm_error *err)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (kind_of(path) == OUT_UNKNOWN) {
        char list[128] = "";
        size_t n = 0, nf = sizeof formats / sizeof formats[0];
        for (size_t i = 0; i < nf; i++)
            n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", i ? (i + 1 < nf ? ", " : " or ") : "",
                                  formats[i].ext);
        spm_errorf(err, "%s: unknown output format (use %s)", path, list);
        return 1;
    }
    if (strrchr(base, '.') == base) {
        spm_errorf(err, "%s: no file name before the extension", path);
        return 1;
    }
    char *target = spm_image_target(path, err);
    if (!target)
        return 1;
    int rc = 0;
    struct stat st;
    const char *tslash = strrchr(target, '/');
    char *dir = spm_xstrdup(target);
    dir[tslash == target ? 1 : tslash - target] = '\0';
    const char *link = strcmp(path, target) ? " (where the symbolic link leads)" : "";
    if (stat(target, &st) == 0 && S_ISDIR(st.st_mode)) {
        spm_errorf(err, "%s: is a directory%s", path, link);
        rc = 1;
    } else if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        spm_errorf(err, "%s: '%s'%s is not a directory", path, dir, link);
        rc = 1;
    } else if (access(dir, W_OK | X_OK) != 0) {
        spm_errorf(err, "%s: output directory '%s'%s is not writable: %s", path, dir, link,
                   strerror(errno));
        rc = 1;
    } else {
        /* access() says yes to root everywhere (/proc, /sys, read-only mounts):
         * only creating a file tells */
        size_t n = strlen(dir) + 64;
        char *probe = spm_xmalloc(n);
        snprintf(probe, n, "%s/.specmip-probe-%ld", dir, (long)getpid());
        int slot = spm_temp_register(probe);
        int fd = open(probe, O_WRONLY | O_CREAT | O_EXCL, 0600);
        if (fd < 0) {
            spm_errorf(err, "%s: cannot create files in '%s'%s: %s", path, dir, link,
                       strerror(errno));
            rc = 1;
        } else {
            close(fd);
            unlink(probe);
        }
        spm_temp_unregister(slot);
        free(probe);
    }
    free(dir);
    free(target);
    return rc;
}

int spm_output_check_all(const char *const *paths, int n, spm_error *err)
{
    char **t = spm_xcalloc((size_t)n + 1, sizeof *t);
    int rc = 0;
    for (int i = 0; i < n && !rc; i++) {
        rc = spm_output_check(paths[i], err) || !(t[i] = spm_image_target(paths[i], err));
        for (int j = 0; j < i && !rc; j++)
            if (!strcmp(t[i], t[j])) {
                if (!strcmp(paths[i], paths[j]))
                    spm_errorf(err, "%s: given twice as an output", paths[i]);
                else
                    spm_errorf(err, "%s and %s: the same file (%s) given twice as an output",
                               paths[j], paths[i], t[i]);
                rc = 1;
            }
    }
    for (int i = 0; i < n; i++)
        free(t[i]);
    free(t);
    return rc;
}

static int write_xyz(const char *path, int width, int height, const float *xyz,
                     const spm_tonemap *tm, const spm_image_attr *attrs, int nattrs,
                     spm_error *err)
{
    out_kind kind = kind_of(path);
    if (kind == OUT_UNKNOWN)
        return spm_output_check(path, err);
    size_t npix = (size_t)width * height;
    int rc;
    float *balanced = NULL;
    if (tm && tm->adapt) { /* white balance: on a copy, the film's XYZ stays as rendered */
        balanced = spm_xmalloc(npix * 3 * sizeof *balanced);
        memcpy(balanced, xyz, npix * 3 * sizeof *balanced);
        spm_tonemap_white_balance(tm, balanced, npix);
        xyz = balanced;
    }
    if (kind == OUT_FLOAT) {
        float *rgb = spm_xmalloc(npix * 3 * sizeof *rgb);
        for (size_t i = 0; i < npix; i++) {
            double v[3] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}, out[3];
            spm_xyz_to_linear_srgb(v, out);
            for (int c = 0; c < 3; c++)
                rgb[3 * i + c] = (float)out[c];
        }
        rc = spm_image_write_attrs(path, width, height, rgb, SPM_PIXEL_FLOAT, attrs, nattrs, err);
        free(rgb);
    } else {
        spm_tonemap def;
        if (!tm) {
            spm_tonemap_default(&def);
            tm = &def;
        }
        unsigned char *rgb8 = spm_xmalloc(npix * 3);
        spm_tonemap_apply(tm, xyz, npix, rgb8);
        rc = spm_image_write_attrs(path, width, height, rgb8, SPM_PIXEL_UINT8, attrs, nattrs, err);
        free(rgb8);
    }
    free(balanced);
    return rc;
}

int spm_output_write_xyz(const char *path, int width, int height, const float *xyz,
                         const spm_tonemap *tm, spm_error *err)
{
    return write_xyz(path, width, height, xyz, tm, NULL, 0, err);
}

int spm_output_write_film(const char *path, const spm_film *film, const spm_tonemap *tm,
                          spm_error *err)
{
    return spm_output_write_film_attrs(path, film, tm, NULL, 0, err);
}

int spm_output_write_film_attrs(const char *path, const spm_film *film, const spm_tonemap *tm,
                                const spm_image_attr *attrs, int nattrs, spm_error *err)
{
    float *xyz = spm_xmalloc((size_t)film->width * film->height * 3 * sizeof *xyz);
    spm_film_resolve(film, xyz);
    int rc = write_xyz(path, film->width, film->height, xyz, tm, attrs, nattrs, err);
    free(xyz);
    return rc;
}
