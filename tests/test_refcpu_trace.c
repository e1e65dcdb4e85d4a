/* CPU reference trace stage: records keyed by (seed, pixel, sample), record
 * conventions, truncation, and the level feeler on hand-made level tables. */
#include "geomtest_scene.h"
#include "render_plan.h"
#include "testutil.h"

/* Bytes of a record that are defined: the head and nvert vertices. */
static int same_record(const spm_path *a, const spm_path *b)
{
    return memcmp(&a->h, &b->h, sizeof a->h) == 0 && a->h.nvert <= SPM_MAX_DEPTH &&
           memcmp(a->v, b->v, a->h.nvert * sizeof a->v[0]) == 0;
}

typedef struct {
    spm_scene s;
    spm_geometry g;
    spm_tables t;
} world;

/* Closed box of reflectance rho (colour 0) with an emitting patch (colour 1)
 * on the ceiling and a second wall colour (2) on the floor. */
static void world_box(world *w, double rho)
{
    ts_init(&w->s);
    int wall = ts_material(&w->s, ts_colour(&w->s, SPM_KIND_REFLECTANCE, rho), -1);
    int light = ts_material(&w->s, -1, ts_colour(&w->s, SPM_KIND_EMISSION, 5.0));
    ts_box(&w->s, wall, (float[]){-1, -1, -1}, (float[]){1, 1, 1}, 0);
    w->s.tris[0].material = w->s.tris[1].material =
        ts_material(&w->s, ts_colour(&w->s, SPM_KIND_REFLECTANCE, rho), -1);
    ts_quad(&w->s, light, (float[]){-0.3f, 0.99f, -0.3f}, (float[]){0.3f, 0.99f, -0.3f},
            (float[]){0.3f, 0.99f, 0.3f}, (float[]){-0.3f, 0.99f, 0.3f});
    memcpy(w->s.eye, (float[]){0, 0, -0.9f}, sizeof w->s.eye);
    memcpy(w->s.dir, (float[]){0, 0, 1}, sizeof w->s.dir);
    w->s.fov_deg = 90.0f;
    spm_error err;
    CHECK(spm_geometry_build(&w->s, &w->g, &err) == 0, "build: %s", err.msg);
    ts_tables(&w->s, &w->t);
}

static void world_free(world *w)
{
    spm_tables_free(&w->t);
    spm_geometry_free(&w->g);
    ts_free(&w->s);
}

static void trace(world *w, spm_u32 spp, spm_u32 first, spm_u32 seed, spm_path *paths,
                  uint8_t *levels)
{
    spm_trace_params p = ts_params(&w->s, &w->g, spp, seed);
    p.first_sample = first;
    spm_ref_trace(&w->g, w->t.materials, w->t.lvlk, &p, paths, levels);
}

static void test_keyed_rng(void)
{
    world w;
    world_box(&w, 0.7);
    enum { NPIX = 16, SPP = 4 };
    static spm_path a[NPIX * SPP], b[NPIX * SPP], c[NPIX * 2];
    uint8_t la[NPIX * SPP], lb[NPIX * SPP], lc[NPIX * 2];
    trace(&w, SPP, 0, 7u, a, la);
    trace(&w, SPP, 0, 7u, b, lb);
    int same = 1;
    for (int i = 0; i < NPIX * SPP; i++)
        same &= same_record(&a[i], &b[i]) && la[i] == lb[i];
    CHECK(same, "the same seed gives identical records and levels");
    /* a pass of 2 samples starting at sample 2 repeats samples 2, 3 */
    trace(&w, 2, 2, 7u, c, lc);
    same = 1;
    for (int px = 0; px < NPIX; px++)
        for (int k = 0; k < 2; k++)
            same &= same_record(&c[px * 2 + k], &a[px * SPP + 2 + k]);
    CHECK(same, "a path depends on (seed, pixel, sample), not on the pass layout");
    trace(&w, SPP, 0, 8u, b, lb);
    int differ = 0, bounced = 0;
    for (int i = 0; i < NPIX * SPP; i++) {
        differ += !same_record(&a[i], &b[i]);
        bounced += a[i].h.nvert > 1;
    }
    CHECK(differ > NPIX * SPP * 9 / 10, "another seed, other paths: %d of %d differ", differ,
          NPIX * SPP);
    CHECK(bounced > 0, "some paths bounce");
    world_free(&w);
}

/* Conventions every record keeps (refcpu.h). */
static void test_record_conventions(void)
{
    world w;
    world_box(&w, 0.7);
    enum { N = 16 * 64 };
    static spm_path p[N];
    static uint8_t lv[N];
    trace(&w, 64, 0, 3u, p, lv);
    int ok = 1, lit = 0, first = 0;
    for (int i = 0; i < N; i++) {
        const spm_path_head *h = &p[i].h;
        ok &= h->end == SPM_END_ABSORBED && h->nvert >= 1; /* closed box: nothing escapes */
        ok &= h->bg == SPM_NONE && h->bg_c == 0.0f;
        ok &= (h->first_emit == SPM_NONE) == (h->first_emit_c == 0.0f);
        if (h->first_emit != SPM_NONE) /* the light seen directly: its colour, weight 1 */
            ok &= h->first_emit == 1u && h->first_emit_c == 1.0f &&
                  (p[i].v[0].ids & 0xFFFFu) == SPM_NONE;
        first += h->first_emit != SPM_NONE;
        for (spm_u32 j = 0; j < h->nvert && j < SPM_MAX_DEPTH; j++) {
            spm_u32 e = p[i].v[j].ids >> 16, r = p[i].v[j].ids & 0xFFFFu;
            ok &= (e == SPM_NONE) == (p[i].v[j].c == 0.0f) && p[i].v[j].c >= 0.0f;
            ok &= e == SPM_NONE || e == 1u; /* the light's emission colour */
            ok &= r == 0u || r == 2u || r == SPM_NONE;
            lit += e != SPM_NONE;
        }
    }
    CHECK(ok, "record conventions hold");
    CHECK(lit > N / 4, "next-event estimation finds the light: %d", lit);
    CHECK(first > 0 && first < N / 4, "the camera sees the light in a corner: %d", first);
    world_free(&w);
}

/* Reflectance 1 everywhere: Russian roulette never ends a path, every
 * record fills up and is truncated. Reflectance 0.5: none reaches 64 (the
 * chance is 2^-63 per path). */
static void test_truncation(void)
{
    world w;
    world_box(&w, 1.0);
    enum { N = 16 * 8 };
    static spm_path p[N];
    static uint8_t lv[N];
    trace(&w, 8, 0, 5u, p, lv);
    /* the light patch is black: paths that hit it end there, and a full
     * record whose last vertex is on it ended there, not by truncation */
    int trunc = 0, full = 0, on_light = 0;
    for (int i = 0; i < N; i++) {
        int light = (p[i].v[p[i].h.nvert - 1].ids & 0xFFFFu) == SPM_NONE;
        trunc += p[i].h.end == SPM_END_TRUNCATED;
        full += p[i].h.nvert == SPM_MAX_DEPTH && !light;
        on_light += light;
    }
    CHECK(trunc == full && trunc + on_light == N && trunc > N / 10,
          "truncated %d, full (not ending on the light) %d, ended on the black light %d of %d",
          trunc, full, on_light, N);
    world_free(&w);
    world_box(&w, 0.5);
    trace(&w, 8, 0, 5u, p, lv);
    trunc = 0;
    for (int i = 0; i < N; i++)
        trunc += p[i].h.end == SPM_END_TRUNCATED;
    CHECK(trunc == 0, "reflectance 0.5: no truncation (%d)", trunc);
    world_free(&w);
}

/* Levels by hand: colour 0 (walls) needs level 2 once or twice, 1 three or
 * four times, 0 from five; colour 2 (floor) always 2; the light (1) 1. */
#define KM SPM_PRETEST_KMAX
static void set_lvlk(uint8_t *lvlk, int light_level)
{
    for (int k = 0; k < KM; k++) {
        lvlk[0 * KM + k] = (uint8_t)(k < 2 ? 2 : k < 4 ? 1 : 0);
        lvlk[1 * KM + k] = (uint8_t)light_level;
        lvlk[2 * KM + k] = 2;
    }
}

static void test_level_feeler(void)
{
    world w;
    world_box(&w, 0.8);
    set_lvlk(w.t.lvlk, 2);
    spm_trace_params p = ts_params(&w.s, &w.g, 32, 9u);
    CHECK(spm_plan_level_start(&w.g, w.t.materials, w.t.lvlk, &p) == 2, "start: coarsest in use");
    w.t.lvlk[2 * KM] = 3;
    CHECK(spm_plan_level_start(&w.g, w.t.materials, w.t.lvlk, &p) == 3, "start follows the table");
    w.t.lvlk[2 * KM] = 2;

    enum { N = 16 * 32 };
    static spm_path pa[N];
    static uint8_t lv[N];
    spm_ref_trace(&w.g, w.t.materials, w.t.lvlk, &p, pa, lv);
    /* expected from the record: the walls' level at their count on the path */
    int ok = 1, seen[3] = {0};
    for (int i = 0; i < N; i++) {
        int k = 0;
        for (spm_u32 j = 0; j < pa[i].h.nvert; j++)
            k += (pa[i].v[j].ids & 0xFFFFu) == 0u;
        int level = k == 0 ? 2 : w.t.lvlk[(k < KM ? k : KM) - 1];
        spm_u32 by = level < 2 ? SPM_SETBY_REFLECTOR : SPM_SETBY_NONE;
        ok &= lv[i] == (uint8_t)(level | (by << SPM_SETBY_SHIFT));
        seen[level]++;
    }
    CHECK(ok, "level = the walls' level at their occurrence count, set by a reflector");
    CHECK(seen[0] && seen[1] && seen[2], "all three levels occur: %d %d %d", seen[0], seen[1],
          seen[2]);

    /* a light needing level 1: paths that record it go to 1 at least, set by
     * the emitter unless the walls got there first (path order) */
    set_lvlk(w.t.lvlk, 1);
    spm_ref_trace(&w.g, w.t.materials, w.t.lvlk, &p, pa, lv);
    ok = 1;
    int by_emitter = 0;
    for (int i = 0; i < N; i++) {
        int k = 0, lit = 0, level = 2;
        spm_u32 by = SPM_SETBY_NONE;
        if (pa[i].h.first_emit == 1u)
            level = 1, by = SPM_SETBY_EMITTER;
        for (spm_u32 j = 0; j < pa[i].h.nvert; j++) {
            spm_u32 r = pa[i].v[j].ids & 0xFFFFu;
            if (r == 0u && w.t.lvlk[(++k < KM ? k : KM) - 1] < level)
                level = w.t.lvlk[(k < KM ? k : KM) - 1], by = SPM_SETBY_REFLECTOR;
            if ((pa[i].v[j].ids >> 16) == 1u && 1 < level)
                level = 1, by = SPM_SETBY_EMITTER;
            lit |= (pa[i].v[j].ids >> 16) == 1u;
        }
        ok &= lv[i] == (uint8_t)(level | (by << SPM_SETBY_SHIFT));
        by_emitter += lit && by == SPM_SETBY_EMITTER;
    }
    CHECK(ok, "emitter levels count once per path, in path order");
    CHECK(by_emitter > 0, "some paths' level set by the light: %d", by_emitter);

    /* without a table (modes that ignore levels) every byte is 0 */
    spm_ref_trace(&w.g, w.t.materials, NULL, &p, pa, lv);
    int zero = 1;
    for (int i = 0; i < N; i++)
        zero &= lv[i] == 0;
    CHECK(zero, "no table: level bytes 0");
    world_free(&w);
}

int main(void)
{
    spm_quiet_warnings = 1;
    test_keyed_rng();
    test_record_conventions();
    test_truncation();
    test_level_feeler();
    TEST_END();
}
