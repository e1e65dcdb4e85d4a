/* `specmip bench --rays SCENE --rays-wavefront N` (bench_wavefront.h): a
 * wavefront of bounces, each traced in path order and sorted. */
#include "bench_wavefront.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "cl_core.h"
#include "interrupt.h"
#include "refcpu_camera.h"
#include "spm_kernel_args.h"

/* ---- the coherent order --------------------------------------------------- */
/* The calling thread's CPU seconds: the sort's cost without the time other
 * processes of a shared machine take from it (its wall time on an idle core). */
static double thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* the 9 low bits of v, two zero bits after each (a Morton code's one axis) */
static spm_u32 spread3(spm_u32 v)
{
    v &= 0x1FFu;
    v = (v | v << 16) & 0x030000FFu;
    v = (v | v << 8) & 0x0300F00Fu;
    v = (v | v << 4) & 0x030C30C3u;
    v = (v | v << 2) & 0x09249249u;
    return v;
}

static void ray_keys(const spm_ray *rays, size_t n, uint64_t *a)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++) /* comparisons, not fminf: libm calls here */
        for (int k = 0; k < 3; k++) {
            float v = rays[i].o[k];
            lo[k] = v < lo[k] ? v : lo[k];
            hi[k] = v > hi[k] ? v : hi[k];
        }
    float scale[3];
    for (int k = 0; k < 3; k++)
        scale[k] = hi[k] > lo[k] ? 512.0f / (hi[k] - lo[k]) : 0.0f;
    for (size_t i = 0; i < n; i++) {
        spm_u32 m = 0, oct = 0;
        for (int k = 0; k < 3; k++) {
            float u = (rays[i].o[k] - lo[k]) * scale[k];
            m |= spread3(u >= 511.0f ? 511u : (spm_u32)u) << k;
            oct |= (spm_u32)(rays[i].d[k] < 0.0f) << k;
        }
        /* the key above the ray's index: sorting the words sorts the pairs */
        a[i] = (uint64_t)(oct << 27 | m) << 32 | (uint64_t)i;
    }
}

void spm_wavefront_order(const spm_ray *rays, size_t n, spm_u32 *perm, double *key_s,
                         double *sort_s)
{
    uint64_t *a = spm_xmalloc((n ? n : 1) * sizeof *a), *b = spm_xmalloc((n ? n : 1) * sizeof *b);
    double t0 = thread_cpu();
    ray_keys(rays, n, a);
    double t1 = thread_cpu();
    for (int pass = 0; pass < 3; pass++) { /* 30 key bits, 10 a pass, lowest first */
        int shift = 32 + 10 * pass;
        size_t count[1024] = {0}, sum = 0;
        for (size_t i = 0; i < n; i++)
            count[(a[i] >> shift) & 1023u]++;
        for (int d = 0; d < 1024; d++) {
            size_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++)
            b[count[(a[i] >> shift) & 1023u]++] = a[i];
        uint64_t *t = a;
        a = b;
        b = t;
    }
    for (size_t i = 0; i < n; i++)
        perm[i] = (spm_u32)a[i];
    *key_s = t1 - t0;
    *sort_s = thread_cpu() - t1;
    free(a);
    free(b);
}

/* ---- the device: the replay kernel, its geometry uploaded once ----------- */
#define ARG_FIELD(dev, host, name) host name;
typedef struct { SPM_RAYS_ARGS(ARG_FIELD, ) } wf_args;
#define SET_ARG(dev, host, name) \
    rc = rc || spm_cl_arg(d->k, i++, sizeof d->a.name, &d->a.name, "spm_rays", err);

typedef struct {
    spm_cl_ctx c;
    int have_ctx;
    cl_program prog;
    cl_kernel k;
    wf_args a; /* tris, nodes, counters for good; rays and hits per launch */
    size_t group;
} wf_dev;

static int dev_open(wf_dev *d, int device, const spm_geometry *g, size_t group, spm_error *err)
{
    memset(d, 0, sizeof *d);
    d->group = group;
    if (spm_cl_ctx_create(device, &d->c, err))
        return 1;
    d->have_ctx = 1;
    const char *files[] = {spm_rays_program_file};
    cl_uint zero[SPM_RAYS_NCOUNTERS] = {0};
    return spm_cl_build(&d->c, files, 1, spm_rays_program_defines[0], &d->prog, err) ||
           spm_cl_kernel(d->prog, "spm_rays", &d->k, err) ||
           spm_cl_buffer(&d->c, CL_MEM_READ_ONLY, (size_t)g->ntris * sizeof *g->tris, g->tris,
                         "triangles", &d->a.tris, err) ||
           spm_cl_buffer(&d->c, CL_MEM_READ_ONLY, (size_t)g->nwide * sizeof *g->wide, g->wide,
                         "nodes", &d->a.nodes, err) ||
           spm_cl_buffer(&d->c, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof zero, zero,
                         "counters", &d->a.counters, err);
}

static void dev_close(wf_dev *d)
{
    spm_cl_release_kernel(d->k);
    spm_cl_release_mem(d->a.tris);
    spm_cl_release_mem(d->a.nodes);
    spm_cl_release_mem(d->a.counters);
    spm_cl_release_program(d->prog);
    if (d->have_ctx)
        spm_cl_ctx_release(&d->c);
}

/* One launch over the n rays (one kind) in buffer rays; its kernel seconds in *s. */
static int dev_launch(wf_dev *d, cl_mem rays, cl_mem hits, size_t n, double *s, spm_error *err)
{
    *s = 0;
    if (!n)
        return 0;
    d->a.rays = rays;
    d->a.hits = hits;
    d->a.first = 0;
    d->a.nrays = (spm_u32)n;
    int rc = 0;
    cl_uint i = 0;
    SPM_RAYS_ARGS(SET_ARG, )
    size_t global = (n + d->group - 1) / d->group * d->group;
    rc = rc || spm_cl_launch(&d->c, d->k, global, d->group, s, "spm_rays", err);
    if (!rc && *s < 0) {
        spm_errorf(err, "device '%s' gives no kernel times (profiling)", d->c.dev.name);
        rc = 1;
    }
    return rc;
}

/* ---- the paths' rays ------------------------------------------------------ */
/* A wave: rays of one kind in path order, each with the path it belongs to. */
typedef struct {
    spm_rayset rs;
    spm_u32 *path;
} wave;

static void wave_alloc(wave *w, size_t cap)
{
    w->rs.rays = spm_xmalloc((cap ? cap : 1) * sizeof *w->rs.rays);
    w->path = spm_xmalloc((cap ? cap : 1) * sizeof *w->path);
    w->rs.n = 0;
    w->rs.nclosest = 0;
}

static void wave_push(wave *w, const spm_ray *r, spm_u32 path)
{
    w->path[w->rs.n] = path;
    w->rs.rays[w->rs.n++] = *r;
    if (r->emitter == SPM_RAY_CLOSEST)
        w->rs.nclosest = w->rs.n;
}

static void wave_free(wave *w)
{
    free(w->rs.rays);
    free(w->path);
    memset(w, 0, sizeof *w);
}

/* A path's random number for bounce `depth`, dimension dim, in [0, 1): two
 * rounds of MurmurHash3's finaliser over the three. */
static float rnd(spm_u32 path, int depth, int dim)
{
    spm_u32 h = path;
    for (int r = 0; r < 2; r++) {
        h ^= (spm_u32)(depth * 16 + dim + 1) * 0x9E3779B1u;
        h ^= h >> 16;
        h *= 0x85EBCA6Bu;
        h ^= h >> 13;
        h *= 0xC2B2AE35u;
        h ^= h >> 16;
    }
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* Depth 1: a ray per path through a random point of its pixel. */
static void camera_wave(const spm_render_setup *s, int spp, wave *w)
{
    int W = s->scene.width, H = s->scene.height;
    wave_alloc(w, (size_t)W * H * spp);
    spm_u32 p = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int j = 0; j < spp; j++, p++) {
                spm_ray r = {{0}, 0xFFFFFFFFu, {0}, SPM_RAY_CLOSEST};
                float cx = 2.0f * (x + rnd(p, 0, 0)) / W - 1.0f;
                float cy = 2.0f * (y + rnd(p, 0, 1)) / H - 1.0f;
                spm_ref_camera_ray(&s->geom.cam, cx, cy, rnd(p, 0, 2), rnd(p, 0, 3), r.o, r.d);
                wave_push(w, &r, p);
            }
}

/* The scene's emitter triangles, and a flag per triangle. */
typedef struct {
    spm_u32 *tri;
    size_t n;
    unsigned char *is;
} light_set;

static void lights_make(const spm_geometry *g, light_set *l)
{
    l->tri = spm_xmalloc(((size_t)g->nemitters + 1) * sizeof *l->tri);
    l->is = spm_xcalloc((size_t)g->ntris + 1, 1);
    l->n = 0;
    for (int i = 0; i < g->nemitters; i++)
        if (g->emitters[i].tri < (spm_u32)g->ntris) {
            l->tri[l->n++] = g->emitters[i].tri;
            l->is[g->emitters[i].tri] = 1;
        }
}

/* Towards a uniform point of a uniformly picked emitter triangle (the
 * reference's area-light point), from x on the side of n. */
static void shadow_ray(const spm_geometry *g, const light_set *l, spm_u32 p, int depth,
                       const float x[3], const float n[3], spm_u32 hit, wave *out)
{
    size_t e = (size_t)(rnd(p, depth, 0) * (float)l->n);
    spm_u32 ei = l->tri[e < l->n ? e : l->n - 1];
    const spm_tri *em = &g->tris[ei];
    float sqr1 = sqrtf(rnd(p, depth, 1)), a = 1.0f - sqr1, b = (1.0f - rnd(p, depth, 2)) * sqr1;
    spm_ray r = {{x[0], x[1], x[2]}, hit, {0}, ei};
    float len2 = 0, cosn = 0;
    for (int k = 0; k < 3; k++) {
        r.d[k] = em->v0[k] + (em->v1[k] - em->v0[k]) * a + (em->v2[k] - em->v0[k]) * b - x[k];
        len2 += r.d[k] * r.d[k];
        cosn += r.d[k] * n[k];
    }
    if (!(len2 > 0) || cosn <= 0) /* the light is behind the surface: no ray */
        return;
    for (int k = 0; k < 3; k++)
        r.d[k] /= sqrtf(len2);
    wave_push(out, &r, p);
}

/* Cosine-weighted about unit n (Malley), in the frame of Duff et al. 2017. */
static void bounce_ray(spm_u32 p, int depth, const float x[3], const float n[3], spm_u32 hit,
                       wave *out)
{
    float u1 = rnd(p, depth, 3), phi = 6.2831853f * rnd(p, depth, 4), r = sqrtf(u1);
    float lx = r * cosf(phi), ly = r * sinf(phi), lz = sqrtf(fmaxf(0.0f, 1.0f - u1));
    float sg = copysignf(1.0f, n[2]), a = -1.0f / (sg + n[2]), b = n[0] * n[1] * a;
    float b1[3] = {1.0f + sg * n[0] * n[0] * a, sg * b, -sg * n[0]};
    float b2[3] = {b, sg + n[1] * n[1] * a, -n[1]};
    spm_ray ray = {{x[0], x[1], x[2]}, hit, {0}, SPM_RAY_CLOSEST};
    for (int k = 0; k < 3; k++)
        ray.d[k] = lx * b1[k] + ly * b2[k] + lz * n[k];
    wave_push(out, &ray, p);
}

/* From the closest hits of wave w at bounce depth: each path's shadow ray
 * and its next bounce; a miss or an emitter ends the path. */
static void next_waves(const spm_geometry *g, const light_set *l, const wave *w,
                       const int *hits, int depth, wave *shadow, wave *bounce)
{
    wave_alloc(shadow, w->rs.n);
    wave_alloc(bounce, w->rs.n);
    for (size_t i = 0; i < w->rs.n; i++) {
        int h = hits[i];
        if (h < 0 || h >= g->ntris || l->is[h])
            continue;
        const spm_ray *r = &w->rs.rays[i];
        const spm_tri *tr = &g->tris[h];
        float t = spm_tri_intersect(tr, r->o, r->d); /* the hit's own test: its t */
        float side = tr->n[0] * r->d[0] + tr->n[1] * r->d[1] + tr->n[2] * r->d[2] > 0 ? -1 : 1;
        float x[3], n[3];
        for (int k = 0; k < 3; k++) {
            x[k] = r->o[k] + t * r->d[k];
            n[k] = side * tr->n[k];
        }
        if (l->n)
            shadow_ray(g, l, w->path[i], depth, x, n, (spm_u32)h, shadow);
        bounce_ray(w->path[i], depth, x, n, (spm_u32)h, bounce);
    }
}

/* ---- one kind of one bounce, both orders ---------------------------------- */
typedef struct {
    size_t n, moved;                 /* rays; rays the sort moved */
    double path_s, sorted_s;         /* kernel seconds, fastest of the repeats */
    double em_path_s, em_sorted_s;   /* Embree's (-1: not run) */
    double key_s, sort_s, gather_s;  /* the sort on the host: one thread's CPU s, fastest */
    size_t differ_sorted, differ_ref, differ_embree;
} kind_row;

typedef struct {
    const spm_rays_opts *o;
    const spm_geometry *g;
    wf_dev dev;
    spm_rays_embree *em;
} study;

/* The sort's cost, the fastest of the repeats; the order in perm, the rays in it in *srt. */
static void time_sort(const spm_rayset *u, int repeat, spm_u32 *perm, spm_rayset *srt,
                      kind_row *row)
{
    row->key_s = row->sort_s = row->gather_s = INFINITY;
    for (int r = 0; r < (repeat > 0 ? repeat : 1); r++) {
        double ks, ss;
        spm_wavefront_order(u->rays, u->n, perm, &ks, &ss);
        double t0 = thread_cpu();
        for (size_t i = 0; i < u->n; i++)
            srt->rays[i] = u->rays[perm[i]];
        double gs = thread_cpu() - t0;
        row->key_s = fmin(row->key_s, ks);
        row->sort_s = fmin(row->sort_s, ss);
        row->gather_s = fmin(row->gather_s, gs);
    }
    row->moved = 0;
    for (size_t i = 0; i < u->n; i++)
        row->moved += perm[i] != i;
}

/* Embree on one order: its time for u's kind. */
static int embree_time(study *st, const spm_rayset *rs, int *hits, double *best, int run,
                       spm_error *err)
{
    double sc, ss;
    spm_rays_embree_bind(st->em, rs, hits);
    if (spm_rays_embree_run(st->em, &sc, &ss, err))
        return 1;
    double s = rs->nclosest ? sc : ss;
    if (run > 0)
        *best = fmin(*best, s);
    return 0;
}

/* The two orders alternating (path, sorted, and Embree's path, sorted after
 * them), a warm-up first; hits of each order read back. */
static int time_orders(study *st, const spm_rayset *u, const spm_rayset *srt, int *hu, int *hs,
                       int *he, kind_row *row, spm_error *err)
{
    wf_dev *d = &st->dev;
    size_t n = u->n;
    cl_mem m[4] = {NULL, NULL, NULL, NULL};
    int bad = spm_cl_buffer(&d->c, CL_MEM_READ_ONLY, n * sizeof *u->rays, u->rays, "rays", &m[0],
                            err) ||
              spm_cl_buffer(&d->c, CL_MEM_READ_ONLY, n * sizeof *u->rays, srt->rays, "rays",
                            &m[1], err) ||
              spm_cl_buffer(&d->c, CL_MEM_READ_WRITE, n * sizeof *hu, NULL, "hits", &m[2], err) ||
              spm_cl_buffer(&d->c, CL_MEM_READ_WRITE, n * sizeof *hu, NULL, "hits", &m[3], err);
    row->path_s = row->sorted_s = row->em_path_s = row->em_sorted_s = INFINITY;
    for (int r = 0; r <= st->o->repeat && !bad; r++) { /* run 0 warms up */
        double a, b;
        bad = dev_launch(d, m[0], m[2], n, &a, err) || dev_launch(d, m[1], m[3], n, &b, err);
        if (!bad && r > 0) {
            row->path_s = fmin(row->path_s, a);
            row->sorted_s = fmin(row->sorted_s, b);
        }
        if (!bad && st->em)
            bad = embree_time(st, srt, hs, &row->em_sorted_s, r, err) ||
                  embree_time(st, u, he, &row->em_path_s, r, err);
        if (!bad && spm_stop_requested()) {
            spm_errorf(err, "interrupted while tracing the wavefront");
            bad = 1;
        }
    }
    bad = bad || spm_cl_read(&d->c, m[2], n * sizeof *hu, hu, "hits", err) ||
          spm_cl_read(&d->c, m[3], n * sizeof *hs, hs, "hits", err);
    for (int i = 0; i < 4; i++)
        spm_cl_release_mem(m[i]);
    if (!st->em)
        row->em_path_s = row->em_sorted_s = -1;
    return bad;
}

/* Rays u (one kind, path order): sorted, both orders traced and timed, the
 * answers compared; hu receives the path order's. */
static int measure_kind(study *st, const spm_rayset *u, int *hu, kind_row *row, spm_error *err)
{
    memset(row, 0, sizeof *row);
    row->n = u->n;
    if (!u->n)
        return 0;
    size_t n = u->n;
    spm_u32 *perm = spm_xmalloc(n * sizeof *perm);
    spm_rayset srt = {spm_xmalloc(n * sizeof *srt.rays), n, u->nclosest};
    int *hs = spm_xmalloc(n * sizeof *hs), *he = spm_xmalloc(n * sizeof *he);
    time_sort(u, st->o->repeat, perm, &srt, row);
    int bad = time_orders(st, u, &srt, hu, hs, he, row, err);
    if (!bad) {
        for (size_t i = 0; i < n; i++)
            row->differ_sorted += hs[i] != hu[perm[i]];
        spm_rays_timing tm;
        size_t cb, sb;
        spm_rays_replay_ref(st->g, u, hs, &tm); /* hs now the reference's */
        spm_rays_compare(u, hu, hs, &cb, &sb);
        row->differ_ref = cb + sb;
        if (st->em) {
            spm_rays_compare(u, hu, he, &cb, &sb);
            row->differ_embree = cb + sb;
        }
    }
    if (st->em)
        spm_rays_embree_bind(st->em, NULL, NULL);
    free(perm);
    free(srt.rays);
    free(hs);
    free(he);
    return bad;
}

/* ---- the study ------------------------------------------------------------ */
#define WF_MAX_DEPTH 16

static double mrays(size_t n, double s)
{
    return s > 0 && isfinite(s) ? (double)n / s / 1e6 : 0;
}

/* the sort, in ns per ray: keys, radix passes, gather */
static double sort_total(const kind_row *k)
{
    return k->key_s + k->sort_s + k->gather_s;
}

static void json_kind(const char *name, const kind_row *k, const char *sep)
{
    printf("     \"%s\": {\"rays\": %zu, \"moved\": %zu, \"path_s\": %.6g, \"sorted_s\": %.6g, "
           "\"path_mrays_s\": %.6g, \"sorted_mrays_s\": %.6g, \"key_s\": %.6g, \"sort_s\": %.6g, "
           "\"gather_s\": %.6g, \"net\": %.6g, ", name, k->n, k->moved, k->path_s, k->sorted_s,
           mrays(k->n, k->path_s), mrays(k->n, k->sorted_s), k->key_s, k->sort_s, k->gather_s,
           k->n ? k->path_s / (k->sorted_s + sort_total(k)) : 0);
    if (k->em_path_s >= 0)
        printf("\"embree_path_mrays_s\": %.6g, \"embree_sorted_mrays_s\": %.6g, ",
               mrays(k->n, k->em_path_s), mrays(k->n, k->em_sorted_s));
    printf("\"differ_sorted\": %zu, \"differ_reference\": %zu, \"differ_embree\": %zu}%s\n",
           k->differ_sorted, k->differ_ref, k->differ_embree, sep);
}

static void text_kind(int depth, const char *name, const kind_row *k)
{
    if (!k->n) {
        printf("  %5d %-7s %9d\n", depth, name, 0);
        return;
    }
    printf("  %5d %-7s %9zu %8.3f %8.3f %7.3f %7.1f %7.1f %7.1f %7.3f", depth, name, k->n,
           mrays(k->n, k->path_s), mrays(k->n, k->sorted_s), k->path_s / k->sorted_s,
           1e9 * k->key_s / k->n, 1e9 * k->sort_s / k->n, 1e9 * k->gather_s / k->n,
           k->path_s / (k->sorted_s + sort_total(k)));
    if (k->em_path_s >= 0)
        printf(" %8.3f %8.3f", mrays(k->n, k->em_path_s), mrays(k->n, k->em_sorted_s));
    printf("  %zu/%zu/%zu\n", k->differ_sorted, k->differ_ref, k->differ_embree);
}

static void report(const spm_rays_opts *o, const spm_render_setup *s, const study *st,
                   kind_row (*rows)[2], int depths, const char *einfo)
{
    const char *scene = o->scene ? o->scene : "default";
    size_t paths = (size_t)s->scene.width * s->scene.height * o->spp;
    if (o->json) {
        printf("{\n  \"scene\": \"%s\", \"triangles\": %d, \"paths\": %zu, \"device\": \"%s\", "
               "\"group\": %zu, \"repeat\": %d,\n  \"embree\": \"%s\",\n  \"depths\": [\n",
               scene, st->g->ntris, paths, st->dev.c.dev.name, st->dev.group, o->repeat, einfo);
        for (int d = 0; d < depths; d++) {
            printf("    {\"depth\": %d,\n", d + 1);
            json_kind("closest", &rows[d][0], ",");
            json_kind("shadow", &rows[d][1], "");
            printf("    }%s\n", d + 1 < depths ? "," : "");
        }
        printf("  ]\n}\n");
        return;
    }
    printf("%s: %d triangles; a wavefront of %zu paths (%dx%d, %d spp), %d bounces\n", scene,
           st->g->ntris, paths, s->scene.width, s->scene.height, o->spp, depths);
    printf("  kernels/rays.cl on %s, work-groups of %zu, fastest of %d, path order and sorted "
           "alternating%s\n", st->dev.c.dev.name, st->dev.group, o->repeat,
           st->em ? ", Embree's runs after each" : "");
    if (st->em)
        printf("  Embree: %s\n", einfo);
    printf("  %5s %-7s %9s %8s %8s %7s %23s %7s%s  %s\n", "depth", "kind", "rays", "path",
           "sorted", "sorted/", "sort CPU ns/ray, 1 thr:", "net", st->em ? "   Embree Mrays/s" : "",
           "differ: sorted/");
    printf("  %5s %-7s %9s %8s %8s %7s %7s %7s %7s %7s%s  %s\n", "", "", "", "Mrays/s",
           "Mrays/s", "path", "keys", "radix", "gather", "", st->em ? "     path   sorted" : "",
           "reference/Embree");
    for (int d = 0; d < depths; d++) {
        text_kind(d + 1, "closest", &rows[d][0]);
        text_kind(d + 1, "shadow", &rows[d][1]);
    }
    printf("  net: path order's kernel time / (sorted order's + the sort's)\n");
}

/* Bounces 1 .. o->wavefront: each traced, then its shadow rays and the next
 * bounce made from the path order's hits (the sorted order's are the same
 * answers: differ_sorted counts any that are not). */
static int run_bounces(study *st, const spm_render_setup *s, kind_row (*rows)[2], int *depths,
                       spm_error *err)
{
    const spm_geometry *g = st->g;
    light_set l;
    lights_make(g, &l);
    wave w;
    camera_wave(s, st->o->spp, &w);
    int bad = 0;
    *depths = 0;
    for (int d = 1; d <= st->o->wavefront && !bad && w.rs.n; d++) {
        int *hits = spm_xmalloc((w.rs.n + 1) * sizeof *hits);
        wave sh, bo;
        bad = measure_kind(st, &w.rs, hits, &rows[d - 1][0], err);
        if (!bad) {
            next_waves(g, &l, &w, hits, d, &sh, &bo);
            int *shits = spm_xmalloc((sh.rs.n + 1) * sizeof *shits);
            bad = measure_kind(st, &sh.rs, shits, &rows[d - 1][1], err);
            free(shits);
            wave_free(&sh);
            wave_free(&w);
            w = bo;
            *depths = d;
        }
        free(hits);
    }
    wave_free(&w);
    free(l.tri);
    free(l.is);
    return bad;
}

int spm_bench_wavefront(const spm_rays_opts *o, const spm_render_setup *s, spm_error *err)
{
    study st;
    memset(&st, 0, sizeof st);
    st.o = o;
    st.g = &s->geom;
    kind_row rows[WF_MAX_DEPTH][2];
    memset(rows, 0, sizeof rows);
    char einfo[512] = "";
    int depths = 0, rc = 0;
    if (o->wavefront > WF_MAX_DEPTH) {
        spm_errorf(err, "--rays-wavefront %d: at most %d bounces", o->wavefront, WF_MAX_DEPTH);
        return SPM_EXIT_INPUT;
    }
    if (dev_open(&st.dev, o->device, st.g, o->group ? (size_t)o->group : SPM_LOCAL_SIZE, err))
        rc = SPM_EXIT_RUNTIME;
    if (!rc && o->embree) {
        spm_rayset none = {NULL, 0, 0};
        st.em = spm_rays_embree_open(st.g, &none, o->threads, o->embree_quality, NULL, einfo,
                                     sizeof einfo, err);
        if (!st.em)
            rc = SPM_EXIT_RUNTIME;
    }
    if (!rc && run_bounces(&st, s, rows, &depths, err))
        rc = SPM_EXIT_RUNTIME;
    spm_error cerr;
    if (spm_rays_embree_close(st.em, &cerr) && !rc) {
        *err = cerr;
        rc = SPM_EXIT_RUNTIME;
    }
    if (rc && spm_stop_requested())
        rc = SPM_EXIT_INTERRUPTED;
    if (!rc)
        report(o, s, &st, rows, depths, einfo);
    dev_close(&st.dev);
    return rc;
}
