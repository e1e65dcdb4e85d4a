/* The pretests' set on a fluorescent scene (scenes/fluorescent.scene): a
 * dye's absorption and emission shapes are inputs of its matrix, never a
 * factor of a path's element-wise product, so the colours a path records
 * (the emissions, the plain reflectances, the fluorescent diagonals) get
 * exactly the levels a pretest over those colours alone gives them, in `ml`
 * (spm_pretest_run) and in `mlc` (spm_mlc_pretest_run; the scene has no
 * spikes, so its composite form is the 1 nm colour with no lanes). The set
 * is built here from the materials, not by the code under test. And the
 * check can fail: with the shapes as factors the blue LED's level is finer
 * (its products with the rhodamine absorption's tail were judged). */
#include <stdlib.h>
#include <string.h>
#include "geometry.h"
#include "mlc_pretest.h"
#include "tables.h"
#include "testutil.h"

static int same(const spm_pretest_result *a, const spm_pretest_result *b)
{
    if (a->level != b->level || memcmp(a->level_k, b->level_k, sizeof a->level_k))
        return 0;
    for (int l = 1; l < SPM_NUM_LEVELS; l++)
        if (a->err[l] != b->err[l])
            return 0;
    return 1;
}

int main(void)
{
    char path[1024];
    spm_scene sc;
    spm_geometry g;
    spm_tables t;
    spm_error err;
    spm_pretest_opts po;
    spm_quiet_warnings = 1;
    spm_pretest_defaults(&po);
    if (spm_scene_load(spm_data_path("scenes/fluorescent.scene", path, sizeof path), &sc, &err) ||
        spm_geometry_build(&sc, &g, &err) || spm_tables_build(&sc, &po, &t, &err)) {
        CHECK(0, "%s", err.msg);
        TEST_END();
    }
    int n = sc.ncolours;
    /* the colours a path records: an emitter's emission, a plain surface's
     * reflectance, a fluorescent surface's diagonal */
    unsigned char *on_path = calloc((size_t)n, 1);
    for (int m = 0; m < sc.nmaterials; m++) {
        const spm_scene_material *mt = &sc.materials[m];
        if (mt->emit >= 0)
            on_path[mt->emit] = 1;
        if (mt->type == (int)SPM_MAT_FLUOR || mt->type == (int)SPM_MAT_DONALDSON)
            on_path[mt->diag] = 1;
        else if (mt->refl >= 0)
            on_path[mt->refl] = 1;
    }
    const spm_spectrum **set = calloc((size_t)n, sizeof *set), **all = calloc((size_t)n, sizeof *all);
    int *at = calloc((size_t)n, sizeof *at), ns = 0, led = -1, shapes = 0;
    spm_mlc_colour *cols = calloc((size_t)n, sizeof *cols);
    double zero_lanes[SPM_MAX_SPIKES] = {0}, lane_cmf[3][SPM_MAX_SPIKES] = {{0}};
    for (int c = 0; c < n; c++) {
        all[c] = &sc.colours[c].s;
        shapes += !on_path[c];
        if (!on_path[c])
            continue;
        if (!strncmp(sc.colours[c].name, "blue_led", 8))
            led = ns;
        cols[ns] = (spm_mlc_colour){&sc.colours[c].s, &sc.colours[c].s, zero_lanes, 0};
        at[ns] = c;
        set[ns++] = &sc.colours[c].s;
    }
    CHECK(shapes == 4 && led >= 0, "%d colours off the paths (the two dyes' shapes: 4), LED %d",
          shapes, led);
    CHECK(t.nspikes == 0, "the scene has %d spike lanes (the mlc check assumes none)", t.nspikes);
    spm_pretest_result *own = calloc((size_t)n, sizeof *own), *mlc = calloc((size_t)n, sizeof *mlc);
    spm_pretest_result *with = calloc((size_t)n, sizeof *with);
    spm_pretest_run(set, ns, &po, own);
    spm_mlc_pretest_run(cols, ns, 0, (const double (*)[SPM_MAX_SPIKES])lane_cmf, NULL, 0, NULL,
                        NULL, 0, &po, mlc);
    spm_pretest_run(all, n, &po, with); /* the shapes as factors too */
    for (int i = 0; i < ns; i++) {
        const char *name = sc.colours[at[i]].name;
        printf("%-22s ml level %d (5 nm worst %.3f; with the shapes as factors %d, %.3f), mlc %d\n",
               name, t.pretest[at[i]].level_k[0], t.pretest[at[i]].err[1], with[at[i]].level_k[0],
               with[at[i]].err[1], t.mlc_pretest[at[i]].level_k[0]);
        CHECK(same(&t.pretest[at[i]], &own[i]), "%s: ml pretest differs from the path colours' own",
              name);
        CHECK(same(&t.mlc_pretest[at[i]], &mlc[i]),
              "%s: mlc pretest differs from the path colours' own", name);
    }
    if (led >= 0)
        CHECK(with[at[led]].level_k[0] < own[led].level_k[0],
              "the LED's level with the shapes as factors (%d) is not finer than without (%d): "
              "this check cannot tell the sets apart", with[at[led]].level_k[0], own[led].level_k[0]);
    free(on_path), free(set), free(all), free(at), free(cols), free(own), free(mlc), free(with);
    spm_tables_free(&t);
    spm_geometry_free(&g);
    spm_scene_free(&sc);
    TEST_END();
}
