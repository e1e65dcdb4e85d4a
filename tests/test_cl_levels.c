/* The level feeler path by path, on both backends, against the rule read
 * back from each path's own record (refcpu.h "Level feeler order"): the
 * finest level among the start level and, in order, the first hit's
 * emission (k = 1), each vertex's reflectance (k = its occurrences on the
 * path so far) and light sample's emission (k = 1), and the background
 * (k = 1), each lowering the level only when strictly finer and naming who
 * did. On scenes whose colours need different levels (saturated_box: one
 * colour whose level gets finer the more often a path meets it;
 * cornell_spiky: smooth walls under a spiky light); every path of every
 * kind counted, and the scene must put paths on at least two levels (a
 * feeler stuck at one level would pass trivially). A kernel/reference
 * comparison alone cannot see a feeler bug both share; this rule can
 * (tools/mutants.txt feeler-coarser-*). */
#include "cl_testlib.h"
#include "render_plan.h"
#include "testutil.h"

#define W 24
#define H 24
#define SPP 4
#define SEED 5u

static void feel(const uint8_t *lvlk, spm_u32 c, int k, spm_u32 who, int *level, spm_u32 *setby)
{
    if (c == SPM_NONE)
        return;
    int l = lvlk[c * SPM_PRETEST_KMAX + (spm_u32)((k < SPM_PRETEST_KMAX ? k : SPM_PRETEST_KMAX) - 1)];
    if (l < *level)
        *level = l, *setby = who;
}

/* The level byte the rule gives for a Lambertian path record. */
static uint8_t expected_level(const spm_path *p, const uint8_t *lvlk, int start)
{
    int level = start;
    spm_u32 setby = SPM_SETBY_NONE;
    feel(lvlk, p->h.first_emit, 1, SPM_SETBY_EMITTER, &level, &setby);
    for (spm_u32 j = 0; j < p->h.nvert; j++) {
        spm_u32 refl = p->v[j].ids & 0xFFFFu, e = p->v[j].ids >> 16;
        int k = 0;
        for (spm_u32 i = 0; i <= j; i++)
            k += (p->v[i].ids & 0xFFFFu) == refl;
        feel(lvlk, refl, k, SPM_SETBY_REFLECTOR, &level, &setby);
        feel(lvlk, e, 1, SPM_SETBY_EMITTER, &level, &setby);
    }
    if (p->h.end == SPM_END_ESCAPED)
        feel(lvlk, p->h.bg, 1, SPM_SETBY_EMITTER, &level, &setby);
    return (uint8_t)((spm_u32)level | (setby << SPM_SETBY_SHIFT));
}

static void check_scene(const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/%s", SPM_SOURCE_DIR, name);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "%s loads", name);
        return;
    }
    for (int m = 0; m < s.tables.nmaterials; m++)
        CHECK(SPM_MAT_TAG(s.tables.materials[m]) == SPM_MAT_LAMBERT,
              "%s: material %d is not Lambertian (the rule here reads Lambertian records)", name, m);
    const uint8_t *lvlk = cl_test_lvlk(&s.tables, SPM_MODE_ML);
    spm_trace_params p = cl_test_params(&s, SEED, 0, SPP);
    int start = spm_plan_level_start(&s.geom, s.tables.materials, lvlk, &p);
    size_t n = (size_t)W * H * SPP;
    spm_path *gp = spm_xcalloc(n, sizeof *gp), *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *gl = spm_xcalloc(n, 1), *cl = spm_xcalloc(n, 1);
    spm_ref_trace(&s.geom, s.tables.materials, lvlk, &p, cp, cl);
    spm_cl_renderer *r;
    spm_error err;
    int have_cl = spm_cl_create(0, &s.geom, &s.tables, SPM_MODE_ML, SEED, &r, &err) == 0;
    CHECK(have_cl, "%s: spm_cl_create: %s", name, err.msg);
    if (have_cl) {
        CHECK(spm_cl_trace(r, 0, SPP, gp, gl, &err) == 0, "spm_cl_trace: %s", err.msg);
        spm_cl_destroy(r);
    }
    size_t ref_bad = 0, cl_bad = 0, cl_paths = 0, per_level[SPM_NUM_LEVELS] = {0};
    for (size_t i = 0; i < n; i++) {
        uint8_t want = expected_level(&cp[i], lvlk, start);
        ref_bad += cl[i] != want;
        per_level[cl[i] & SPM_LEVEL_MASK]++;
        if (have_cl && !cl_test_path_differs(&gp[i], &cp[i])) { /* the kernel's own record */
            cl_paths++;
            cl_bad += gl[i] != expected_level(&gp[i], lvlk, start);
        }
    }
    int levels_used = 0;
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        levels_used += per_level[l] > 0;
    printf("%s: start level %d, paths per level %zu %zu %zu %zu %zu; off the rule: reference %zu "
           "of %zu, kernel %zu of %zu\n", name, start, per_level[0], per_level[1], per_level[2],
           per_level[3], per_level[4], ref_bad, n, cl_bad, cl_paths);
    CHECK(ref_bad == 0, "%s: %zu reference paths off the feeler's rule", name, ref_bad);
    CHECK(cl_bad == 0, "%s: %zu kernel paths off the feeler's rule", name, cl_bad);
    CHECK(cl_paths > n * 9 / 10, "%s: only %zu of %zu kernel paths comparable", name, cl_paths, n);
    CHECK(levels_used >= 2, "%s: paths on %d level only", name, levels_used);
    free(gp), free(cp), free(gl), free(cl);
    cl_test_scene_close(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    check_scene("saturated_box.scene");
    check_scene("cornell_spiky.scene");
    TEST_END();
}
