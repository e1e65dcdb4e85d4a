/* The Embree 3 side of `specmip bench --rays` (bench_rays.h). Optional: built
 * with SPM_HAVE_EMBREE (CMake finds libembree-dev), a stub otherwise. */
#include "bench_rays.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef SPM_HAVE_EMBREE
spm_rays_embree *spm_rays_embree_open(const spm_geometry *g, const spm_rayset *rs, int threads,
                                      int quality, int *hits, char *info, size_t infolen,
                                      spm_error *err)
{
    (void)g, (void)rs, (void)threads, (void)quality, (void)hits, (void)info, (void)infolen;
    spm_errorf(err, "this specmip was built without Embree (apt-get install libembree-dev, then "
                    "configure again), so --embree is not available");
    return NULL;
}

int spm_rays_embree_run(spm_rays_embree *e, double *closest_s, double *shadow_s, spm_error *err)
{
    (void)e, (void)closest_s, (void)shadow_s;
    spm_errorf(err, "built without Embree");
    return 1;
}

void spm_rays_embree_bind(spm_rays_embree *e, const spm_rayset *rs, int *hits)
{
    (void)e, (void)rs, (void)hits;
}

int spm_rays_embree_close(spm_rays_embree *e, spm_error *err)
{
    (void)e, (void)err;
    return 0;
}
#else
#include <embree3/rtcore.h>
#include <limits.h>
#include <math.h>
#include <pmmintrin.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <xmmintrin.h>
#include "interrupt.h"

/* The intersect context carries the triangles a ray must not hit. */
typedef struct {
    struct RTCIntersectContext ctx;
    unsigned skip, emitter;
} skip_ctx;

static void skip_filter(const struct RTCFilterFunctionNArguments *a)
{
    const skip_ctx *c = (const skip_ctx *)a->context;
    for (unsigned i = 0; i < a->N; i++) {
        /* RTCHitN's primID field (rtcore_ray.h's accessor is C++ only) */
        unsigned prim = ((const unsigned *)a->hit)[5 * a->N + i];
        if (prim == c->skip || prim == c->emitter)
            a->valid[i] = 0;
    }
}

typedef struct {
    RTCScene scene;
    const spm_geometry *g;
    const spm_rayset *rs;
    int *hits;
    size_t begin, end;
    atomic_size_t next;
} job;

#define CHUNK 256 /* rays a thread takes at a time */

static void closest(job *j, size_t i)
{
    const spm_ray *r = &j->rs->rays[i];
    float o[3]; /* where the renderer's traversal starts it */
    spm_ray_spawn(j->g, r->skip, r->o, r->d, o);
    skip_ctx c;
    rtcInitIntersectContext(&c.ctx);
    c.ctx.filter = skip_filter;
    c.skip = r->skip;
    c.emitter = RTC_INVALID_GEOMETRY_ID;
    struct RTCRayHit rh;
    rh.ray = (struct RTCRay){o[0], o[1], o[2], 0.0f, r->d[0], r->d[1], r->d[2], 0.0f,
                             INFINITY, UINT_MAX, 0, 0};
    rh.hit.geomID = rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(j->scene, &c.ctx, &rh);
    j->hits[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : (int)rh.hit.primID;
}

/* Occluded over [0, te], te where the ray meets its emitter (everything when
 * it does not): trace.cl's "the closest hit is the emitter or nothing". */
static void shadow(job *j, size_t i)
{
    const spm_ray *r = &j->rs->rays[i];
    float o[3]; /* where the renderer's traversal starts it */
    spm_ray_spawn(j->g, r->skip, r->o, r->d, o);
    float te = spm_tri_intersect(&j->g->tris[r->emitter], o, r->d);
    if (r->emitter == r->skip)
        te = -1.0f;
    skip_ctx c;
    rtcInitIntersectContext(&c.ctx);
    c.ctx.filter = skip_filter;
    c.skip = r->skip;
    c.emitter = r->emitter;
    struct RTCRay ray = {o[0], o[1], o[2], 0.0f, r->d[0], r->d[1], r->d[2], 0.0f,
                         te >= 0.0f ? te : INFINITY, UINT_MAX, 0, 0};
    rtcOccluded1(j->scene, &c.ctx, &ray);
    j->hits[i] = ray.tfar == -INFINITY ? INT_MAX : -1;
}

/* Which triangle occludes shadow ray i (after the timed runs, for comparing
 * answers): the closest hit over the same range. */
static void occluder(job *j, size_t i)
{
    const spm_ray *r = &j->rs->rays[i];
    float o[3]; /* where the renderer's traversal starts it */
    spm_ray_spawn(j->g, r->skip, r->o, r->d, o);
    float te = r->emitter == r->skip ? -1.0f : spm_tri_intersect(&j->g->tris[r->emitter], o, r->d);
    skip_ctx c;
    rtcInitIntersectContext(&c.ctx);
    c.ctx.filter = skip_filter;
    c.skip = r->skip;
    c.emitter = r->emitter;
    struct RTCRayHit rh;
    rh.ray = (struct RTCRay){o[0], o[1], o[2], 0.0f, r->d[0], r->d[1], r->d[2], 0.0f,
                             te >= 0.0f ? te : INFINITY, UINT_MAX, 0, 0};
    rh.hit.geomID = rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(j->scene, &c.ctx, &rh);
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID)
        j->hits[i] = (int)rh.hit.primID;
}

static void *worker(void *arg)
{
    job *j = arg;
    /* Embree's advice for its traversal threads */
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    int shadows = j->begin >= j->rs->nclosest;
    for (;;) {
        size_t b = atomic_fetch_add(&j->next, CHUNK);
        if (b >= j->end || spm_stop_requested())
            return NULL;
        size_t e = b + CHUNK < j->end ? b + CHUNK : j->end;
        for (size_t i = b; i < e; i++)
            (shadows ? shadow : closest)(j, i);
    }
}

static double run(job *j, size_t begin, size_t end, int threads)
{
    j->begin = begin;
    j->end = end;
    atomic_store(&j->next, begin);
    pthread_t t[64];
    double t0 = spm_now();
    int n = 0;
    for (; n < threads - 1; n++)
        if (pthread_create(&t[n], NULL, worker, j))
            break;
    worker(j);
    for (int k = 0; k < n; k++)
        pthread_join(t[k], NULL);
    return spm_now() - t0;
}

static void on_error(void *user, enum RTCError code, const char *str)
{
    spm_error *err = user;
    spm_errorf(err, "Embree error %d: %s", (int)code, str ? str : "");
}

struct spm_rays_embree {
    RTCDevice dev;
    job j;
    int threads;
    spm_error *err; /* Embree's error callback writes here */
};

spm_rays_embree *spm_rays_embree_open(const spm_geometry *g, const spm_rayset *rs, int threads,
                                      int quality, int *hits, char *info, size_t infolen,
                                      spm_error *err)
{
    if (threads < 1 || threads > 64)
        threads = 2;
    char cfg[64];
    snprintf(cfg, sizeof cfg, "threads=%d", threads);
    err->msg[0] = 0;
    RTCDevice dev = rtcNewDevice(cfg);
    if (!dev) {
        spm_errorf(err, "rtcNewDevice(%s) failed (error %d)", cfg, (int)rtcGetDeviceError(NULL));
        return NULL;
    }
    rtcSetDeviceErrorFunction(dev, on_error, err);
    RTCScene scene = rtcNewScene(dev);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    static const enum RTCBuildQuality q[] = {RTC_BUILD_QUALITY_LOW, RTC_BUILD_QUALITY_MEDIUM,
                                             RTC_BUILD_QUALITY_HIGH};
    static const char *const qname[] = {"low", "medium", "high"};
    quality = quality < 0 || quality > 2 ? 1 : quality;
    rtcSetSceneBuildQuality(scene, q[quality]);
    RTCGeometry geo = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), (size_t)g->ntris * 3);
    unsigned *idx = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(unsigned), (size_t)g->ntris);
    if (v && idx) {
        /* the triangles' own vertices, in their order */
        for (int i = 0; i < g->ntris; i++) {
            const spm_tri *t = &g->tris[i];
            for (int k = 0; k < 3; k++) {
                v[9 * i + k] = t->v0[k];
                v[9 * i + 3 + k] = t->v1[k];
                v[9 * i + 6 + k] = t->v2[k];
            }
            for (int k = 0; k < 3; k++)
                idx[3 * i + k] = (unsigned)(3 * i + k);
        }
        rtcCommitGeometry(geo);
        rtcAttachGeometry(scene, geo);
    }
    rtcReleaseGeometry(geo);
    double t0 = spm_now();
    rtcCommitScene(scene);
    double build_s = spm_now() - t0;
    snprintf(info, infolen, "Embree %d.%d.%d, %s build quality, rtcIntersect1/rtcOccluded1 on %d "
             "threads, FTZ+DAZ (build %.3f s)", RTC_VERSION_MAJOR, RTC_VERSION_MINOR,
             RTC_VERSION_PATCH, qname[quality], threads, build_s);
    if (err->msg[0]) {
        rtcReleaseScene(scene);
        rtcReleaseDevice(dev);
        return NULL;
    }
    spm_rays_embree *e = spm_xcalloc(1, sizeof *e);
    e->dev = dev;
    e->j = (job){scene, g, rs, hits, 0, 0, 0};
    e->threads = threads;
    e->err = err;
    return e;
}

int spm_rays_embree_run(spm_rays_embree *e, double *closest_s, double *shadow_s, spm_error *err)
{
    *closest_s = run(&e->j, 0, e->j.rs->nclosest, e->threads);
    *shadow_s = run(&e->j, e->j.rs->nclosest, e->j.rs->n, e->threads);
    if (spm_stop_requested()) {
        spm_errorf(err, "interrupted while replaying rays");
        return 1;
    }
    if (e->err->msg[0]) {
        *err = *e->err;
        return 1;
    }
    return 0;
}

void spm_rays_embree_bind(spm_rays_embree *e, const spm_rayset *rs, int *hits)
{
    static const spm_rayset none = {NULL, 0, 0};
    e->j.rs = rs ? rs : &none;
    e->j.hits = hits;
}

int spm_rays_embree_close(spm_rays_embree *e, spm_error *err)
{
    if (!e)
        return 0;
    const spm_rayset *rs = e->j.rs;
    int rc = 0;
    for (size_t i = rs->nclosest; i < rs->n && !spm_stop_requested(); i++)
        if (e->j.hits[i] == INT_MAX)
            occluder(&e->j, i);
    if (e->err->msg[0]) {
        *err = *e->err;
        rc = 1;
    }
    rtcReleaseScene(e->j.scene);
    rtcReleaseDevice(e->dev);
    free(e);
    return rc;
}
#endif
