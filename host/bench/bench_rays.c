/* `specmip bench --rays` (bench_rays.h): record, save, load and replay rays. */
#include "bench_rays.h"
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cl_core.h"
#include "geometry_vec3.h"
#include "interrupt.h"
#include "refcpu.h"
#include "backend_cpu.h"
#include "backends.h"
#include "bench_wavefront.h"
#include "bvh_quant.h"
#include "spm_kernel_args.h"

/* Work-group size: the renderer's unless --rays-group sets one; the variant
 * (0 one ray per work-item, 1 packets: --rays-packet, 2 the quantised tree:
 * --rays-quant) picks the program's defines, spm_rays_program_defines[2 *
 * variant + stats build]. */
static size_t group = SPM_LOCAL_SIZE;
static int variant;

typedef struct {
    spm_ray *r;
    size_t n, cap;
} ray_list;

static void push(ray_list *l, const spm_ray *r)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 4096;
        l->r = spm_xrealloc(l->r, l->cap * sizeof *l->r);
    }
    l->r[l->n++] = *r;
}

static void sink(void *ctx, const spm_ray *r)
{
    ray_list *l = ctx;
    push(&l[r->emitter == SPM_RAY_CLOSEST ? 0 : 1], r);
}

void spm_rayset_free(spm_rayset *rs)
{
    free(rs->rays);
    memset(rs, 0, sizeof *rs);
}

static void join(ray_list l[2], spm_rayset *rs)
{
    rs->n = l[0].n + l[1].n;
    rs->nclosest = l[0].n;
    rs->rays = spm_xmalloc((rs->n ? rs->n : 1) * sizeof *rs->rays);
    if (l[0].n)
        memcpy(rs->rays, l[0].r, l[0].n * sizeof *rs->rays);
    if (l[1].n)
        memcpy(rs->rays + l[0].n, l[1].r, l[1].n * sizeof *rs->rays);
    free(l[0].r);
    free(l[1].r);
}

int spm_rays_record(const spm_render_plan *plan, int spp, spm_rayset *rs, spm_error *err)
{
    memset(rs, 0, sizeof *rs);
    ray_list l[2];
    memset(l, 0, sizeof l);
    spm_trace_params p = spm_plan_pass_params(plan, 0, (spm_u32)spp);
    size_t npaths = plan->npix * (size_t)spp, chunk = 1024;
    spm_path *paths = spm_xmalloc(chunk * sizeof *paths);
    uint8_t levels[1024];
    spm_ref_rays = (spm_ref_ray_sink){sink, l};
    int rc = 0;
    for (size_t b = 0; b < npaths && !rc; b += chunk) {
        if (spm_stop_requested()) {
            spm_errorf(err, "interrupted while recording rays");
            rc = SPM_EXIT_INTERRUPTED;
            break;
        }
        size_t e = b + chunk < npaths ? b + chunk : npaths;
        spm_ref_trace_range(plan->geom, plan->tables->materials, plan->lvlk,
                            (int)plan->start_level, &p, b, e, paths, levels);
    }
    spm_ref_rays = (spm_ref_ray_sink){NULL, NULL};
    free(paths);
    join(l, rs);
    return rc;
}

static spm_u32 fnv(spm_u32 h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 16777619u;
    return h;
}

spm_u32 spm_rays_geometry_hash(const spm_geometry *g)
{
    spm_u32 h = 2166136261u;
    h = fnv(h, g->tris, (size_t)g->ntris * sizeof *g->tris);
    return fnv(h, g->nodes, (size_t)g->nnodes * sizeof *g->nodes);
}

/* The file: "SPMRAYS1", u32 triangles, u32 geometry hash, u64 closest-hit
 * rays, u64 shadow rays, then the spm_ray records (closest first), all in
 * the host's byte order. */
static const char MAGIC[8] = {'S', 'P', 'M', 'R', 'A', 'Y', 'S', '1'};
typedef struct {
    char magic[8];
    spm_u32 ntris, hash;
    uint64_t nclosest, nshadow;
} file_head;

int spm_rays_save(const char *path, const spm_geometry *g, const spm_rayset *rs, spm_error *err)
{
    char part[4200];
    snprintf(part, sizeof part, "%s.part", path);
    FILE *f = fopen(part, "wb");
    if (!f) {
        spm_errorf(err, "%s: %s", part, strerror(errno));
        return 1;
    }
    file_head h;
    memcpy(h.magic, MAGIC, sizeof MAGIC);
    h.ntris = (spm_u32)g->ntris;
    h.hash = spm_rays_geometry_hash(g);
    h.nclosest = rs->nclosest;
    h.nshadow = rs->n - rs->nclosest;
    int bad = fwrite(&h, sizeof h, 1, f) != 1 ||
              (rs->n && fwrite(rs->rays, sizeof *rs->rays, rs->n, f) != rs->n);
    if (fclose(f) || bad || rename(part, path)) {
        spm_errorf(err, "%s: %s", path, strerror(errno));
        remove(part);
        return 1;
    }
    return 0;
}

static int ray_ok(const spm_ray *r, spm_u32 ntris)
{
    for (int k = 0; k < 3; k++)
        if (!isfinite(r->o[k]) || !isfinite(r->d[k]))
            return 0;
    return (r->skip == 0xFFFFFFFFu || r->skip < ntris) &&
           (r->emitter == SPM_RAY_CLOSEST || r->emitter < ntris);
}

int spm_rays_load(const char *path, const spm_geometry *g, spm_rayset *rs, spm_error *err)
{
    memset(rs, 0, sizeof *rs);
    FILE *f = fopen(path, "rb");
    if (!f) {
        spm_errorf(err, "%s: %s", path, strerror(errno));
        return 1;
    }
    file_head h;
    int rc = 1;
    if (fread(&h, sizeof h, 1, f) != 1 || memcmp(h.magic, MAGIC, sizeof MAGIC)) {
        spm_errorf(err, "%s: not a ray file (no SPMRAYS1 header)", path);
    } else if (h.ntris != (spm_u32)g->ntris || h.hash != spm_rays_geometry_hash(g)) {
        spm_errorf(err, "%s: recorded on other geometry (%u triangles, hash %08x; this scene: %d, "
                   "%08x): record it again with --rays-save", path, h.ntris, h.hash, g->ntris,
                   spm_rays_geometry_hash(g));
    } else if (h.nclosest > ((uint64_t)1 << 32) || h.nshadow > ((uint64_t)1 << 32)) {
        spm_errorf(err, "%s: header claims %llu + %llu rays", path,
                   (unsigned long long)h.nclosest, (unsigned long long)h.nshadow);
    } else {
        rs->nclosest = (size_t)h.nclosest;
        rs->n = (size_t)(h.nclosest + h.nshadow);
        rs->rays = spm_xmalloc((rs->n ? rs->n : 1) * sizeof *rs->rays);
        size_t got = fread(rs->rays, sizeof *rs->rays, rs->n, f);
        char extra;
        if (got != rs->n) {
            spm_errorf(err, "%s: truncated: ray %zu of %zu missing (byte %zu)", path, got, rs->n,
                       sizeof h + got * sizeof *rs->rays);
        } else if (fread(&extra, 1, 1, f) == 1) {
            spm_errorf(err, "%s: data after the last of its %zu rays", path, rs->n);
        } else {
            rc = 0;
            for (size_t i = 0; i < rs->n && !rc; i++)
                if (!ray_ok(&rs->rays[i], h.ntris) ||
                    (i < rs->nclosest) != (rs->rays[i].emitter == SPM_RAY_CLOSEST)) {
                    spm_errorf(err, "%s: ray %zu (byte %zu) is malformed (non-finite, a triangle "
                               "out of range, or a kind out of order)", path, i,
                               sizeof h + i * sizeof *rs->rays);
                    rc = 1;
                }
        }
    }
    fclose(f);
    if (rc)
        spm_rayset_free(rs);
    return rc;
}

/* ---- a coherent order (--rays-sort) --------------------------------------- */
typedef struct {
    uint64_t key;
    spm_u32 at;
} ray_key;

static int key_cmp(const void *a, const void *b)
{
    const ray_key *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return x->at < y->at ? -1 : x->at > y->at;
}

/* 10 bits of each cell coordinate interleaved (a Morton code) */
static uint64_t morton3(const spm_u32 c[3])
{
    uint64_t m = 0;
    for (int b = 0; b < 10; b++)
        for (int k = 0; k < 3; k++)
            m |= (uint64_t)((c[k] >> b) & 1u) << (3 * b + k);
    return m;
}

/* Rays [b, e) stably by the octant of their direction, then their origin's
 * cell of a 1024^3 grid over the origins' bounds in Morton order: neighbours
 * in the order start near each other and head the same way. */
static void sort_kind(spm_ray *rays, size_t b, size_t e)
{
    if (e - b < 2)
        return;
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++)
        lo[k] = hi[k] = rays[b].o[k];
    for (size_t i = b; i < e; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], rays[i].o[k]);
            hi[k] = fmaxf(hi[k], rays[i].o[k]);
        }
    ray_key *keys = spm_xmalloc((e - b) * sizeof *keys);
    for (size_t i = b; i < e; i++) {
        spm_u32 cell[3], octant = 0;
        for (int k = 0; k < 3; k++) {
            double span = (double)hi[k] - lo[k], u = span > 0 ? (rays[i].o[k] - lo[k]) / span : 0;
            cell[k] = u >= 1 ? 1023u : (spm_u32)(u * 1024);
            octant |= (spm_u32)(rays[i].d[k] < 0) << k;
        }
        keys[i - b] = (ray_key){(uint64_t)octant << 30 | morton3(cell), (spm_u32)(i - b)};
    }
    qsort(keys, e - b, sizeof *keys, key_cmp);
    spm_ray *tmp = spm_xmalloc((e - b) * sizeof *tmp);
    for (size_t i = 0; i < e - b; i++)
        tmp[i] = rays[b + keys[i].at];
    memcpy(rays + b, tmp, (e - b) * sizeof *tmp);
    free(tmp);
    free(keys);
}

/* ---- replay on OpenCL ---------------------------------------------------- */
#define ARG_FIELD(dev, host, name) host name;
typedef struct { SPM_RAYS_ARGS(ARG_FIELD, ) } rays_args;
#define SET_ARG(dev, host, name) \
    rc = rc || spm_cl_arg(k, i++, sizeof a->name, &a->name, "spm_rays", err);

static int set_args(cl_kernel k, const rays_args *a, spm_error *err)
{
    int rc = 0;
    cl_uint i = 0;
    SPM_RAYS_ARGS(SET_ARG, )
    return rc;
}

/* One launch over rays [first, first + n); its kernel time in *s (-1: no times). */
static int launch(spm_cl_ctx *c, cl_kernel k, rays_args *a, size_t first, size_t n, double *s,
                  spm_error *err)
{
    *s = 0;
    if (!n)
        return 0;
    a->first = (spm_u32)first;
    a->nrays = (spm_u32)n;
    size_t global = (n + group - 1) / group * group;
    return set_args(k, a, err) || spm_cl_launch(c, k, global, group, s, "spm_rays", err);
}

static cl_mem buffer(spm_cl_ctx *c, cl_mem_flags fl, size_t size, void *host, spm_error *err,
                     int *bad)
{
    cl_mem m = NULL;
    if (!*bad)
        *bad = spm_cl_buffer(c, fl, size, host, "rays", &m, err);
    return m;
}

static int read_counters(spm_cl_ctx *c, cl_mem m, cl_uint *v, spm_error *err)
{
    return spm_cl_read(c, m, SPM_RAYS_NCOUNTERS * sizeof *v, v, "counters", err);
}

static int zero_counters(spm_cl_ctx *c, cl_mem m, spm_error *err)
{
    cl_uint z[SPM_RAYS_NCOUNTERS] = {0};
    return spm_cl_write(c, m, sizeof z, z, "counters", err);
}

/* The counting build over both kinds: per-ray nodes and triangle tests. */
static int count_costs(spm_cl_ctx *c, cl_program prog, rays_args *a, const spm_rayset *rs,
                       spm_rays_timing *tm, spm_error *err)
{
    cl_kernel k;
    if (spm_cl_kernel(prog, "spm_rays", &k, err))
        return 1;
    size_t ns = rs->n - rs->nclosest;
    cl_uint v[SPM_RAYS_NCOUNTERS];
    double s;
    int rc = zero_counters(c, a->counters, err) ||
         launch(c, k, a, 0, rs->nclosest, &s, err) || read_counters(c, a->counters, v, err);
    if (!rc) {
    tm->nodes_closest = rs->nclosest ? (double)v[SPM_COUNTER_NODES] / rs->nclosest : 0;
    tm->tris_closest = rs->nclosest ? (double)v[SPM_COUNTER_TRIS] / rs->nclosest : 0;
    rc = zero_counters(c, a->counters, err) || launch(c, k, a, rs->nclosest, ns, &s, err) ||
         read_counters(c, a->counters, v, err);
    }
    if (!rc) {
    tm->nodes_shadow = ns ? (double)v[SPM_COUNTER_NODES] / ns : 0;
    tm->tris_shadow = ns ? (double)v[SPM_COUNTER_TRIS] / ns : 0;
    }
    spm_cl_release_kernel(k);
    return rc;
}

const char spm_rays_program_file[] = "kernels/rays.cl";
const char *const spm_rays_program_defines[6] = {"", "-DSPM_RAYS_STATS", "-DSPM_RAYS_PACKET",
                                                 "-DSPM_RAYS_PACKET -DSPM_RAYS_STATS",
                                                 "-DSPM_RAYS_QUANT",
                                                 "-DSPM_RAYS_QUANT -DSPM_RAYS_STATS"};

int spm_rays_replay_cl(int device, const spm_geometry *g, const spm_rayset *rs, int repeat,
                   int stats, int *hits, spm_rays_timing *tm, char *devname, size_t devlen,
                   void (*each)(void *ctx, int run), void *ctx, spm_error *err)
{
    memset(tm, 0, sizeof *tm);
    tm->nodes_closest = tm->nodes_shadow = tm->tris_closest = tm->tris_shadow = -1;
    spm_cl_ctx c;
    if (spm_cl_ctx_create(device, &c, err))
    return 1;
    snprintf(devname, devlen, "%s", c.dev.name);
    const char *files[] = {spm_rays_program_file};
    cl_program prog = NULL, sprog = NULL;
    cl_kernel k = NULL;
    rays_args a;
    memset(&a, 0, sizeof a);
    const char *const *defs = spm_rays_program_defines + 2 * variant;
    int bad = spm_cl_build(&c, files, 1, defs[0], &prog, err) ||
          (stats && spm_cl_build(&c, files, 1, defs[1], &sprog, err));
    a.tris = buffer(&c, CL_MEM_READ_ONLY, (size_t)g->ntris * sizeof *g->tris, g->tris, err, &bad);
    /* the tree the variant traverses: the wide nodes, or their quantised twin */
    spm_bvhq_node *qn = NULL;
    size_t nq = 0;
    if (!bad && variant == 2)
        bad = spm_bvhq_build(g, &qn, &nq, err);
    tm->tree_bytes = variant == 2 ? nq * sizeof *qn : (size_t)g->nwide * sizeof *g->wide;
    a.nodes = buffer(&c, CL_MEM_READ_ONLY, tm->tree_bytes, variant == 2 ? (void *)qn : g->wide,
                     err, &bad);
    free(qn);
    a.rays = buffer(&c, CL_MEM_READ_ONLY, rs->n * sizeof *rs->rays, rs->rays, err, &bad);
    a.hits = buffer(&c, CL_MEM_READ_WRITE, rs->n * sizeof *hits, NULL, err, &bad);
    a.counters = buffer(&c, CL_MEM_READ_WRITE, SPM_RAYS_NCOUNTERS * sizeof(cl_uint), NULL, err,
                    &bad);
    if (!bad) {
    bad = spm_cl_kernel(prog, "spm_rays", &k, err) || zero_counters(&c, a.counters, err);
    }
    size_t ns = rs->n - rs->nclosest;
    tm->closest_s = tm->shadow_s = INFINITY;
    /* run 0 warms up (PoCL compiles a kernel again at its first launch) */
    for (int r = 0; r <= repeat && !bad; r++) {
    double sc, ss;
    bad = launch(&c, k, &a, 0, rs->nclosest, &sc, err) ||
          launch(&c, k, &a, rs->nclosest, ns, &ss, err);
    if (!bad && (sc < 0 || ss < 0)) {
        spm_errorf(err, "device '%s' gives no kernel times (profiling)", c.dev.name);
        bad = 1;
    }
    if (!bad && r > 0) {
        tm->closest_s = sc < tm->closest_s ? sc : tm->closest_s;
        tm->shadow_s = ss < tm->shadow_s ? ss : tm->shadow_s;
    }
    if (!bad && each)
        each(ctx, r);
    if (!bad && spm_stop_requested()) {
        spm_errorf(err, "interrupted while replaying rays");
        bad = 1;
    }
    }
    cl_uint v[SPM_RAYS_NCOUNTERS];
    if (!bad && rs->n)
    bad = spm_cl_read(&c, a.hits, rs->n * sizeof *hits, hits, "hits", err);
    if (!bad && !(bad = read_counters(&c, a.counters, v, err)))
    tm->stack_overflows = v[SPM_COUNTER_STACK];
    if (!bad && stats)
    bad = count_costs(&c, sprog, &a, rs, tm, err);
    spm_cl_release_kernel(k);
    cl_mem mems[] = {a.tris, a.nodes, a.rays, a.hits, a.counters};
    for (size_t i = 0; i < sizeof mems / sizeof *mems; i++)
    spm_cl_release_mem(mems[i]);
    spm_cl_release_program(prog);
    spm_cl_release_program(sprog);
    spm_cl_ctx_release(&c);
    return bad;
}

/* ---- the reference's traversal -------------------------------------------- */
void spm_rays_replay_ref(const spm_geometry *g, const spm_rayset *rs, int *hits,
                     spm_rays_timing *tm)
{
    memset(tm, 0, sizeof *tm);
    tm->tris_closest = tm->tris_shadow = -1;
    for (int kind = 0; kind < 2; kind++) {
    size_t b = kind ? rs->nclosest : 0, e = kind ? rs->n : rs->nclosest;
    unsigned long long n0 = spm_bvh_nodes_tested;
    double t0 = spm_now();
    for (size_t i = b; i < e; i++) {
        if (!(i & 4095) && spm_stop_requested())
            return; /* the caller sees the flag */
        float t;
        hits[i] = spm_bvh_intersect(g, rs->rays[i].o, rs->rays[i].d, rs->rays[i].skip, &t);
    }
    double s = spm_now() - t0, per = e > b ? (double)(spm_bvh_nodes_tested - n0) / (e - b) : 0;
    *(kind ? &tm->shadow_s : &tm->closest_s) = s;
    *(kind ? &tm->nodes_shadow : &tm->nodes_closest) = per;
    }
}

static int occluded(int h, spm_u32 emitter)
{
    return h >= 0 && (spm_u32)h != emitter;
}

void spm_rays_compare(const spm_rayset *rs, const int *a, const int *b, size_t *closest_bad,
                  size_t *shadow_bad)
{
    *closest_bad = *shadow_bad = 0;
    for (size_t i = 0; i < rs->nclosest; i++)
    *closest_bad += a[i] != b[i];
    for (size_t i = rs->nclosest; i < rs->n; i++)
    *shadow_bad += occluded(a[i], rs->rays[i].emitter) != occluded(b[i], rs->rays[i].emitter);
}

static int share_vertex(const spm_tri *a, const spm_tri *b)
{
    const float *va[3] = {a->v0, a->v1, a->v2}, *vb[3] = {b->v0, b->v1, b->v2};
    for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
        if (!memcmp(va[i], vb[j], 3 * sizeof(float)))
            return 1;
    return 0;
}

/* The triangle an answer names: a closest-hit ray's hit, a shadow ray's occluder. */
static int answer_tri(const spm_geometry *g, const spm_ray *r, int closest, int h)
{
    if (h < 0 || h >= g->ntris || (!closest && (spm_u32)h == r->emitter))
    return -1;
    return h;
}

size_t spm_rays_differ_adjacent(const spm_geometry *g, const spm_rayset *rs, const int *a,
                            const int *b)
{
    size_t n = 0;
    for (size_t i = 0; i < rs->n; i++) {
    const spm_ray *r = &rs->rays[i];
    int closest = i < rs->nclosest;
    int differ = closest ? a[i] != b[i]
                         : occluded(a[i], r->emitter) != occluded(b[i], r->emitter);
    if (!differ)
        continue;
    int ta = answer_tri(g, r, closest, a[i]), tb = answer_tri(g, r, closest, b[i]);
    int origin = r->skip < (spm_u32)g->ntris ? (int)r->skip : -1;
    if (ta >= 0 && tb >= 0)
        n += share_vertex(&g->tris[ta], &g->tris[tb]);
    else if ((ta >= 0 || tb >= 0) && origin >= 0)
        n += share_vertex(&g->tris[ta >= 0 ? ta : tb], &g->tris[origin]);
    }
    return n;
}

/* ---- the benchmark -------------------------------------------------------- */
static double mrays(size_t n, double s)
{
    return s > 0 ? n / s / 1e6 : 0;
}

static void json_num(FILE *f, const char *key, double v, const char *sep)
{
    if (v < 0 || !isfinite(v))
    fprintf(f, "\"%s\": null%s", key, sep);
    else
    fprintf(f, "\"%s\": %.6g%s", key, v, sep);
}

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (const char *p = s; *p; p++)
    if (*p == '"' || *p == '\\')
        fprintf(f, "\\%c", *p);
    else if ((unsigned char)*p < 0x20)
        fprintf(f, "\\u%04x", (unsigned char)*p);
    else
        fputc(*p, f);
    fputc('"', f);
}

static void json_impl(FILE *f, const char *name, const char *what, const spm_rayset *rs,
                  const spm_rays_timing *t, size_t cbad, size_t sbad, const char *sep)
{
    fprintf(f, "  \"%s\": {\"what\": ", name);
    json_str(f, what);
    fprintf(f, ", ");
    size_t ns = rs->n - rs->nclosest;
    json_num(f, "closest_s", t->closest_s, ", ");
    json_num(f, "shadow_s", t->shadow_s, ", ");
    json_num(f, "closest_mrays_s", mrays(rs->nclosest, t->closest_s), ", ");
    json_num(f, "shadow_mrays_s", mrays(ns, t->shadow_s), ", ");
    json_num(f, "nodes_closest", t->nodes_closest, ", ");
    json_num(f, "nodes_shadow", t->nodes_shadow, ", ");
    json_num(f, "tris_closest", t->tris_closest, ", ");
    json_num(f, "tris_shadow", t->tris_shadow, ", ");
    fprintf(f, "\"closest_differ\": %zu, \"shadow_differ\": %zu}%s\n", cbad, sbad, sep);
}

static void text_row(FILE *f, const char *what, const spm_rayset *rs, const spm_rays_timing *t)
{
    size_t ns = rs->n - rs->nclosest;
    fprintf(f, "  %-12s %9.3f %9.3f", what, mrays(rs->nclosest, t->closest_s),
        mrays(ns, t->shadow_s));
    if (t->nodes_closest >= 0)
    fprintf(f, " %8.1f %8.1f", t->nodes_closest, t->nodes_shadow);
    else
    fprintf(f, " %8s %8s", "-", "-");
    if (t->tris_closest >= 0)
    fprintf(f, " %8.1f %8.1f", t->tris_closest, t->tris_shadow);
    else
    fprintf(f, " %8s %8s", "-", "-");
    fprintf(f, "\n");
}

/* Embree's runs between the kernel's (spm_rays_replay_cl's `each`) */
typedef struct {
    spm_rays_embree *e;
    spm_rays_timing *tm;
    int rc;
    spm_error err;
} interleave;

static void embree_run(void *ctx, int run)
{
    interleave *il = ctx;
    double sc, ss;
    if (il->rc)
    return;
    il->rc = spm_rays_embree_run(il->e, &sc, &ss, &il->err);
    if (!il->rc && run > 0) { /* run 0 is the warm-up, as the kernel's */
    il->tm->closest_s = sc < il->tm->closest_s ? sc : il->tm->closest_s;
    il->tm->shadow_s = ss < il->tm->shadow_s ? ss : il->tm->shadow_s;
    }
}

/* What the report shows of the three traversals. */
typedef struct {
    spm_rays_timing tcl, tref, tem; /* the kernel's, the reference's, Embree's */
    int have_embree;
    char dev[256], einfo[512], what[512];
    size_t rcb, rsb, ecb, esb, eedge; /* rays that differ: closest, shadow; at an edge */
} rays_report;

static void print_text(const spm_rays_opts *o, const spm_render_setup *s, const spm_rayset *rs,
                       const rays_report *r)
{
    const spm_geometry *g = &s->geom;
    size_t ns = rs->n - rs->nclosest;
    printf("%s: %d triangles, %d BVH nodes; %zu closest-hit and %zu shadow rays (%dx%d, "
           "%d spp)\n", o->scene ? o->scene : "built-in scene", g->ntris, g->nnodes,
           rs->nclosest, ns, s->scene.width, s->scene.height, o->spp);
    printf("  %-12s %9s %9s %17s %17s\n", "", "closest", "shadow", "nodes/ray",
           "tri tests/ray");
    printf("  %-12s %9s %9s %8s %8s %8s %8s\n", "traversal", "Mrays/s", "Mrays/s",
           "closest", "shadow", "closest", "shadow");
    text_row(stdout, "specmip", rs, &r->tcl);
    text_row(stdout, "reference", rs, &r->tref);
    if (r->have_embree)
        text_row(stdout, "Embree", rs, &r->tem);
    printf("  specmip: %s, fastest of %d%s; its tree %.1f MB\n"
           "  reference: the CPU reference's traversal, 1 thread (nodes: box tests)\n",
           r->what, o->repeat, r->have_embree ? ", each run beside one of Embree's" : "",
           r->tcl.tree_bytes / 1e6);
    if (r->have_embree) {
        printf("  Embree: %s, fastest of %d\n", r->einfo, o->repeat);
        printf("  specmip / Embree rays/s: closest %.3f, shadow %.3f\n",
               r->tem.closest_s / r->tcl.closest_s, r->tem.shadow_s / r->tcl.shadow_s);
    }
    printf("  differ from the reference: %zu of %zu closest, %zu of %zu shadow\n", r->rcb,
           rs->nclosest, r->rsb, ns);
    if (r->have_embree)
        printf("  differ from Embree: %zu of %zu closest, %zu of %zu shadow (%zu of them "
               "at a shared edge or vertex)\n", r->ecb,
               rs->nclosest, r->esb, ns, r->eedge);
    if (r->tcl.stack_overflows)
        printf("  BVH stack overflows: %u\n", r->tcl.stack_overflows);
}

/* The report as one JSON object on standard output. */
static void print_json(const spm_rays_opts *o, const spm_render_setup *s, const spm_rayset *rs,
                       const rays_report *r, double record_s)
{
    const spm_geometry *g = &s->geom;
    printf("{\n  \"scene\": ");
    json_str(stdout, o->scene ? o->scene : "default");
    printf(", \"triangles\": %d, \"nodes\": %d, \"width\": %d, "
           "\"height\": %d, \"spp\": %d, \"rays_closest\": %zu, \"rays_shadow\": %zu,\n"
           "  \"load_s\": %.6g, \"bvh_s\": %.6g, \"record_s\": %.6g, "
           "\"stack_overflows\": %u, \"tree_bytes\": %zu,\n",
           g->ntris, g->nnodes, s->scene.width, s->scene.height, o->spp, rs->nclosest,
           rs->n - rs->nclosest, s->times.load_s, s->times.bvh_s, record_s,
           r->tcl.stack_overflows, r->tcl.tree_bytes);
    json_impl(stdout, "specmip", r->what, rs, &r->tcl, 0, 0, ",");
    json_impl(stdout, "reference", "CPU reference traversal, 1 thread", rs, &r->tref, r->rcb,
              r->rsb, ",");
    if (r->have_embree) {
        json_impl(stdout, "embree", r->einfo, rs, &r->tem, r->ecb, r->esb, ",");
        printf("  \"embree_differ_adjacent\": %zu\n", r->eedge);
    } else {
        printf("  \"embree\": null\n");
    }
    printf("}\n");
}

/* The variant and work-group size the options ask for, or why they do not go together. */
static int rays_variant(const spm_rays_opts *o, spm_error *err)
{
    if (o->group)
        group = (size_t)o->group;
    if (o->packet && o->quant) {
        spm_errorf(err, "--rays-packet and --rays-quant: one variant at a time");
        return SPM_EXIT_INPUT;
    }
    if (o->wavefront && (o->packet || o->quant || o->sort || o->save || o->load || o->stats)) {
        spm_errorf(err, "--rays-wavefront traces its own rays in both orders: --rays-packet, "
                   "--rays-quant, --rays-sort, --rays-save, --rays-load and --rays-stats do not apply");
        return SPM_EXIT_INPUT;
    }
    variant = o->quant ? 2 : o->packet;
    if (variant == 1 && group > 64) {
        spm_errorf(err, "--rays-packet: work-groups of at most 64 rays (--rays-group %zu)", group);
        return SPM_EXIT_INPUT;
    }
    return 0;
}

int spm_bench_rays(const spm_rays_opts *o, spm_error *err)
{
    if (rays_variant(o, err))
        return SPM_EXIT_INPUT;
    spm_render_config cfg;
    spm_render_config_defaults(&cfg);
    cfg.scene_path = o->scene;
    cfg.width = o->width;
    cfg.height = o->height;
    cfg.seed = o->seed;
    cfg.backend = &spm_backend_kind_cpu; /* the plan and the reference; the replay opens a device */
    spm_render_setup s;
    int rc = spm_render_setup_open(&cfg, &s, err);
    if (rc) {
        spm_render_setup_close(&s);
        return rc;
    }
    if (o->wavefront) { /* its own rays, bounce by bounce */
        rc = spm_bench_wavefront(o, &s, err);
        spm_render_setup_close(&s);
        return rc;
    }
    const spm_geometry *g = &s.geom;
    spm_rayset rs;
    memset(&rs, 0, sizeof rs);
    double t0 = spm_now();
    if (o->load)
        rc = spm_rays_load(o->load, g, &rs, err) ? SPM_EXIT_INPUT : 0;
    else
        rc = spm_rays_record(&s.plan, o->spp, &rs, err);
    double record_s = spm_now() - t0;
    if (!rc && o->sort) { /* every traversal replays the same order */
        sort_kind(rs.rays, 0, rs.nclosest);
        sort_kind(rs.rays, rs.nclosest, rs.n);
    }
    if (!rc && o->save && spm_rays_save(o->save, g, &rs, err))
        rc = SPM_EXIT_INPUT;
    int *hcl = spm_xmalloc((rs.n + 1) * sizeof *hcl), *href = spm_xmalloc((rs.n + 1) * sizeof *href);
    int *hem = spm_xmalloc((rs.n + 1) * sizeof *hem);
    rays_report r;
    memset(&r, 0, sizeof r);
    /* Embree's scene is built first, then its runs alternate with the kernel's */
    interleave il = {NULL, &r.tem, 0, {{0}}};
    r.tem.nodes_closest = r.tem.nodes_shadow = r.tem.tris_closest = r.tem.tris_shadow = -1;
    r.tem.closest_s = r.tem.shadow_s = INFINITY;
    if (!rc && o->embree) {
        il.e = spm_rays_embree_open(g, &rs, o->threads, o->embree_quality, hem, r.einfo,
                                    sizeof r.einfo, err);
        if (!il.e)
            rc = spm_stop_requested() ? SPM_EXIT_INTERRUPTED : SPM_EXIT_RUNTIME;
    }
    if (!rc && spm_rays_replay_cl(o->device, g, &rs, o->repeat, o->stats, hcl, &r.tcl, r.dev,
                                  sizeof r.dev, il.e ? embree_run : NULL, &il, err))
        rc = spm_stop_requested() ? SPM_EXIT_INTERRUPTED : SPM_EXIT_RUNTIME;
    if (!rc && il.rc) {
        *err = il.err;
        rc = spm_stop_requested() ? SPM_EXIT_INTERRUPTED : SPM_EXIT_RUNTIME;
    }
    spm_error cerr;
    if (spm_rays_embree_close(il.e, &cerr) && !rc) {
        *err = cerr;
        rc = SPM_EXIT_RUNTIME;
    }
    r.have_embree = !rc && il.e;
    if (!rc) {
        spm_rays_replay_ref(g, &rs, href, &r.tref);
        spm_rays_compare(&rs, hcl, href, &r.rcb, &r.rsb);
        if (spm_stop_requested()) {
            spm_errorf(err, "interrupted while replaying rays");
            rc = SPM_EXIT_INTERRUPTED;
        }
    }
    if (r.have_embree) {
        spm_rays_compare(&rs, hcl, hem, &r.ecb, &r.esb);
        r.eedge = spm_rays_differ_adjacent(g, &rs, hcl, hem);
    }
    if (!rc) {
        snprintf(r.what, sizeof r.what, "specmip kernels/rays.cl%s on %s, work-groups of %zu",
                 variant == 1 ? " (packets)" : variant == 2 ? " (quantised nodes)" : "", r.dev,
                 group);
        if (o->json)
            print_json(o, &s, &rs, &r, record_s);
        else
            print_text(o, &s, &rs, &r);
    }
    free(hcl);
    free(href);
    free(hem);
    spm_rayset_free(&rs);
    spm_render_setup_close(&s);
    return rc;
}
