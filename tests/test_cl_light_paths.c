/* The light integrator's kernels (kernels/lighttrace.cl spm_light_trace, the
 * shade kernels' _lt twins in kernels/shade_splats.clh) against the CPU
 * reference (host/cpu/refcpu_lighttrace.c, refcpu_shade.c
 * spm_ref_shade_splats), subpath by subpath and splat by splat, with the
 * same random streams (backend_cl.h's light subpath hooks):
 *  - the records: each subpath's vertices (colour words, splat weights, the
 *    types' vertex words), its end, the light's own splat weight, the pixel
 *    word of every slab (the pixel each splat lands in) and the level byte
 *    the feeler chose;
 *  - the splats: each side shades its own records with every slab's pixel
 *    word replaced by a tag of its own (subpath, slab), so a splat read back
 *    from the device's list (appended in any order) says where it came
 *    from; per tag, the XYZ and every spectral bin of the splat against the
 *    reference's.
 * Cases: the spiky Cornell box (diffuse; its area light in hero, a point
 * light in its place in ml, its subpaths at several levels), the prism
 * throwing its spectrum on a wall (a spot light; subpaths commit to a
 * wavelength in the glass), the fluorescent relay (light-flow order through
 * two dyes, a spot light) in ml; spectral output in
 * 5 nm bins throughout. Each case also checks that what it compares
 * happened (splats, committed subpaths, fluorescent vertices, levels). */
#include "cl_testlib.h"
#include "integrator_testlib.h"
#include "render_plan.h"
#include "testutil.h"

#define SEED 7u
#define SLABS (SPM_MAX_DEPTH + 1)
#define TAG0 0x10000u /* tags start above any pixel of these images */
/* as test_cl_trace: a subpath may diverge only where a few ulps of cos/sin
 * move a ray across an edge or a draw across a branch; a record whose weight
 * or vertex word is beyond CL_TEST_WEIGHT_REL (cl_testlib.h) counts as one.
 * Measured: 0 of the 21 504 subpaths diverge; the worst record word 7.2e-5
 * relative, a grazing cosine (0.017, 1.2e-6 absolute) in the prism. */
#define MAX_DIVERGENT_FRACTION 1e-3
/* A splat is its record's weight (within CL_TEST_WEIGHT_REL of the
 * reference's) times the shade stage's product of factors, which the kernel
 * fuses and sums in another order (test_cl_shade: 4 + 2 log2(lanes) ulps;
 * test_cl_fluor: n/2 ulps more per fluorescent vertex, 2.4e-5 relative at
 * 400 lanes). Measured worst: 9.1e-6 relative (the point-lit box, from its
 * record weight's 9.0e-6 at a seventh vertex), 3e-7 in the prism, 2.1e-6
 * in the relay; bound: the weight's 1e-4. */
#define SPLAT_REL CL_TEST_WEIGHT_REL

typedef struct {
    const char *name, *scene;
    const char *const (*sub)[2]; /* lines replaced in the scene (nsub) */
    int nsub, mode, w, h, spp;
} lt_case;

/* a point light of a smooth spectrum in place of the F11 lamp, whose spikes
 * would set every subpath's level from its start, and a tall box of a
 * narrow-peaked colour: subpaths that meet it need a finer level */
static const char *const point_light[][2] = {
    {"quad light ", "light point 0.278 0.5 0.2795 white 0.05\n"},
    {"spectrum f11 ", "spectrum f11 file illuminant_F11.csv\n"
                      "spectrum peak inline 380 0.1 540 0.1 545 0.9 550 0.1 780 0.1 end\n"},
    {"material tall_box ", "material tall_box reflect peak\n"}};

/* one program each (a kernel build is most of a case's time) */
static const lt_case cases[] = {
    {"room area hero", "scenes/cornell_spiky.scene", NULL, 0, SPM_MODE_HERO, 24, 24, 8},
    {"room point ml", "scenes/cornell_spiky.scene", point_light, 3, SPM_MODE_ML, 24, 24, 8},
    {"prism ml", "scenes/prism_wall.scene", NULL, 0, SPM_MODE_ML, 64, 16, 8},
    {"relay ml", "tests/data/scenes/fluor_relay.scene", NULL, 0, SPM_MODE_ML, 16, 16, 16},
};

/* One side's subpaths: records, level bytes, pixel words (backend_cl.h's
 * layout), and the splats of its records shaded with tagged pixel words. */
typedef struct {
    spm_path *p;
    uint8_t *lv;
    spm_u32 *px;
    spm_splats sp;
    long *at; /* per tag - TAG0: the splat's index in sp (-1 none, -2 twice) */
} side;

static void side_init(side *s, size_t n, int ch)
{
    s->p = spm_xcalloc(n, sizeof *s->p);
    s->lv = spm_xcalloc(n, 1);
    s->px = spm_xcalloc(n * SLABS, sizeof *s->px);
    s->at = spm_xcalloc(n * SLABS, sizeof *s->at);
    spm_splats_init(&s->sp, ch);
}

static void side_free(side *s)
{
    free(s->p);
    free(s->lv);
    free(s->px);
    free(s->at);
    spm_splats_free(&s->sp);
}

/* s's pixel words with each splat's slab tagged */
static spm_u32 *tagged(const side *s, size_t n)
{
    spm_u32 *t = spm_xcalloc(n * SLABS, sizeof *t);
    for (size_t k = 0; k < n * SLABS; k++)
        t[k] = s->px[k] == SPM_NO_PIXEL ? SPM_NO_PIXEL : TAG0 + (spm_u32)k;
    return t;
}

/* s->at from the tags of s->sp; the splats whose tag is not one of n SLABS. */
static size_t index_splats(side *s, size_t n)
{
    size_t stray = 0;
    for (size_t k = 0; k < n * SLABS; k++)
        s->at[k] = -1;
    for (size_t i = 0; i < s->sp.n; i++) {
        spm_u32 t = s->sp.px[i];
        if (t < TAG0 || t - TAG0 >= n * SLABS) {
            stray++;
            continue;
        }
        long *a = &s->at[t - TAG0];
        *a = *a == -1 ? (long)i : -2;
    }
    return stray;
}

/* The reference's subpaths [0, n) of pass 0 and their splats. */
static void reference_side(const cl_test_scene *s, const spm_render_plan *pl,
                           const spm_trace_params *p, size_t n, side *c)
{
    spm_light_path *lp = spm_xcalloc(n, sizeof *lp);
    spm_ref_light_trace_range(&s->geom, s->tables.materials, pl->lvlk, (int)pl->start_level, p,
                              0, n, lp, c->lv);
    for (size_t i = 0; i < n; i++) {
        c->p[i] = lp[i].p;
        memcpy(&c->px[i * SLABS], lp[i].px, sizeof lp[i].px);
    }
    spm_u32 *t = tagged(c, n);
    for (size_t i = 0; i < n; i++)
        memcpy(lp[i].px, &t[i * SLABS], sizeof lp[i].px);
    spm_ref_shade_splats(pl->mode, pl->shade, pl->spec, pl->pix_ch, p, 0, lp, c->lv, n, &c->sp);
    free(t);
    free(lp);
}

/* The kernels' subpaths [0, n) of pass 0 and their splats; 1: they did not run. */
static int kernel_side(const spm_render_plan *pl, spm_u32 spp, size_t n, side *g)
{
    spm_cl_renderer *r;
    spm_error err;
    int rc = spm_cl_create_plan(0, pl, &r, &err);
    if (!rc) {
        rc = spm_cl_light_trace(r, 0, spp, 0, n, g->p, g->px, g->lv, &err);
        spm_u32 *t = rc ? NULL : tagged(g, n);
        rc = rc || spm_cl_light_shade(r, 0, spp, 0, n, g->p, t, g->lv, &g->sp, &err);
        free(t);
        spm_cl_destroy(r);
    }
    CHECK(rc == 0, "%s: the kernels: %s", pl->mode->name, err.msg);
    return rc;
}

static double rel(double a, double b)
{
    double m = fmax(fabs(a), fabs(b));
    return m > 0.0 ? fabs(a - b) / m : 0.0;
}

/* Record against record: 1 when a discrete word differs; *w the largest
 * relative difference of a weight (vertex words only when the plan's
 * records hold them). */
static int record_differs(const side *c, const side *g, size_t i, int ext, double *w)
{
    const spm_path *a = &c->p[i], *b = &g->p[i];
    *w = rel(a->h.first_emit_c, b->h.first_emit_c);
    if (a->h.nvert != b->h.nvert || a->h.end != b->h.end || a->h.first_emit != b->h.first_emit ||
        memcmp(&c->px[i * SLABS], &g->px[i * SLABS], SLABS * sizeof *c->px))
        return 1;
    for (spm_u32 j = 0; j < a->h.nvert; j++) {
        if (a->v[j].ids != b->v[j].ids || (ext && a->x[j].ids != b->x[j].ids))
            return 1;
        *w = fmax(*w, rel(a->v[j].c, b->v[j].c));
        if (ext)
            *w = fmax(*w, fmax(rel(a->x[j].light, b->x[j].light),
                               fmax(rel(a->x[j].lobe, b->x[j].lobe),
                                    rel(a->x[j].hit_c, b->x[j].hit_c))));
    }
    return 0;
}

/* The splat of tag k on both sides: 1 when one side has it and the other
 * not (or one has it twice); *w the largest difference of a component
 * relative to the largest of its group (XYZ, the bins). */
static int splat_differs(const side *c, const side *g, size_t k, int ch, double *w)
{
    long a = c->at[k], b = g->at[k];
    *w = 0.0;
    if (a == -1 && b == -1)
        return 0;
    if (a < 0 || b < 0)
        return 1;
    const float *u = &c->sp.v[(size_t)ch * (size_t)a], *v = &g->sp.v[(size_t)ch * (size_t)b];
    for (int grp = 0; grp < 2; grp++) {
        int lo = grp ? 3 : 0, hi = grp ? ch : 3;
        double m = 0.0;
        for (int q = lo; q < hi; q++)
            m = fmax(m, fmax(fabs(u[q]), fabs(v[q])));
        for (int q = lo; q < hi && m > 0.0; q++)
            *w = fmax(*w, fabs((double)u[q] - (double)v[q]) / m);
    }
    return 0;
}

/* What a case exercised, from the reference's records. */
typedef struct {
    size_t splats, light_splats, committed, fluor, levels;
} coverage;

static coverage covered(const cl_test_scene *s, const side *c, size_t n)
{
    coverage cv = {c->sp.n, 0, 0, 0, 0};
    int seen[SPM_LEVEL_MASK + 1] = {0};
    for (size_t i = 0; i < n; i++) {
        const spm_path *p = &c->p[i];
        cv.light_splats += c->px[i * SLABS] != SPM_NO_PIXEL;
        seen[c->lv[i] & SPM_LEVEL_MASK] = 1;
        int com = 0;
        for (spm_u32 j = 0; j < p->h.nvert; j++) {
            spm_u32 refl = p->v[j].ids & 0xFFFFu, splat = c->px[i * SLABS + j + 1] != SPM_NO_PIXEL;
            com |= SPM_VX_LAMBDA(p->x[j]) != SPM_NONE;
            cv.committed += com && splat;
            cv.fluor += splat && s->tables.nfluor && refl != SPM_NONE &&
                        refl >= (spm_u32)s->tables.fluor_first;
        }
    }
    for (int l = 0; l <= (int)SPM_LEVEL_MASK; l++)
        cv.levels += seen[l];
    return cv;
}

static void compare(const lt_case *k, const cl_test_scene *s, const spm_render_plan *pl,
                    side *c, side *g, size_t n)
{
    int ext = pl->vertex_bytes > sizeof(spm_vertex), ch = pl->pix_ch;
    size_t diverged = 0, level_diff = 0, splat_diff = 0, over = 0, compared = 0;
    double wrec = 0.0, wsplat = 0.0;
    size_t stray = index_splats(c, n) + index_splats(g, n);
    for (size_t i = 0; i < n; i++) {
        double w;
        if (record_differs(c, g, i, ext, &w) || !(w <= CL_TEST_WEIGHT_REL)) {
            diverged++;
            continue;
        }
        wrec = fmax(wrec, w);
        level_diff += c->lv[i] != g->lv[i];
        for (size_t sl = 0; sl < SLABS; sl++) {
            size_t t = i * SLABS + sl;
            int d = splat_differs(c, g, t, ch, &w);
            splat_diff += d;
            compared += !d && c->at[t] >= 0;
            over += !d && !(w <= SPLAT_REL);
            wsplat = d ? wsplat : fmax(wsplat, w);
        }
    }
    coverage cv = covered(s, c, n);
    printf("%-15s %zu subpaths, %zu diverged; %zu splats (%zu of the light's own, %zu after a "
           "commit, %zu at a fluorescent vertex), %zu compared, %zu missing on one side, %zu "
           "beyond %g; %d channels; %zu levels, %zu level bytes differ; worst relative: record "
           "weight %.3g, splat %.3g\n",
           k->name, n, diverged, cv.splats, cv.light_splats, cv.committed, cv.fluor, compared,
           splat_diff, over, SPLAT_REL, ch, cv.levels, level_diff, wrec, wsplat);
    CHECK(cv.splats >= n / 4 && compared >= cv.splats / 2, "%s: %zu splats, %zu compared",
          k->name, cv.splats, compared);
    CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%s: %zu of %zu subpaths "
          "diverged", k->name, diverged, n);
    CHECK(level_diff == 0, "%s: %zu equal records with other level bytes", k->name, level_diff);
    CHECK(splat_diff == 0 && stray == 0, "%s: %zu splats on one side only, %zu without a tag",
          k->name, splat_diff, stray);
    CHECK(over == 0, "%s: %zu splats beyond %g relative (worst %.3g)", k->name, over, SPLAT_REL,
          wsplat);
    /* what the case is there for */
    int area = 0, prism = strstr(k->scene, "prism") != NULL;
    for (int e = 0; e < s->geom.nemitters; e++)
        area |= s->geom.emitters[e].kind == SPM_LIGHT_AREA;
    CHECK(area ? cv.light_splats > n / 50 : cv.light_splats == 0,
          "%s: %zu splats of the light's own vertex (area lights: %d)", k->name, cv.light_splats,
          area);
    CHECK(!prism || cv.committed > cv.splats / 2, "%s: %zu splats after a commit", k->name,
          cv.committed);
    CHECK(!s->tables.nfluor || cv.fluor > cv.splats / 4, "%s: %zu splats at a fluorescent vertex",
          k->name, cv.fluor);
    CHECK(!pl->mode->levelled || k->sub == NULL || cv.levels >= 2, "%s: %zu levels", k->name, cv.levels);
}

static void run_case(const lt_case *k)
{
    char path[1024], var[64];
    const char *file = spm_data_path(k->scene, path, sizeof path);
    if (k->sub) {
        snprintf(var, sizeof var, "light_paths_%d.scene", (int)(k - cases));
        if (it_write_variant(file, var, k->sub, k->nsub))
            return;
        file = var;
    }
    cl_test_scene s;
    spm_render_plan pl;
    spm_error err;
    if (cl_test_scene_load(&s, file, k->w, k->h)) {
        CHECK(0, "%s: %s loads", k->name, file);
        return;
    }
    if (spm_render_plan_init(&pl, &s.geom, &s.tables, k->mode, SEED, &err) ||
        spm_render_plan_integrator(&pl, SPM_INTEGRATOR_LIGHT, &err) ||
        spm_render_plan_spectral(&pl, 5, &err)) {
        CHECK(0, "%s: plan: %s", k->name, err.msg);
        cl_test_scene_close(&s);
        return;
    }
    size_t n = pl.npix * (size_t)k->spp;
    spm_trace_params p = spm_plan_pass_params(&pl, 0, (spm_u32)k->spp);
    side c, g;
    side_init(&c, n, pl.pix_ch);
    side_init(&g, n, pl.pix_ch);
    reference_side(&s, &pl, &p, n, &c);
    if (!kernel_side(&pl, (spm_u32)k->spp, n, &g))
        compare(k, &s, &pl, &c, &g, n);
    side_free(&c);
    side_free(&g);
    spm_render_plan_free(&pl);
    cl_test_scene_close(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++)
        run_case(&cases[k]);
    TEST_END();
}
