/* Shared by the batching tests (test_cl_batch*.c): a bundled scene, or the
 * default one, at a given size, with its geometry and tables; and the check
 * that two passes' statistics count the same paths the same way. */
#ifndef SPM_TEST_CL_BATCH_H
#define SPM_TEST_CL_BATCH_H
#include "cl_testlib.h"
#include "testutil.h"

/* The scenes the batching tests render: the default Cornell box (every ml
 * path at one level) and the spiky one (ml paths at several levels, so the
 * bucket sort runs in every batch). */
static const char *const batch_scenes[] = {NULL, "scenes/cornell_spiky.scene"};
static const int batch_modes[] = {SPM_MODE_ML,    SPM_MODE_MLC,  SPM_MODE_REF,
                                  SPM_MODE_TRUTH, SPM_MODE_HERO, SPM_MODE_RGB};

/* rel: a scene file under the data root, or NULL for the default scene. */
static inline int batch_scene_open(cl_test_scene *s, const char *rel, int w, int h)
{
    if (!rel)
        return cl_test_scene_open(s, w, h);
    char path[1024];
    spm_error err;
    spm_pretest_opts po;
    spm_quiet_warnings = 1;
    spm_pretest_defaults(&po);
    memset(s, 0, sizeof *s);
    if (spm_scene_load(spm_data_path(rel, path, sizeof path), &s->scene, &err)) {
        printf("%s: %s\n", rel, err.msg);
        return 1;
    }
    s->scene.width = w;
    s->scene.height = h;
    if (spm_geometry_build(&s->scene, &s->geom, &err) ||
        spm_tables_build(&s->scene, &po, &s->tables, &err)) {
        printf("%s set-up: %s\n", rel, err.msg);
        return 1;
    }
    return 0;
}

/* Levels with any path in them. */
static inline int batch_levels_used(const spm_pass_stats *st)
{
    int n = 0;
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        n += st->level_paths[l][0] + st->level_paths[l][1] + st->level_paths[l][2] > 0;
    return n;
}

static inline void batch_check_same_stats(const spm_pass_stats *a, const spm_pass_stats *b,
                                          const char *what)
{
    CHECK(a->paths == b->paths && a->truncated == b->truncated && a->nonfinite == b->nonfinite,
          "%s: paths %llu/%llu truncated %llu/%llu non-finite %llu/%llu", what,
          (unsigned long long)a->paths, (unsigned long long)b->paths,
          (unsigned long long)a->truncated, (unsigned long long)b->truncated,
          (unsigned long long)a->nonfinite, (unsigned long long)b->nonfinite);
    CHECK(memcmp(a->level_paths, b->level_paths, sizeof a->level_paths) == 0,
          "%s: paths per level differ", what);
}
#endif
