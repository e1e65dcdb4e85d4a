/* Several OpenCL devices of the same kind (PoCL "basic basic": two
 * single-threaded CPU devices) render the same image as one device, bit for
 * bit, however the passes are split: the render loop's split, a fixed
 * alternating split, a device failing on a pass (SPECMIP_CL_FAIL) or at
 * opening (as a kernel build failure would). A single device failing part-way
 * leaves an error and a film of exactly the passes it finished. */
#include <stdlib.h>
#include <string.h>
#include "cl_core.h"
#include "backend_cl.h"
#include "backends.h"
#include "testutil.h"

#define W 40
#define H 30
#define SPP 24
#define SPP_PER_PASS 2 /* 12 passes: every device gets some */
#define NPASSES (SPP / SPP_PER_PASS)
#define SEED 7u

static int open_with(spm_render_config *c, spm_render_setup *s, int ndev, const int *devs)
{
    spm_error err;
    spm_render_config_defaults(c);
    c->width = W;
    c->height = H;
    c->seed = SEED;
    c->ndevices = ndev;
    for (int i = 0; i < ndev; i++)
        c->devices[i] = devs[i];
    int rc = spm_render_setup_open(c, s, &err);
    CHECK(rc == 0, "setup: %s", err.msg);
    return rc;
}

/* Renders spp samples per pixel with the setup's devices into film. */
static int render(spm_render_setup *s, int spp, spm_film *film, spm_run_result *r)
{
    spm_error err;
    spm_film_init(film, W, H, &err);
    spm_run_opts o = {.spp = spp, .spp_per_pass = SPP_PER_PASS, .stop = NULL, .progress = 0};
    int rc = spm_render_run(s->b, s->nb, (size_t)W * H, &o, film, r, &err);
    if (rc)
        printf("render: %s\n", err.msg);
    return rc;
}

static int same_film(const spm_film *a, const spm_film *b)
{
    return a->samples == b->samples && !memcmp(a->sum, b->sum, sizeof(double) * 3 * W * H);
}

/* One device renders the reference film. */
static int reference(spm_film *ref)
{
    spm_render_config c;
    spm_render_setup s;
    spm_run_result r;
    int dev0 = 0;
    if (open_with(&c, &s, 1, &dev0))
        return 1;
    int rc = render(&s, SPP, ref, &r);
    CHECK(rc == 0 && r.spp_done == SPP, "reference render");
    CHECK(r.total.nonfinite == 0, "%llu non-finite samples", (unsigned long long)r.total.nonfinite);
    spm_render_setup_close(&s);
    return rc;
}

/* Both devices through the render loop, and an alternating split by hand. */
static void splits(const spm_film *ref)
{
    spm_render_config c;
    spm_render_setup s;
    spm_run_result r;
    spm_film film;
    int devs[2] = {1, 0};
    if (open_with(&c, &s, 2, devs))
        return;
    CHECK(s.nb == 2, "%d devices opened", s.nb);
    CHECK(render(&s, SPP, &film, &r) == 0, "two devices render");
    CHECK(same_film(ref, &film), "two devices: film differs from one device's");
    printf("render loop split: %d + %d passes\n", r.passes_by_backend[0], r.passes_by_backend[1]);
    /* each device takes a pass before it has a time estimate, so both work */
    CHECK(r.passes_by_backend[0] > 0 && r.passes_by_backend[1] > 0 &&
              r.passes_by_backend[0] + r.passes_by_backend[1] == NPASSES,
          "the render loop split %d passes as %d + %d", NPASSES, r.passes_by_backend[0],
          r.passes_by_backend[1]);
    CHECK(r.per_backend[0].paths > 0 && r.per_backend[1].paths > 0 &&
              r.per_backend[0].paths + r.per_backend[1].paths == (uint64_t)W * H * SPP,
          "paths per device %llu + %llu", (unsigned long long)r.per_backend[0].paths,
          (unsigned long long)r.per_backend[1].paths);
    spm_film_free(&film);

    /* even passes on one device, odd on the other, added in pass order */
    spm_error err;
    spm_film_init(&film, W, H, &err);
    float *img = spm_xcalloc((size_t)W * H * 3, sizeof *img);
    for (int p = 0; p < NPASSES; p++) {
        spm_pass_stats st;
        memset(&st, 0, sizeof st);
        spm_backend *b = s.b[p % 2];
        int rc = b->pass(b, (spm_u32)(p * SPP_PER_PASS), SPP_PER_PASS, img, &st, &err);
        CHECK(rc == 0, "pass %d: %s", p, err.msg);
        spm_film_add_pass(&film, img, SPP_PER_PASS);
    }
    CHECK(same_film(ref, &film), "alternating split: film differs from one device's");
    free(img);
    spm_film_free(&film);
    spm_render_setup_close(&s);
}

/* Device 1's first pass fails: device 0 renders everything, same film. */
static void enqueue_failure(const spm_film *ref)
{
    spm_render_config c;
    spm_render_setup s;
    spm_run_result r;
    spm_film film;
    int devs[2] = {0, 1};
    setenv("SPECMIP_CL_FAIL", "1:0", 1); /* read when a device is opened */
    int rc = open_with(&c, &s, 2, devs);
    unsetenv("SPECMIP_CL_FAIL");
    if (rc)
        return;
    CHECK(render(&s, SPP, &film, &r) == 0, "render with a failing device");
    CHECK(r.failed[1] && !r.failed[0], "failed flags %d %d", r.failed[0], r.failed[1]);
    CHECK(r.passes_by_backend[0] == NPASSES && r.passes_by_backend[1] == 0, "passes %d + %d",
          r.passes_by_backend[0], r.passes_by_backend[1]);
    CHECK(same_film(ref, &film), "failing device: film differs from one device's");
    spm_film_free(&film);
    spm_render_setup_close(&s);
}

/* Device 1 cannot be opened (stands in for a kernel build failure): it is left
 * out and the render goes on with device 0. */
static spm_backend *open_failing_1(int device, const spm_render_plan *plan, spm_error *err)
{
    if (device == 1) {
        spm_errorf(err, "clBuildProgram: CL_BUILD_PROGRAM_FAILURE (injected)");
        return NULL;
    }
    return spm_backend_cl_create(device, plan, err);
}

static void open_failure(const spm_film *ref)
{
    spm_render_config c;
    spm_render_setup s;
    spm_run_result r;
    spm_film film;
    spm_error err;
    spm_render_config_defaults(&c);
    c.width = W;
    c.height = H;
    c.seed = SEED;
    c.all_devices = 1;
    c.open_device = open_failing_1;
    int rc = spm_render_setup_open(&c, &s, &err);
    CHECK(rc == 0 && s.nb == 1, "setup with a device failing to build: rc %d, %d devices", rc,
          s.nb);
    if (!rc) {
        CHECK(render(&s, SPP, &film, &r) == 0, "render after a build failure");
        CHECK(same_film(ref, &film), "build failure: film differs from one device's");
        spm_film_free(&film);
    }
    spm_render_setup_close(&s);

    /* every device failing to open: a runtime error */
    c.all_devices = 0;
    c.ndevices = 1;
    c.devices[0] = 1;
    rc = spm_render_setup_open(&c, &s, &err);
    CHECK(rc == SPM_EXIT_RUNTIME && strstr(err.msg, "BUILD") != NULL, "rc %d: %s", rc, err.msg);
    spm_render_setup_close(&s);
    /* the same index twice, or an unknown one: input errors */
    c.open_device = NULL;
    c.ndevices = 2;
    c.devices[0] = c.devices[1] = 0;
    rc = spm_render_setup_open(&c, &s, &err);
    CHECK(rc == SPM_EXIT_INPUT, "device listed twice: rc %d", rc);
    spm_render_setup_close(&s);
    c.ndevices = 1;
    c.devices[0] = 9;
    rc = spm_render_setup_open(&c, &s, &err);
    CHECK(rc == SPM_EXIT_INPUT, "unknown device: rc %d", rc);
    spm_render_setup_close(&s);
}

/* The only device fails on its 4th pass: an error, and the film holds exactly
 * the 3 passes it finished (the reference device's first 3 passes). */
static void all_failed(void)
{
    spm_render_config c;
    spm_render_setup s;
    spm_run_result r;
    spm_film film, want;
    int dev1 = 1;
    setenv("SPECMIP_CL_FAIL", "1:3", 1);
    int rc = open_with(&c, &s, 1, &dev1);
    unsetenv("SPECMIP_CL_FAIL");
    if (rc)
        return;
    CHECK(render(&s, SPP, &film, &r) == 1, "a render whose only device fails must fail");
    CHECK(r.failed[0] && r.passes_in_film == 3 && r.spp_done == 3 * SPP_PER_PASS,
          "%d passes, %d spp in the film", r.passes_in_film, r.spp_done);
    spm_render_setup_close(&s);
    int dev0 = 0;
    if (open_with(&c, &s, 1, &dev0))
        return;
    CHECK(render(&s, 3 * SPP_PER_PASS, &want, &r) == 0, "render of 3 passes");
    CHECK(same_film(&want, &film), "film of a failed render is not its finished passes");
    spm_film_free(&film);
    spm_film_free(&want);
    spm_render_setup_close(&s);
}

int main(void)
{
    /* PoCL reads this at platform initialisation, i.e. at the first OpenCL call */
    setenv("POCL_DEVICES", "basic basic", 1);
    spm_quiet_warnings = 1;
    spm_cl_device *list;
    int n;
    spm_error err;
    if (spm_cl_devices(&list, &n, &err)) {
        printf("no OpenCL platform: %s\n", err.msg);
        return 1;
    }
    free(list);
    CHECK(n == 2, "POCL_DEVICES='basic basic' gave %d devices", n);
    spm_film ref;
    if (n == 2 && reference(&ref) == 0) {
        splits(&ref);
        enqueue_failure(&ref);
        open_failure(&ref);
        all_failed();
        spm_film_free(&ref);
    }
    TEST_END();
}
