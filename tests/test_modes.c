/* The mode descriptors (modes.h) and the render plan built from them
 * (render_plan.h): names, slots, the shade tables' layout as the kernels read
 * it, the kernels and defines the OpenCL backend compiles, the footprint, the
 * slots a plan marks used, and the two ways of counting levels. */
#include <stdlib.h>
#include <string.h>
#include "refcpu.h"
#include "render_plan.h"
#include "testutil.h"

static void names(void)
{
    char list[256];
    spm_mode_list(" ", list, sizeof list);
    for (int m = 0; m < SPM_MODE_COUNT; m++) {
        const spm_mode_desc *d = spm_mode(m);
        CHECK(d && d->id == m, "mode %d: descriptor at its index", m);
        CHECK(spm_mode_parse(spm_mode_name(m)) == m, "mode %d: its name parses back", m);
        CHECK(d && d->help && d->help[0], "mode %d: a help line", m);
        CHECK(strstr(list, spm_mode_name(m)) != NULL, "%s in the list '%s'", spm_mode_name(m), list);
    }
    CHECK(spm_mode(SPM_MODE_COUNT) == NULL && spm_mode(-1) == NULL, "no mode past the array");
    CHECK(spm_mode_parse("no-such-mode") == -1, "unknown name");
    CHECK(!strcmp(spm_mode_name(99), "?"), "unknown id");
}

static void slots(void)
{
    const spm_mode_desc *ml = spm_mode(SPM_MODE_ML), *ref = spm_mode(SPM_MODE_REF);
    uint8_t l2 = 2u | (SPM_SETBY_REFLECTOR << SPM_SETBY_SHIFT);
    CHECK(spm_mode_slot(ml, l2) == 2, "ml: a level-2 byte (set-by bits too) shades in slot 2");
    CHECK(spm_mode_slot(ml, 7u) == SPM_NUM_LEVELS - 1, "ml: past the finest table clamps");
    CHECK(spm_mode_slot(ref, l2) == 0, "ref: one slot whatever the byte");
    CHECK(spm_mode_nslots(ml) == SPM_NUM_LEVELS && spm_mode_nslots(ref) == 1, "slot counts");
}

/* Every slot of every mode on real tables: rows padded to whole vectors with
 * zeros, the kernel's vectors per colour in its define, distinct kernels per
 * slot, and a footprint that is the tables' bytes. */
static void tables(const spm_tables *t)
{
    for (int m = 0; m < SPM_MODE_COUNT; m++) {
        const spm_mode_desc *d = spm_mode(m);
        size_t bytes = 0;
        char prev[64] = "";
        for (int s = 0; s < spm_mode_nslots(d); s++) {
            spm_shade_table tab;
            spm_shade_table_build(d, t, s, &tab);
            CHECK(tab.lanes >= 1 && tab.lanes <= tab.stride, "%s slot %d: %d lanes in %d", d->name,
                  s, tab.lanes, tab.stride);
            CHECK(tab.width > 0 && tab.stride % tab.width == 0, "%s slot %d: stride %d of width %d",
                  d->name, s, tab.stride, tab.width);
            int zero = 1;
            for (int c = 0; c < tab.ncolours; c++)
                for (int l = tab.lanes; l < tab.stride; l++)
                    zero &= tab.rows[(size_t)c * tab.stride + l] == 0.0f;
            for (int ch = 0; tab.w && ch < 3; ch++)
                for (int l = tab.lanes; l < tab.stride; l++)
                    zero &= tab.w[ch * tab.stride + l] == 0.0f;
            CHECK(zero, "%s slot %d: padding is zero", d->name, s);
            CHECK((tab.w != NULL) == !d->per_path, "%s: weights unless drawn per path", d->name);
            char name[64], define[96], want[32];
            spm_mode_kernel(d, t, s, name, sizeof name, define, sizeof define);
            snprintf(want, sizeof want, "=%d", tab.stride / tab.width);
            CHECK(strstr(define, "=") == NULL || strstr(define, want) != NULL,
                  "%s slot %d: define '%s' says %s vectors", d->name, s, define, want + 1);
            CHECK(strcmp(name, prev) != 0, "%s slot %d: kernel '%s' of its own", d->name, s, name);
            snprintf(prev, sizeof prev, "%s", name);
            bytes += ((size_t)tab.ncolours * tab.stride + (tab.w ? 3 * (size_t)tab.stride : 0) +
                      tab.nextra) * sizeof(float);
            spm_shade_table_free(&tab);
        }
        CHECK(spm_mode_footprint(d, t) == bytes, "%s: footprint %zu, tables %zu", d->name,
              spm_mode_footprint(d, t), bytes);
    }
}

static void plan(const spm_geometry *g, const spm_tables *t)
{
    spm_render_plan p;
    spm_error err;
    CHECK(spm_render_plan_init(&p, g, t, SPM_MODE_COUNT, 1, &err) != 0, "unknown mode refused");
    spm_tables no_mlc = *t;
    no_mlc.mlc_lvlk = NULL;
    CHECK(spm_render_plan_init(&p, g, &no_mlc, SPM_MODE_MLC, 1, &err) != 0 &&
              strstr(err.msg, "Composite Model"),
          "mlc without its tables refused");
    for (int m = 0; m < SPM_MODE_COUNT; m++) {
        if (spm_render_plan_init(&p, g, t, m, 1, &err)) {
            CHECK(0, "%s: plan: %s", spm_mode_name(m), err.msg);
            continue;
        }
        const spm_mode_desc *d = p.mode;
        CHECK(p.used[spm_mode_slot(d, (uint8_t)p.start_level)], "%s: the start level is used",
              d->name);
        /* every level byte the trace gives a pass lands in a used slot */
        spm_trace_params tp = spm_plan_pass_params(&p, 0, 2);
        size_t n = p.npix * 2;
        spm_path *paths = spm_xcalloc(n, sizeof *paths);
        uint8_t *lv = spm_xcalloc(n, 1);
        spm_ref_trace_range(g, t->materials, p.lvlk, (int)p.start_level, &tp, 0, n, paths, lv);
        int in_used = 1;
        size_t hist[256] = {0};
        for (size_t i = 0; i < n; i++) {
            in_used &= p.used[spm_mode_slot(d, lv[i])];
            hist[lv[i]]++;
        }
        CHECK(in_used, "%s: every path's slot is used", d->name);
        spm_pass_stats a, b;
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        spm_count_levels(d, paths, lv, n, &a);
        spm_count_levels_hist(d, hist, n, &b);
        CHECK(a.paths == n && b.paths == n, "%s: paths counted", d->name);
        CHECK(!memcmp(a.level_paths, b.level_paths, sizeof a.level_paths),
              "%s: counts by path and by histogram agree", d->name);
        if (!d->levelled)
            CHECK(a.level_paths[0][SPM_SETBY_NONE] == n, "%s: every path at level 0", d->name);
        free(paths);
        free(lv);
        spm_render_plan_free(&p);
    }
}

int main(void)
{
    spm_quiet_warnings = 1;
    names();
    slots();
    const char *scenes[] = {NULL, "scenes/cornell_spiky.scene"};
    for (size_t k = 0; k < sizeof scenes / sizeof *scenes; k++) {
        spm_scene sc;
        spm_geometry g;
        spm_tables t;
        spm_pretest_opts po;
        spm_error err;
        char path[1024];
        spm_pretest_defaults(&po);
        int rc = scenes[k] ? spm_scene_load(spm_data_path(scenes[k], path, sizeof path), &sc, &err)
                           : spm_scene_default(&sc, &err);
        if (!rc) {
            sc.width = 8, sc.height = 6;
            rc = spm_geometry_build(&sc, &g, &err) || spm_tables_build(&sc, &po, &t, &err);
        }
        if (rc) {
            CHECK(0, "scene %s: %s", scenes[k] ? scenes[k] : "default", err.msg);
            continue;
        }
        tables(&t);
        plan(&g, &t);
        spm_tables_free(&t);
        spm_geometry_free(&g);
        spm_scene_free(&sc);
    }
    TEST_END();
}
