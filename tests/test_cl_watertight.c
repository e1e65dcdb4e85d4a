/* The kernel's triangle test (watertight_testlib.h) through the ray replay,
 * which runs the renderer's own traversal (kernels/traverse.clh): a grazing
 * ray hits a 1e-8 m^2 triangle, and no ray through a shared edge or vertex of
 * a closed mesh passes between its triangles; and the kernel answers every
 * ray as the CPU reference does. */
#include "bench_rays.h"
#include "cl_testlib.h"
#include "watertight_testlib.h"

static void run(const wt_case *c)
{
    int *hits = malloc(c->n * sizeof *hits);
    spm_rayset rs = {c->rays, c->n, c->n};
    spm_rays_timing tm;
    char dev[256];
    spm_error err;
    int rc = spm_rays_replay_cl(0, &c->g, &rs, 1, 0, hits, &tm, dev, sizeof dev, NULL, NULL, &err);
    CHECK(rc == 0, "%s: replay: %s", c->name, err.msg);
    if (!rc) {
        wt_check("kernel", c, hits);
        size_t differ = 0;
        for (size_t i = 0; i < c->n; i++) {
            float t;
            differ += hits[i] != spm_bvh_intersect(&c->g, c->rays[i].o, c->rays[i].d,
                                                   c->rays[i].skip, &t);
        }
        printf("%s: kernel and reference differ on %zu of %zu rays\n", c->name, differ, c->n);
        CHECK(differ == 0, "%s: the kernel answers as the reference", c->name);
    }
    free(hits);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    wt_all(run);
    TEST_END();
}
