/* The ray replay of `specmip bench --rays`: the recorder captures every ray
 * the reference's paths cast (one closest-hit ray per vertex plus one per
 * escape, one shadow ray per vertex), and kernels/rays.cl, the renderer's own
 * traversal, answers every recorded ray exactly as the CPU reference's
 * traversal does. Exact, not within a tolerance: both use MiniLight's float
 * ray-triangle test with the same operation order (contraction off) and break
 * a tie in t by the lower index, so the answer to one ray does not depend on
 * the order either visits the BVH in. */
#include <string.h>
#include "bench_rays.h"
#include "refcpu.h"
#include "backend_cpu.h"
#include "backends.h"
#include "render_testlib.h"
#include "testutil.h"

static void one_scene(const char *name)
{
    char path[1024];
    spm_render_config cfg;
    spm_render_config_defaults(&cfg);
    if (name) {
        rt_scene_path(name, path, sizeof path);
        cfg.scene_path = path;
    }
    cfg.width = cfg.height = 32;
    cfg.backend = &spm_backend_kind_cpu;
    const char *what = name ? name : "built-in scene";
    spm_render_setup s;
    spm_error err;
    int rc = spm_render_setup_open(&cfg, &s, &err);
    CHECK(rc == 0, "%s: %s", what, err.msg);
    if (rc)
        return;
    const int spp = 2;
    spm_rayset rs;
    CHECK(spm_rays_record(&s.plan, spp, &rs, &err) == 0, "%s: %s", what, err.msg);

    /* the same paths traced again without the recorder: the rays they cast */
    spm_trace_params p = spm_plan_pass_params(&s.plan, 0, spp);
    size_t npaths = s.plan.npix * spp, want_closest = 0, want_shadow = 0;
    spm_path *paths = spm_xmalloc(npaths * sizeof *paths);
    uint8_t *levels = spm_xmalloc(npaths);
    spm_ref_trace_range(&s.geom, s.tables.materials, s.plan.lvlk, (int)s.plan.start_level, &p, 0,
                        npaths, paths, levels);
    for (size_t i = 0; i < npaths; i++) {
        want_closest += paths[i].h.nvert + (paths[i].h.end == SPM_END_ESCAPED);
        want_shadow += s.geom.nemitters ? paths[i].h.nvert : 0;
    }
    CHECK(rs.nclosest == want_closest && rs.n - rs.nclosest == want_shadow,
          "%s: recorded %zu closest-hit and %zu shadow rays, the paths cast %zu and %zu", what,
          rs.nclosest, rs.n - rs.nclosest, want_closest, want_shadow);

    int *hcl = spm_xmalloc(rs.n * sizeof *hcl), *href = spm_xmalloc(rs.n * sizeof *href);
    spm_rays_timing tcl, tref;
    char dev[256];
    rc = spm_rays_replay_cl(0, &s.geom, &rs, 1, 1, hcl, &tcl, dev, sizeof dev, NULL, NULL, &err);
    CHECK(rc == 0, "%s: %s", what, err.msg);
    if (!rc) {
        spm_rays_replay_ref(&s.geom, &rs, href, &tref);
        size_t cbad, sbad;
        spm_rays_compare(&rs, hcl, href, &cbad, &sbad);
        CHECK(cbad == 0 && sbad == 0, "%s: the kernel differs from the reference on %zu of %zu "
              "closest-hit and %zu of %zu shadow rays", what, cbad, rs.nclosest, sbad,
              rs.n - rs.nclosest);
        /* the answers are not all alike: hits and misses, lit and occluded */
        size_t hit = 0, miss = 0, lit = 0, dark = 0;
        for (size_t i = 0; i < rs.nclosest; i++)
            hcl[i] >= 0 ? hit++ : miss++;
        for (size_t i = rs.nclosest; i < rs.n; i++)
            hcl[i] < 0 || (spm_u32)hcl[i] == rs.rays[i].emitter ? lit++ : dark++;
        CHECK(hit > 0 && miss > 0 && lit > 0 && dark > 0,
              "%s: %zu hits, %zu misses, %zu lit, %zu occluded", what, hit, miss, lit, dark);
        CHECK(tcl.stack_overflows == 0, "%s: %u stack overflows", what, tcl.stack_overflows);
        CHECK(tcl.nodes_closest >= 1 && tcl.tris_closest > 0 && tcl.nodes_shadow >= 1,
              "%s: counted %.2f nodes and %.2f triangles per closest-hit ray", what,
              tcl.nodes_closest, tcl.tris_closest);
    }
    free(hcl);
    free(href);
    free(paths);
    free(levels);
    spm_rayset_free(&rs);
    spm_render_setup_close(&s);
}

int main(void)
{
    one_scene(NULL);
    one_scene("multilight.scene");
    one_scene("colorful.scene");
    TEST_END();
}
