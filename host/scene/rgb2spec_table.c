/* The RGB-to-spectrum coefficient table (rgb2spec_table.h): fitting, the
 * cache file, the lookup, and the model's bin means. */
#include "rgb2spec_table.h"
#include "colour.h"
#include "rgb2spec.h"
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define START_STEPS 8    /* continuation from grey to a column's first node */
#define CACHE_FORMAT 2u  /* bump when the fit or the layout changes */
#define GREY_MIN 1e-6    /* a grey's value kept off 0 and 1 (finite coefficients) */
#define SPM_PATH_MAX_CACHE 4096

static double smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }

static size_t table_floats(int res) { return (size_t)3 * res * res * res * 3; }

void spm_rgb2spec_node_rgb(const spm_rgb2spec_table *t, int l, int k, int j, int i,
                           double rgb[3])
{
    double z = t->z[k], d = t->res - 1, x = i / d, y = j / d;
    rgb[l] = z;
    rgb[(l + 1) % 3] = z * x * x;
    rgb[(l + 2) % 3] = z * y * y;
}

static float *node(const spm_rgb2spec_table *t, int l, int k, int j, int i)
{
    int r = t->res;
    return t->coef + ((((size_t)l * r + k) * r + j) * r + i) * 3;
}

typedef struct {
    spm_rgb2spec_table *t;
    double (*w)[SPM_TRUTH_BINS];
    atomic_int next; /* the next column (l, j) to fit */
} build_job;

static void store(float *dst, const double c[3])
{
    for (int m = 0; m < 3; m++)
        dst[m] = (float)c[m];
}

/* One (l, j, i) line along z: the node at k0 fitted from grey, then each
 * node from its neighbour towards the top and towards black (pbrt-v4's
 * order), so the line follows one branch of solutions. */
static void fit_line(build_job *b, int l, int j, int i)
{
    const spm_rgb2spec_table *t = b->t;
    int k0 = t->res / 5;
    double grey[3] = {0.5, 0.5, 0.5}, rgb[3], prev[3], c0[3] = {0, 0, 0};
    spm_rgb2spec_node_rgb(t, l, k0, j, i, rgb);
    spm_rgb2spec_refine(b->w, grey, rgb, START_STEPS, c0);
    store(node(t, l, k0, j, i), c0);
    for (int dir = 1; dir >= -1; dir -= 2) {
        double c[3] = {c0[0], c0[1], c0[2]};
        spm_rgb2spec_node_rgb(t, l, k0, j, i, prev);
        for (int k = k0 + dir; k >= 0 && k < t->res; k += dir) {
            spm_rgb2spec_node_rgb(t, l, k, j, i, rgb);
            spm_rgb2spec_refine(b->w, prev, rgb, 1, c);
            store(node(t, l, k, j, i), c);
            memcpy(prev, rgb, sizeof prev);
        }
    }
}

static void *build_worker(void *arg)
{
    build_job *b = arg;
    int res = b->t->res;
    for (;;) {
        int col = atomic_fetch_add(&b->next, 1);
        if (col >= 3 * res)
            return NULL;
        for (int i = 0; i < res; i++)
            fit_line(b, col / res, col % res, i);
    }
}

int spm_rgb2spec_table_build(int res, int threads, spm_rgb2spec_table *t, spm_error *err)
{
    if (!spm_d65(err) || spm_cmf_init(err))
        return 1;
    memset(t, 0, sizeof *t);
    t->res = res;
    t->z = spm_xmalloc(sizeof(float) * res);
    t->coef = spm_xmalloc(sizeof(float) * table_floats(res));
    for (int k = 0; k < res; k++)
        t->z[k] = (float)smoothstep(smoothstep((double)k / (res - 1)));
    t->w = spm_xmalloc(sizeof(double) * 3 * SPM_TRUTH_BINS);
    spm_rgb2spec_weights(t->w);
    build_job b = {.t = t, .w = t->w};
    atomic_init(&b.next, 0);
    if (threads <= 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        threads = n > 0 ? (int)(n < 64 ? n : 64) : 1;
    }
    pthread_t tid[64];
    int started = 0;
    for (; started < threads - 1; started++)
        if (pthread_create(&tid[started], NULL, build_worker, &b))
            break;
    build_worker(&b);
    for (int n = 0; n < started; n++)
        pthread_join(tid[n], NULL);
    return 0;
}

void spm_rgb2spec_table_free(spm_rgb2spec_table *t)
{
    free(t->w);
    free(t->z);
    free(t->coef);
    memset(t, 0, sizeof *t);
}

/* ---- the lookup ---- */

/* u in [0, 1] of z = smoothstep(smoothstep(u)): smoothstep's inverse is
 * 1/2 - sin(asin(1 - 2 y) / 3). */
static double unsmooth(double y) { return 0.5 - sin(asin(1.0 - 2.0 * y) / 3.0); }

/* Where a non-grey rgb (in [0, 1]) falls in the grid: its largest component
 * l, and per axis (i, j, k) the node below and the fraction to the next, in
 * the nodes' index (x = sqrt(ratio), u = unsmooth^2(z)). */
static void grid_position(const spm_rgb2spec_table *t, const double rgb[3], int *lp,
                          int base[3], double f[3])
{
    int l = rgb[0] >= rgb[1] ? (rgb[0] >= rgb[2] ? 0 : 2) : (rgb[1] >= rgb[2] ? 1 : 2);
    double z = rgb[l], d = t->res - 1, p[3];
    p[0] = sqrt(rgb[(l + 1) % 3] / z) * d;
    p[1] = sqrt(rgb[(l + 2) % 3] / z) * d;
    p[2] = unsmooth(unsmooth(z)) * d;
    for (int a = 0; a < 3; a++) {
        base[a] = (int)p[a] < t->res - 2 ? (int)p[a] : t->res - 2;
        f[a] = p[a] - base[a];
    }
    *lp = l;
}

void spm_rgb2spec_lookup(const spm_rgb2spec_table *t, const double rgb_in[3], double coef[3])
{
    double rgb[3];
    for (int c = 0; c < 3; c++)
        rgb[c] = rgb_in[c] > 0.0 ? (rgb_in[c] < 1.0 ? rgb_in[c] : 1.0) : 0.0; /* NaN -> 0 */
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
        /* S(z) = g  <=>  z = (g - 1/2) / sqrt(g (1 - g)) */
        double g = fmin(fmax(rgb[0], GREY_MIN), 1.0 - GREY_MIN);
        coef[0] = coef[1] = 0.0;
        coef[2] = (g - 0.5) / sqrt(g * (1.0 - g));
        return;
    }
    int l, base[3];
    double f[3];
    grid_position(t, rgb, &l, base, f);
    for (int m = 0; m < 3; m++) {
        double v = 0.0;
        for (int corner = 0; corner < 8; corner++) {
            int ox = corner & 1, oy = (corner >> 1) & 1, oz = corner >> 2;
            double wgt = (ox ? f[0] : 1 - f[0]) * (oy ? f[1] : 1 - f[1]) * (oz ? f[2] : 1 - f[2]);
            v += wgt * node(t, l, base[2] + oz, base[1] + oy, base[0] + ox)[m];
        }
        coef[m] = v;
    }
}

/* Catmull-Rom weights for the nodes i-1..i+2 at fraction f of [i, i+1]. */
static void catmull_rom(double f, double w[4])
{
    double f2 = f * f, f3 = f2 * f;
    w[0] = 0.5 * (-f3 + 2 * f2 - f);
    w[1] = 0.5 * (3 * f3 - 5 * f2 + 2);
    w[2] = 0.5 * (-3 * f3 + 4 * f2 + f);
    w[3] = 0.5 * (f3 - f2);
}

/* A node's coefficient m with indices one beyond the table extrapolated
 * linearly (c[-1] = 2 c[0] - c[1]), so the end intervals stay second order. */
static double node_ext(const spm_rgb2spec_table *t, int l, int k, int j, int i, int m)
{
    int r = t->res;
    if (k < 0 || k >= r)
        return 2 * node_ext(t, l, k < 0 ? 0 : r - 1, j, i, m) -
               node_ext(t, l, k < 0 ? 1 : r - 2, j, i, m);
    if (j < 0 || j >= r)
        return 2 * node_ext(t, l, k, j < 0 ? 0 : r - 1, i, m) -
               node_ext(t, l, k, j < 0 ? 1 : r - 2, i, m);
    if (i < 0 || i >= r)
        return 2 * node(t, l, k, j, i < 0 ? 0 : r - 1)[m] - node(t, l, k, j, i < 0 ? 1 : r - 2)[m];
    return node(t, l, k, j, i)[m];
}

void spm_rgb2spec_lookup_cubic(const spm_rgb2spec_table *t, const double rgb_in[3],
                               double coef[3])
{
    double rgb[3];
    for (int c = 0; c < 3; c++)
        rgb[c] = rgb_in[c] > 0.0 ? (rgb_in[c] < 1.0 ? rgb_in[c] : 1.0) : 0.0;
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
        spm_rgb2spec_lookup(t, rgb, coef);
        return;
    }
    int l, base[3];
    double f[3], w[3][4];
    grid_position(t, rgb, &l, base, f);
    for (int a = 0; a < 3; a++)
        catmull_rom(f[a], w[a]);
    for (int m = 0; m < 3; m++) {
        double v = 0.0;
        for (int c = 0; c < 4; c++)
            for (int b = 0; b < 4; b++)
                for (int a = 0; a < 4; a++)
                    v += w[2][c] * w[1][b] * w[0][a] *
                         node_ext(t, l, base[2] + c - 1, base[1] + b - 1, base[0] + a - 1, m);
        coef[m] = v;
    }
}

void spm_rgb2spec_texel(const spm_rgb2spec_table *t, spm_texel_kind kind, const double rgb[3],
                        double coef[3], double *scale)
{
    double m = fmax(rgb[0], fmax(rgb[1], rgb[2]));
    if (!(m > 0.0) || !isfinite(m)) {
        coef[0] = coef[1] = coef[2] = 0.0;
        *scale = 0.0;
        return;
    }
    double unit[3] = {rgb[0] / m, rgb[1] / m, rgb[2] / m};
    const double *target = kind == SPM_TEXEL_REFLECTANCE ? rgb : unit;
    *scale = kind == SPM_TEXEL_REFLECTANCE ? 1.0 : m;
    spm_rgb2spec_lookup_cubic(t, target, coef);
    if (coef[0] == 0.0 && coef[1] == 0.0)
        return; /* a grey: exact */
    if (spm_rgb2spec_delta_e_w(t->w, coef, target) > SPM_TEXEL_MAX_DE00)
        spm_rgb2spec_refine(t->w, target, target, 1, coef);
}

int spm_rgb2spec_texel_spectrum(spm_texel_kind kind, const double coef[3], double scale,
                                spm_spectrum *out, spm_error *err)
{
    spm_rgb2spec_eval(coef, out);
    spm_spectrum_scale(out, scale);
    if (kind != SPM_TEXEL_EMISSION)
        return 0;
    const spm_spectrum *d65 = spm_d65(err);
    if (!d65 || spm_cmf_init(err))
        return 1;
    double xyz[3];
    spm_xyz_emission(d65, xyz);
    spm_spectrum_multiply(out, d65);
    spm_spectrum_scale(out, 1.0 / xyz[1]);
    out->kind = SPM_KIND_EMISSION;
    return 0;
}

/* ---- the model's bin means ---- */

static double sigmoid(double z) { return 0.5 + z / (2.0 * sqrt(1.0 + z * z)); }

void spm_sigmoid_level_sum(const double coef[3], int level, double *out)
{
    int bins = SPM_LEVEL_BINS(level), per = SPM_TRUTH_BINS / bins;
    for (int b = 0; b < bins; b++) {
        double s = 0.0;
        for (int i = b * per; i < (b + 1) * per; i++) {
            double x = (i + 0.5) / SPM_TRUTH_BINS;
            s += sigmoid((coef[0] * x + coef[1]) * x + coef[2]);
        }
        out[b] = s / per;
    }
}

/* Gauss-Legendre nodes and weights on [-1, 1] (half of each symmetric set). */
static const double GL_X[8][4] = {
    {0},
    {0.5773502691896257},
    {0.7745966692414834, 0},
    {0.8611363115940526, 0.3399810435848563},
    {0.9061798459386640, 0.5384693101056831, 0},
    {0.9324695142031521, 0.6612093864662645, 0.2386191860831969},
    {0.9491079123427585, 0.7415311855993945, 0.4058451513773972, 0},
    {0.9602898564975363, 0.7966664774136267, 0.5255324099163290, 0.1834346424956498},
};
static const double GL_W[8][4] = {
    {2},
    {1},
    {0.5555555555555556, 0.8888888888888888},
    {0.3478548451374538, 0.6521451548625461},
    {0.2369268850561891, 0.4786286704993665, 0.5688888888888889},
    {0.1713244923791704, 0.3607615730481386, 0.4679139345726910},
    {0.1294849661688697, 0.2797053914892766, 0.3818300505051189, 0.4179591836734694},
    {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620},
};

/* mean over [a, b] of f = 1/2 sum_q w_q f(m + h x_q), m = (a+b)/2, h = (b-a)/2 */
void spm_sigmoid_level_gauss(const double coef[3], int level, int n, double *out)
{
    int bins = SPM_LEVEL_BINS(level);
    n = n < 1 ? 1 : (n > 8 ? 8 : n);
    double h = 0.5 / bins;
    for (int b = 0; b < bins; b++) {
        double m = (b + 0.5) / bins, s = 0.0;
        for (int q = 0; q < (n + 1) / 2; q++) {
            double xs[2] = {m - h * GL_X[n - 1][q], m + h * GL_X[n - 1][q]};
            int both = GL_X[n - 1][q] != 0.0;
            for (int e = 0; e <= both; e++)
                s += GL_W[n - 1][q] * sigmoid((coef[0] * xs[e] + coef[1]) * xs[e] + coef[2]);
        }
        out[b] = 0.5 * s;
    }
}

/* ---- the cache ---- */

typedef struct {
    char magic[8];
    uint32_t format, res;
    uint64_t inputs; /* FNV-1a of the fitter's weights */
} cache_header;

uint64_t spm_rgb2spec_inputs_hash(int res)
{
    static double w[3][SPM_TRUTH_BINS];
    spm_rgb2spec_weights(w);
    uint64_t h = 1469598103934665603ull;
    const unsigned char *p = (const unsigned char *)w;
    for (size_t i = 0; i < sizeof w; i++)
        h = (h ^ p[i]) * 1099511628211ull;
    return (h ^ (uint64_t)(res * 256 + CACHE_FORMAT)) * 1099511628211ull;
}

static const char *cache_dir(char *buf, size_t size)
{
    const char *d = getenv("SPECMIP_CACHE_DIR"), *x = getenv("XDG_CACHE_HOME"),
               *h = getenv("HOME");
    if (d && *d)
        snprintf(buf, size, "%s", d);
    else if (x && *x)
        snprintf(buf, size, "%s/specmip", x);
    else if (h && *h)
        snprintf(buf, size, "%s/.cache/specmip", h);
    else
        return NULL;
    return buf;
}

int spm_rgb2spec_cache_read(const char *path, int res, uint64_t inputs, spm_rgb2spec_table *t)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return 1;
    cache_header hd;
    int bad = fread(&hd, sizeof hd, 1, f) != 1 ||
                                       memcmp(hd.magic, "SPMR2SPC", 8) ||
                                       hd.format != CACHE_FORMAT || hd.res != (uint32_t)res ||
                                       hd.inputs != inputs;
    if (!bad) {
        t->res = res;
        t->w = spm_xmalloc(sizeof(double) * 3 * SPM_TRUTH_BINS);
        spm_rgb2spec_weights(t->w);
        t->z = spm_xmalloc(sizeof(float) * res);
        t->coef = spm_xmalloc(sizeof(float) * table_floats(res));
        bad = fread(t->z, sizeof(float), res, f) != (size_t)res ||
              fread(t->coef, sizeof(float), table_floats(res), f) != table_floats(res) ||
              fgetc(f) != EOF;
        for (size_t i = 0; !bad && i < table_floats(res); i++)
            bad = !isfinite(t->coef[i]);
        if (bad)
            spm_rgb2spec_table_free(t);
    }
    fclose(f);
    return bad;
}

/* Written whole to a temporary file beside `path`, then renamed over it. */
int spm_rgb2spec_cache_write(const char *path, uint64_t inputs, const spm_rgb2spec_table *t)
{
    char tmp[SPM_PATH_MAX_CACHE];
    snprintf(tmp, sizeof tmp, "%s.XXXXXX", path);
    int fd = mkstemp(tmp);
    if (fd < 0)
        return 1;
    FILE *f = fdopen(fd, "wb");
    if (!f) {
        close(fd);
        unlink(tmp);
        return 1;
    }
    cache_header hd = {.format = CACHE_FORMAT, .res = (uint32_t)t->res, .inputs = inputs};
    memcpy(hd.magic, "SPMR2SPC", 8);
    int bad = fwrite(&hd, sizeof hd, 1, f) != 1 ||
              fwrite(t->z, sizeof(float), t->res, f) != (size_t)t->res ||
              fwrite(t->coef, sizeof(float), table_floats(t->res), f) != table_floats(t->res);
    bad |= fflush(f) != 0 || fsync(fileno(f)) != 0;
    bad |= fclose(f) != 0;
    if (bad || rename(tmp, path)) {
        unlink(tmp);
        return 1;
    }
    return 0;
}

static pthread_mutex_t srgb_lock = PTHREAD_MUTEX_INITIALIZER;
static spm_rgb2spec_table srgb;

const spm_rgb2spec_table *spm_rgb2spec_srgb(spm_error *err)
{
    pthread_mutex_lock(&srgb_lock);
    const spm_rgb2spec_table *r = &srgb;
    if (!srgb.coef) {
        if (!spm_d65(err) || spm_cmf_init(err)) {
            pthread_mutex_unlock(&srgb_lock);
            return NULL;
        }
        uint64_t inputs = spm_rgb2spec_inputs_hash(SPM_RGB2SPEC_RES);
        char dir[SPM_PATH_MAX_CACHE - 64], path[SPM_PATH_MAX_CACHE];
        int have_dir = cache_dir(dir, sizeof dir) != NULL;
        snprintf(path, sizeof path, "%s/rgb2spec-srgb-%d.bin", have_dir ? dir : ".",
                 SPM_RGB2SPEC_RES);
        if (!have_dir || spm_rgb2spec_cache_read(path, SPM_RGB2SPEC_RES, inputs, &srgb)) {
            if (spm_rgb2spec_table_build(SPM_RGB2SPEC_RES, 0, &srgb, err))
                r = NULL;
            else if (have_dir) {
                spm_make_dirs(dir, NULL, 0); /* a failure is no error: fitted again */
                spm_rgb2spec_cache_write(path, inputs, &srgb);
            }
        }
    }
    pthread_mutex_unlock(&srgb_lock);
    return r;
}
