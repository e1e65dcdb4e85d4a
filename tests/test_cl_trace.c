/* The trace kernel against the CPU reference (same scene, seed, samples):
 * per path the record's ids, counts and ending must be equal, its weights
 * close, its level byte equal; and the records do not depend on the mode.
 * Also on MiniLight's Cornell box lit by a sun 1.5e11 away, and on the
 * textured box (scenes/textured.scene), whose vertices record colours the
 * texture lookup picks (kernels/texture.clh, host/cpu/refcpu_texture.c),
 * on it with coated textured materials, and on a textured room with glass
 * and gold spheres that widen the ray cone. */
#include "cl_testlib.h"
#include "testutil.h"

#define W 32
#define H 32
#define SPP 8
#define SEED 7u

/* Paths that diverge (cl_test_path_differs in cl_testlib.h) must stay rare:
 * with at most a few ulps of direction error per bounce, a flip needs a ray
 * within ~1e-6 of an edge in a scene of a few dozen triangles; 1 in 1000
 * paths is a generous ceiling (measured: see the printed count), while a
 * real transport mismatch diverges on most paths. */
#define MAX_DIVERGENT_FRACTION 1e-3
/* Smooth glass spheres of 528 triangles refract those ulps across many more
 * edges: 41 of 8192 paths (0.005) of textured_glass.scene diverge, as many
 * with the ray cone's widening switched off on both sides; a mismatch in the
 * cone's arithmetic moves the level of many lookups past a bounce (the
 * kernel without its curvature term: 290 of 8192; without its roughness
 * term: 939 and 1096). */
#define MAX_DIVERGENT_FRACTION_GLASS 1e-2

static void compare_pass_within(const cl_test_scene *s, spm_cl_renderer *r, int mode,
                                spm_u32 first, double max_fraction)
{
    size_t n = (size_t)W * H * SPP;
    spm_path *gp = spm_xcalloc(n, sizeof *gp), *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *gl = spm_xcalloc(n, 1), *cl = spm_xcalloc(n, 1);
    spm_error err;
    int rc = spm_cl_trace(r, first, SPP, gp, gl, &err);
    CHECK(rc == 0, "spm_cl_trace: %s", err.msg);
    spm_trace_params p = cl_test_params(s, SEED, first, SPP);
    spm_ref_trace(&s->geom, s->tables.materials, cl_test_lvlk(&s->tables, mode), &p, cp, cl);
    size_t diverged = 0, level_diff = 0, exact = 0, vertices = 0, escaped = 0, lit = 0;
    for (size_t i = 0; i < n; i++) {
        int d = cl_test_path_differs(&gp[i], &cp[i]);
        diverged += d;
        level_diff += !d && gl[i] != cl[i];
        exact += cl_test_path_hash(&gp[i]) == cl_test_path_hash(&cp[i]);
        vertices += cp[i].h.nvert;
        escaped += cp[i].h.end == SPM_END_ESCAPED;
        for (spm_u32 j = 0; j < cp[i].h.nvert; j++)
            lit += (cp[i].v[j].ids >> 16) != SPM_NONE;
    }
    printf("first sample %u: %zu paths, %zu vertices, %zu lit vertices, %zu escaped; "
           "%zu bit-identical records, %zu diverged (%.2g), %zu level bytes differ\n",
           first, n, vertices, lit, escaped, exact, diverged, (double)diverged / (double)n,
           level_diff);
    /* the scene must exercise the comparison: bounces, lights, escapes */
    CHECK(vertices > n && lit > n / 4, "too little transport to compare (%zu, %zu)", vertices, lit);
    CHECK((double)diverged <= max_fraction * (double)n, "%zu of %zu paths diverged", diverged, n);
    CHECK(level_diff == 0, "%zu paths with equal records have different level bytes", level_diff);
    free(gp);
    free(cp);
    free(gl);
    free(cl);
}

static void compare_pass(const cl_test_scene *s, spm_cl_renderer *r, int mode, spm_u32 first)
{
    compare_pass_within(s, r, mode, first, MAX_DIVERGENT_FRACTION);
}

/* Hash of the whole pass's records as the kernel writes them in `mode`. */
static uint64_t mode_records_hash(const cl_test_scene *s, int mode)
{
    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, &s->geom, &s->tables, mode, SEED, &r, &err)) {
        CHECK(0, "spm_cl_create(mode %d): %s", mode, err.msg);
        return 0;
    }
    size_t n = (size_t)W * H * 2;
    spm_path *gp = spm_xcalloc(n, sizeof *gp);
    uint8_t *gl = spm_xcalloc(n, 1);
    uint64_t h = 0;
    if (spm_cl_trace(r, 0, 2, gp, gl, &err) == 0)
        for (size_t i = 0; i < n; i++)
            h = h * 31u + cl_test_path_hash(&gp[i]);
    else
        CHECK(0, "spm_cl_trace(mode %d): %s", mode, err.msg);
    free(gp);
    free(gl);
    spm_cl_destroy(r);
    return h;
}

/* The kernel against the reference in ml on the scene file `rel` (under the
 * source tree), loaded into *s, which the caller closes, at most `frac` of
 * the paths diverging: 0 if it loaded. */
static int compare_file_within(cl_test_scene *s, const char *rel, const char *what, double frac)
{
    char path[1024];
    spm_cl_renderer *r;
    spm_error err;
    snprintf(path, sizeof path, "%s/%s", SPM_SOURCE_DIR, rel);
    if (cl_test_scene_load(s, path, W, H) != 0) {
        CHECK(0, "the %s scene loads", what);
        return 1;
    }
    if (spm_cl_create(0, &s->geom, &s->tables, SPM_MODE_ML, SEED, &r, &err) == 0) {
        compare_pass_within(s, r, SPM_MODE_ML, 0, frac);
        spm_cl_destroy(r);
    } else {
        CHECK(0, "spm_cl_create (%s): %s", what, err.msg);
    }
    return 0;
}

static int compare_file(cl_test_scene *s, const char *rel, const char *what)
{
    return compare_file_within(s, rel, what, MAX_DIVERGENT_FRACTION);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    cl_test_scene s;
    if (cl_test_scene_open(&s, W, H))
        return 1;
    spm_cl_renderer *r;
    spm_error err;
    int modes[] = {SPM_MODE_ML, SPM_MODE_MLC};
    for (int m = 0; m < 2; m++) {
        if (spm_cl_create(0, &s.geom, &s.tables, modes[m], SEED, &r, &err)) {
            CHECK(0, "spm_cl_create: %s", err.msg);
            continue;
        }
        compare_pass(&s, r, modes[m], 0);
        if (m == 0)
            compare_pass(&s, r, modes[m], SPP); /* a later pass: samples keyed by index */
        spm_cl_destroy(r);
    }

    /* every mode shades the same records */
    uint64_t h0 = mode_records_hash(&s, SPM_MODE_REF);
    int others[] = {SPM_MODE_ML, SPM_MODE_MLC, SPM_MODE_RGB, SPM_MODE_HERO, SPM_MODE_TRUTH};
    for (int i = 0; i < 5; i++) {
        uint64_t h = mode_records_hash(&s, others[i]);
        CHECK(h == h0, "records in mode %d differ from ref's", others[i]);
    }
    cl_test_scene_close(&s);

    /* coordinates up to 1e12 (scene_build.h): the sun's rays in float */
    compare_file(&s, "tests/data/scenes/cornellbox_sun.ml.txt", "far-sun");
    cl_test_scene_close(&s);

    /* textures: the records' colour ids are the lookups' picks, which must be
     * the reference's; and they must be picks, many colours beyond the
     * materials' own */
    if (compare_file(&s, "scenes/textured.scene", "textured") == 0) {
        CHECK(s.geom.ntex > 0 && s.geom.uvs, "the textured scene has texture words");
        size_t n = (size_t)W * H * SPP;
        spm_path *cp = spm_xcalloc(n, sizeof *cp);
        uint8_t *cl = spm_xcalloc(n, 1), *seen = spm_xcalloc(SPM_NONE, 1);
        spm_trace_params p = cl_test_params(&s, SEED, 0, SPP);
        spm_ref_trace(&s.geom, s.tables.materials, cl_test_lvlk(&s.tables, SPM_MODE_ML), &p, cp, cl);
        int distinct = 0;
        for (size_t i = 0; i < n; i++)
            for (spm_u32 j = 0; j < cp[i].h.nvert; j++) {
                spm_u32 c = cp[i].v[j].ids & 0xFFFFu;
                distinct += c != SPM_NONE && !seen[c];
                seen[c] = 1;
            }
        printf("textured: %d distinct reflectance colours recorded, %d materials\n", distinct,
               s.tables.nmaterials);
        CHECK(distinct > 2 * s.tables.nmaterials, "the textures picked %d colours", distinct);
        free(cp);
        free(cl);
        free(seen);
    }
    cl_test_scene_close(&s);

    /* coated materials on textures: the specular lobe records white, the
     * diffuse one a pick from the material's palette of effective colours */
    if (compare_file(&s, "tests/data/scenes/textured_coated.scene", "textured coated") == 0)
        CHECK(s.geom.ntex > 0 && s.geom.tex[SPM_TEXD_NPAL] == 3,
              "the coated textures have a palette each (%u palettes)",
              s.geom.ntex ? s.geom.tex[SPM_TEXD_NPAL] : 0u);
    cl_test_scene_close(&s);

    /* the ray cone widened past curved mirrors and through smooth and rough
     * glass before the textures' lookups (texture.clh tex_cone_bounce) */
    compare_file_within(&s, "tests/data/scenes/textured_glass.scene", "textured glass",
                        MAX_DIVERGENT_FRACTION_GLASS);
    cl_test_scene_close(&s);

    /* emitters of unequal power: the kernel picks and weighs them through the
     * table (spm_emitter) as the reference does */
    if (compare_file(&s, "tests/data/scenes/cornell_two_lights.scene", "two-light") == 0)
        CHECK(s.geom.emit_power == 1, "two lights of unequal power are picked by power");
    cl_test_scene_close(&s);
    TEST_END();
}
