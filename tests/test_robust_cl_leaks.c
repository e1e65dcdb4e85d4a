/* No OpenCL object outlives its renderer. Every buffer, kernel, program,
 * queue (and, through the queue, every event) holds a reference to its
 * context, so a context whose reference count is back to exactly the one we
 * hold after spm_cl_destroy proves nothing was leaked. The context is caught
 * by interposing clCreateContext (this program's definition wins over the
 * ICD loader's for the statically linked host library). Checked after a
 * rendered pass in several modes, and on the error paths: a create that
 * fails after the context exists (a kernel that does not build) and a pass
 * that fails (path records too large for one buffer). The test first shows the count
 * is sensitive: one extra buffer raises it. */
#define _GNU_SOURCE /* RTLD_NEXT */
#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "cl_testlib.h"
#include "testutil.h"

static cl_context last_ctx;

cl_context clCreateContext(const cl_context_properties *props, cl_uint ndev,
                           const cl_device_id *devs,
                           void(CL_CALLBACK *notify)(const char *, const void *, size_t, void *),
                           void *user, cl_int *rc)
{
    typedef cl_context (*real_fn)(const cl_context_properties *, cl_uint, const cl_device_id *,
                                  void(CL_CALLBACK *)(const char *, const void *, size_t, void *),
                                  void *, cl_int *);
    real_fn real = (real_fn)dlsym(RTLD_NEXT, "clCreateContext");
    cl_context c = real(props, ndev, devs, notify, user, rc);
    if (c) {
        clRetainContext(c); /* ours: keeps it queryable after the renderer lets go */
        last_ctx = c;
    }
    return c;
}

static cl_uint refcount(cl_context c)
{
    cl_uint n = 0;
    clGetContextInfo(c, CL_CONTEXT_REFERENCE_COUNT, sizeof n, &n, NULL);
    return n;
}

/* After the renderer is gone only our reference may be left; then drop it. */
static void check_released(const char *what)
{
    CHECK(last_ctx != NULL, "%s: no context was created", what);
    if (!last_ctx)
        return;
    /* PoCL's worker threads drop their references to finished commands a
     * moment after clFinish returns: wait up to 2 s for them. */
    cl_uint n = refcount(last_ctx);
    for (int i = 0; i < 200 && n > 1; i++) {
        nanosleep(&(struct timespec){0, 10000000}, NULL);
        n = refcount(last_ctx);
    }
    CHECK(n == 1, "%s: context still has %u references (1 is ours): objects leaked", what, n);
    clReleaseContext(last_ctx);
    last_ctx = NULL;
}

static void render_and_destroy(const cl_test_scene *s, int mode)
{
    spm_cl_renderer *r;
    spm_error err;
    int rc = spm_cl_create(0, &s->geom, &s->tables, mode, 1, &r, &err);
    CHECK(rc == 0, "create mode %d: %s", mode, err.msg);
    if (rc)
        return;
    if (mode == SPM_MODE_ML) { /* the count must see a leaked buffer */
        cl_mem extra = clCreateBuffer(last_ctx, CL_MEM_READ_WRITE, 64, NULL, NULL);
        cl_uint with = refcount(last_ctx);
        clReleaseMemObject(extra);
        CHECK(with == refcount(last_ctx) + 1, "a buffer is not counted (%u)", with);
    }
    size_t npix = (size_t)s->geom.cam.width * (size_t)s->geom.cam.height;
    float *img = calloc(npix * 3, sizeof *img);
    spm_pass_stats st;
    memset(&st, 0, sizeof st);
    for (spm_u32 pass = 0; pass < 2; pass++)
        CHECK(spm_cl_pass(r, pass * 2, 2, img, &st, &err) == 0, "pass: %s", err.msg);
    free(img);
    spm_cl_destroy(r);
    char what[64];
    snprintf(what, sizeof what, "after a render in mode %d", mode);
    check_released(what);
}

int main(void)
{
#if defined(__SANITIZE_ADDRESS__)
    /* PoCL and the ICD loader are not instrumented (tools/test.sh leaves the
     * OpenCL tests out of the sanitizer build). */
    printf("skipped in the sanitizer build\n");
    return 77;
#endif
    if (!cl_test_have_device())
        return 1;
    cl_test_scene s;
    if (cl_test_scene_open(&s, 16, 16))
        return 1;
    int modes[] = {SPM_MODE_ML, SPM_MODE_MLC, SPM_MODE_TRUTH, SPM_MODE_HERO, SPM_MODE_RGB};
    for (size_t i = 0; i < sizeof modes / sizeof *modes; i++)
        render_and_destroy(&s, modes[i]);
    cl_test_scene_close(&s);

    /* Error paths. A create whose kernel build fails (a data root whose
     * shade.cl has a broken line) fails after the context exists; a pass
     * made one batch of 16 x 16 x spp paths whose records need more than the
     * device's largest buffer fails after create. */
    spm_cl_device dev;
    spm_error err;
    CHECK(spm_cl_device_get(0, &dev, &err) == 0, "%s", err.msg);
    char root[] = "/tmp/specmip-leaks-XXXXXX", cmd[512];
    const char *data = getenv("SPECMIP_DATA");
    CHECK(data != NULL, "SPECMIP_DATA is not set (ctest sets it): the broken-kernel case needs it");
    const char *made = mkdtemp(root);
    CHECK(made != NULL, "mkdtemp %s", root);
    if (data && made) {
        snprintf(cmd, sizeof cmd,
                 "cp -r '%s/include' '%s/kernels' '%s/' && echo 'this is not OpenCL' >> '%s/kernels/shade.cl'",
                 data, data, root, root);
        CHECK(system(cmd) == 0, "%s", cmd);
        char *saved = strdup(data);
        setenv("SPECMIP_DATA", root, 1);
        if (cl_test_scene_open(&s, 16, 16) == 0) {
            spm_cl_renderer *r;
            CHECK(spm_cl_create(0, &s.geom, &s.tables, SPM_MODE_ML, 1, &r, &err) != 0,
                  "a broken kernel built");
            printf("%s\n", err.msg);
            check_released("after a failed create");
            cl_test_scene_close(&s);
        }
        setenv("SPECMIP_DATA", saved, 1);
        free(saved);
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
        CHECK(system(cmd) == 0, "%s", cmd);
    }
    /* spp sized to the device: the smallest power of two whose vertex
     * records outgrow its largest buffer (32768 on PoCL here: 4 GB). */
    const cl_ulong per_spp = (cl_ulong)16 * 16 * SPM_MAX_DEPTH * sizeof(spm_vertex);
    spm_u32 spp = 1;
    while ((cl_ulong)spp * per_spp <= dev.max_alloc && spp < (1u << 30))
        spp <<= 1;
    CHECK((cl_ulong)spp * per_spp > dev.max_alloc, "no spp outgrows a %llu-byte buffer",
          (unsigned long long)dev.max_alloc);
    printf("a pass of 16x16 at %u spp: %.1f GB of vertex records, the device's largest buffer %.1f GB\n",
           spp, (double)spp * (double)per_spp / 1e9, (double)dev.max_alloc / 1e9);
    if (cl_test_scene_open(&s, 16, 16) == 0) {
        spm_cl_renderer *r;
        int rc = spm_cl_create(0, &s.geom, &s.tables, SPM_MODE_ML, 1, &r, &err);
        CHECK(rc == 0, "16^2 create: %s", err.msg);
        if (rc == 0) {
            spm_cl_set_batch_paths(r, (size_t)-1); /* the whole pass in one batch */
            float img[16 * 16 * 3];
            spm_pass_stats st;
            memset(&st, 0, sizeof st);
            CHECK(spm_cl_pass(r, 0, spp, img, &st, &err) != 0, "records past the largest buffer accepted");
            printf("%s\n", err.msg);
            spm_cl_destroy(r);
            check_released("after a failed pass");
        }
    }
    cl_test_scene_close(&s);
    TEST_END();
}
