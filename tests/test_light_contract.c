/* The light contract (host/cpu/refcpu_lights.h), each call against an
 * estimator of its own:
 *  - chi-squared: light_sample's directions from a point on a floor under two
 *    area lights of other power, a blocker and a point light that shares the
 *    selection, against the density the contract gives a direction
 *    (light_pdf_hit of the emitter a ray along it meets, 0 when the blocker
 *    is met first), and each sample's claimed density against it; the point
 *    light's samples are deltas, outside the histogram (tests/chi2_testlib.h);
 *    by the power table and through the light tree (the pmf light_pdf_hit
 *    reads then the walk's from the point);
 *  - a one-vertex light tracer: rays from light_sample_emission (a light by
 *    the selection's pmf, then its point and direction with their
 *    densities) onto a diffuse floor, binned by the pixel that sees where
 *    they land; the floor's radiance rho E / pi per pixel against the path
 *    tracer's render of the same floor (spm_ref_trace, next-event
 *    estimation), within their joint standard error; a spot among the
 *    lights, its falloff written here;
 *  - chi-squared of the spot's emission directions against the uniform
 *    cone, of the distant light's emission origins against the uniform
 *    disc of the scene's bounding sphere, and of a two-sided area light's
 *    emission directions against |cos| / (2 pi) over both faces. */
#include <string.h>
#include "chi2_testlib.h"
#include "geomtest_scene.h"
#include "geometry.h"
#include "light_tree.h"
#include "materials.h"
#include "refcpu_lights.h"
#include "spm_rng.h"

#define ALPHA 0.01
#define RHO 0.5
#define POINT_I 0.3

/* the area lights: quads at height h over [x0, x1] x [z0, z1], facing down,
 * radiance e */
static const struct {
    double h, x0, x1, z0, z1, e;
} lights[2] = {{1.0, -0.8, -0.2, -0.3, 0.3, 1.0}, {0.6, 0.3, 0.7, -0.2, 0.4, 4.0}};
static const float point_pos[3] = {0.1f, 0.8f, -0.1f};
/* the spot: at spot_pos aimed along spot_axis (unit), cone 45 degrees (on
 * a boundary of chi2_testlib's theta cells, whose midpoint rule would miss
 * 0.2 % of the density at an edge inside one), its falloff from 30,
 * intensity SPOT_I */
static const float spot_pos[3] = {-0.3f, 0.7f, 0.2f};
static const double spot_axis[3] = {0.26726124191242440, -0.80178372573727319,
                                    -0.53452248382484879}; /* (1, -3, -2) / sqrt(14) */
#define SPOT_I 0.4
#define SPOT_CONE (45.0 * M_PI / 180.0)
#define SPOT_BEAM (30.0 * M_PI / 180.0)

/* Mitsuba 3's spot falloff, written here from its definition: 1 to the
 * beam angle, linear in the angle to 0 at the cone's edge */
static double spot_falloff(const float d[3])
{
    double c = d[0] * spot_axis[0] + d[1] * spot_axis[1] + d[2] * spot_axis[2];
    double th = acos(fmin(1.0, fmax(-1.0, c)));
    return th <= SPOT_BEAM ? 1.0 : th < SPOT_CONE ? (SPOT_CONE - th) / (SPOT_CONE - SPOT_BEAM) : 0.0;
}

/* The floor y = 0, the lights, a point light of intensity POINT_I and a
 * spot (colours Y 1) and, with blocker, a black quad under the second
 * light. */
static int build(spm_scene *s, spm_geometry *g, spm_tables *t, int blocker, float eye_y)
{
    static spm_scene_light pl[2];
    ts_init(s);
    s->width = s->height = 6;
    s->fov_deg = 100.0f;
    memcpy(s->eye, (float[]){0.0f, eye_y, 0.0f}, sizeof s->eye);
    memcpy(s->dir, (float[]){0.0f, -1.0f, 0.0f}, sizeof s->dir);
    int floor_m = ts_material(s, ts_colour(s, SPM_KIND_REFLECTANCE, RHO), -1);
    ts_quad(s, floor_m, (float[]){-50, 0, -50}, (float[]){-50, 0, 50}, (float[]){50, 0, 50},
            (float[]){50, 0, -50});
    for (int k = 0; k < 2; k++) {
        int m = ts_material(s, -1, ts_colour(s, SPM_KIND_EMISSION, lights[k].e));
        float h = (float)lights[k].h, x0 = (float)lights[k].x0, x1 = (float)lights[k].x1;
        float z0 = (float)lights[k].z0, z1 = (float)lights[k].z1;
        ts_quad(s, m, (float[]){x0, h, z0}, (float[]){x1, h, z0}, (float[]){x1, h, z1},
                (float[]){x0, h, z1});
    }
    if (blocker)
        ts_quad(s, ts_material(s, -1, -1), (float[]){0.1f, 0.3f, 0.0f},
                (float[]){0.35f, 0.3f, 0.0f}, (float[]){0.35f, 0.3f, 0.3f},
                (float[]){0.1f, 0.3f, 0.3f});
    int white = ts_colour(s, SPM_KIND_EMISSION, 1.0);
    pl[0] = (spm_scene_light){.kind = SPM_LIGHT_POINT, .colour = white};
    memcpy(&pl[0].p[SPM_LIGHT_P_POS], point_pos, sizeof point_pos);
    pl[0].p[SPM_LIGHT_P_SCALE] = (float)POINT_I;
    pl[1] = (spm_scene_light){.kind = SPM_LIGHT_SPOT, .colour = white};
    memcpy(&pl[1].p[SPM_LIGHT_P_POS], spot_pos, sizeof spot_pos);
    for (int i = 0; i < 3; i++)
        pl[1].p[SPM_LIGHT_P_DIR + i] = (float)spot_axis[i];
    pl[1].p[SPM_LIGHT_P_A] = (float)SPOT_CONE;
    pl[1].p[SPM_LIGHT_P_B] = (float)SPOT_BEAM;
    pl[1].p[SPM_LIGHT_P_C] = (float)cos(SPOT_CONE);
    pl[1].p[SPM_LIGHT_P_SCALE] = (float)SPOT_I;
    s->lights = pl;
    s->nlights = 2;
    spm_error err;
    if (spm_geometry_build(s, g, &err)) {
        CHECK(0, "build: %s", err.msg);
        return 1;
    }
    ts_tables(s, t);
    return 0;
}

static void scene_free(spm_scene *s, spm_geometry *g, spm_tables *t)
{
    s->lights = NULL; /* static */
    spm_tables_free(t);
    spm_geometry_free(g);
    ts_free(s);
}

/* ---- chi-squared of light_sample ------------------------------------------ */

typedef struct {
    const spm_geometry *g;
    const spm_material *mats;
    float x[3];
    spm_u32 hit;
    spm_ref_hit h;
    spm_u32 next; /* the sample index of the next draw */
} lsample_ctx;

/* a direction in the floor's frame (z along +y) and back */
static void to_world(const double l[3], float w[3])
{
    w[0] = (float)l[0], w[1] = (float)l[2], w[2] = (float)l[1];
}

static int ls_sample(void *ctx, const double wo[3], const double u[3], double wi[3], double *pdf,
                     double *w)
{
    (void)wo, (void)u; /* the contract draws its own numbers, by key */
    lsample_ctx *c = ctx;
    spm_ref_key k = {3u, 0u, c->next++};
    spm_ref_lsample ls;
    if (!spm_ref_light_sample(c->g, c->mats, &k, SPM_DIM_VERTEX(0), c->x, c->hit, &c->h, &ls) ||
        ls.delta)
        return 0;
    wi[0] = ls.wi[0], wi[1] = ls.wi[2], wi[2] = ls.wi[1];
    *pdf = ls.pdf;
    *w = 0.0;
    return 1;
}

/* the contract's density of a direction: light_pdf_hit of the emitter a ray
 * along it meets first (0: none, or the blocker) */
static double ls_pdf(void *ctx, const double wo[3], const double wl[3])
{
    (void)wo;
    const lsample_ctx *c = ctx;
    float d[3], t;
    to_world(wl, d);
    int e = spm_bvh_intersect(c->g, c->x, d, c->hit, &t);
    if (e < 0 || !(c->g->light_pdf[e] > 0.0f))
        return 0.0;
    const float *n = c->g->tris[e].n;
    float ce = -(d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
    return ce > 0.0f ? spm_ref_light_pdf_hit(c->g, c->x, c->hit, (spm_u32)e, t, ce) : 0.0;
}

static void chi2_light_sample(double alpha_test, int tree)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    if (build(&s, &g, &t, 1, 0.5f))
        return;
    if (tree) /* the selection and light_pdf_hit's pmf through the light tree */
        spm_light_tree_attach(&g, t.materials);
    lsample_ctx c;
    memset(&c, 0, sizeof c);
    c.g = &g, c.mats = t.materials;
    memcpy(c.x, (float[]){0.05f, 0.0f, 0.1f}, sizeof c.x);
    float up[3] = {0.0f, 1.0f, 0.0f}, down[3] = {0.0f, -1.0f, 0.0f}, tt;
    c.hit = (spm_u32)spm_bvh_intersect(&g, (float[]){c.x[0], -1.0f, c.x[2]}, up, 0xFFFFFFFFu, &tt);
    memcpy(c.h.d, down, sizeof down);
    memcpy(c.h.ng, g.tris[c.hit].n, sizeof c.h.ng);
    memcpy(c.h.n, up, sizeof up);
    double wo[3] = {0.0, 0.0, 1.0};
    chi2_sampler smp = {tree ? "light_sample (area lights, tree)" : "light_sample (area lights)",
                        &c, ls_sample, ls_pdf, NULL};
    chi2_run(&smp, wo, 400000L, 0, alpha_test);
    scene_free(&s, &g, &t);
}

/* ---- a one-vertex light tracer against the path tracer -------------------- */

#define N_LT 4000000L
#define LT_SPP 2048u
#define EYE_Y 0.5f

/* the pixel (camera looking straight down from eye, spm_camera) that sees
 * floor point y, or -1: the floor point is eye + eye_y tan_half (right cx +
 * up cy), linear in (cx, cy), so a pixel's jittered rays cover its
 * footprint uniformly */
static int pixel_of(const spm_camera *cam, const float y[3])
{
    double v[3] = {y[0] - cam->eye[0], y[1] - cam->eye[1], y[2] - cam->eye[2]}, cx = 0, cy = 0;
    for (int i = 0; i < 3; i++)
        cx += v[i] * cam->right[i], cy += v[i] * cam->up[i];
    cx /= cam->eye[1] * cam->tan_half;
    cy /= cam->eye[1] * cam->tan_half;
    int px = (int)floor((cx + 1.0) / 2.0 * cam->width), py = (int)floor((1.0 - cy) / 2.0 * cam->height);
    return px < 0 || py < 0 || px >= cam->width || py >= cam->height ? -1 : py * cam->width + px;
}

/* light tracer: per pixel the floor's radiance rho E / pi and its standard
 * error, E the flux landing in the pixel's footprint over its area */
static void light_trace(const spm_geometry *g, const spm_tables *t, double *l, double *se)
{
    int np = g->cam.width * g->cam.height;
    double *s1 = calloc((size_t)np, sizeof *s1), *s2 = calloc((size_t)np, sizeof *s2);
    double foot = 2.0 * g->cam.eye[1] * g->cam.tan_half / g->cam.width;
    uint64_t seed = 99;
    for (long r = 0; r < N_LT; r++) {
        spm_u32 u24 = (spm_u32)(chi2_u01(&seed) * SPM_EMIT_CDF_ONE);
        spm_u32 k = g->emit_power ? spm_emitter_search(g->emitters, (spm_u32)g->nemitters, u24)
                                  : u24 % (spm_u32)g->nemitters;
        const spm_emitter *e = &g->emitters[k];
        float u[4] = {(float)chi2_u01(&seed), (float)chi2_u01(&seed), (float)chi2_u01(&seed),
                      (float)chi2_u01(&seed)}, o[3], d[3], pp, pd, tt;
        spm_ref_light_sample_emission(g, k, u, o, d, &pp, &pd);
        if (!(pp > 0.0f && pd > 0.0f))
            continue;
        /* beta = Le |cos_o| / (pmf pdf_pos pdf_dir), Le's Y the colour's value */
        double le, cos_o = 1.0;
        if (e->kind == SPM_LIGHT_AREA) {
            const spm_tri *tr = &g->tris[e->tri];
            le = t->truth[t->materials[tr->material].emit * SPM_TRUTH_BINS];
            cos_o = fabs(d[0] * tr->n[0] + d[1] * tr->n[1] + d[2] * tr->n[2]);
        } else {
            le = t->truth[e->colour * SPM_TRUTH_BINS] * e->p[SPM_LIGHT_P_SCALE];
            le *= e->kind == SPM_LIGHT_SPOT ? spot_falloff(d) : 1.0;
        }
        double beta = le * cos_o / ((double)e->pdf * pp * pd);
        int hit = spm_bvh_intersect(g, o, d, e->tri, &tt);
        if (hit < 0 || t->materials[g->tris[hit].material].refl == SPM_NONE)
            continue; /* only the floor reflects */
        float y[3] = {o[0] + tt * d[0], o[1] + tt * d[1], o[2] + tt * d[2]};
        int px = pixel_of(&g->cam, y);
        if (px >= 0)
            s1[px] += beta, s2[px] += beta * beta;
    }
    for (int i = 0; i < np; i++) {
        double m = s1[i] / N_LT, v = fmax(0.0, s2[i] / N_LT - m * m) / (N_LT - 1);
        double k = RHO / M_PI / (foot * foot);
        l[i] = k * m, se[i] = k * sqrt(v);
    }
    free(s1), free(s2);
}

static void light_tracer(void)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    if (build(&s, &g, &t, 0, EYE_Y))
        return;
    int np = s.width * s.height;
    double *lt = calloc((size_t)np, sizeof *lt), *lse = calloc((size_t)np, sizeof *lse);
    light_trace(&g, &t, lt, lse);
    /* the path tracer: per pixel the mean Y of its paths and its standard error */
    spm_trace_params p = ts_params(&s, &g, LT_SPP, 5u);
    size_t n = (size_t)np * LT_SPP;
    spm_path *paths = malloc(n * sizeof *paths);
    uint8_t *levels = malloc(n);
    float *xyz = malloc(3 * n * sizeof *xyz);
    spm_ref_trace(&g, t.materials, t.lvlk, &p, paths, levels);
    spm_ref_shade(&t, SPM_MODE_REF, &p, 0, paths, levels, n, xyz);
    double worst = 0.0, sum_lt = 0.0, sum_pt = 0.0;
    int bad = 0;
    for (int px = 0; px < np; px++) {
        double s1 = 0.0, s2 = 0.0;
        for (size_t i = (size_t)px * LT_SPP; i < (size_t)(px + 1) * LT_SPP; i++)
            s1 += xyz[3 * i + 1], s2 += (double)xyz[3 * i + 1] * xyz[3 * i + 1];
        double m = s1 / LT_SPP, v = fmax(0.0, s2 / LT_SPP - m * m) / (LT_SPP - 1);
        double z = (lt[px] - m) / sqrt(lse[px] * lse[px] + v);
        worst = fmax(worst, fabs(z));
        bad += !(fabs(z) <= 4.5); /* two-sided 6.8e-6 per pixel: 2.4e-4 over 36 */
        sum_lt += lt[px], sum_pt += m;
    }
    printf("light tracer vs path tracer: %d pixels, mean radiance %.5f vs %.5f (%.2f %%), worst "
           "|z| %.2f\n", np, sum_lt / np, sum_pt / np, 100.0 * (sum_lt / sum_pt - 1.0), worst);
    CHECK(sum_pt > 0.0 && sum_lt > 0.0, "nothing lit (%g, %g)", sum_lt, sum_pt);
    CHECK(bad == 0, "%d pixels differ beyond 4.5 standard errors (worst %.2f)", bad, worst);
    free(paths), free(levels), free(xyz), free(lt), free(lse);
    scene_free(&s, &g, &t);
}

/* ---- chi-squared of the spot's emission directions ------------------------ */

typedef struct {
    const spm_geometry *g;
    spm_u32 k;       /* the spot's entry in the selection */
    double b1[3], b2[3]; /* a frame about its axis */
} spot_ctx;

static int spot_sample(void *ctx, const double wo[3], const double u[3], double wi[3],
                       double *pdf, double *w)
{
    (void)wo;
    const spot_ctx *c = ctx;
    float uf[4] = {0.5f, 0.5f, (float)u[0], (float)u[1]}, o[3], d[3], pp, pd;
    spm_ref_light_sample_emission(c->g, c->k, uf, o, d, &pp, &pd);
    double l[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++) {
        l[0] += d[i] * c->b1[i];
        l[1] += d[i] * c->b2[i];
        l[2] += d[i] * spot_axis[i];
    }
    double n = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    for (int i = 0; i < 3; i++)
        wi[i] = l[i] / n;
    *pdf = pd;
    *w = 0.0;
    return pp == 1.0f;
}

/* uniform in the cone, written here: 1 / (2 pi (1 - cos c)) inside */
static double spot_pdf(void *ctx, const double wo[3], const double wi[3])
{
    (void)ctx, (void)wo;
    return wi[2] >= cos(SPOT_CONE) ? 1.0 / (2.0 * M_PI * (1.0 - cos(SPOT_CONE))) : 0.0;
}

static void chi2_spot_emission(double alpha_test)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    if (build(&s, &g, &t, 0, 0.5f))
        return;
    spot_ctx c = {&g, 0, {0}, {0}};
    for (int i = 0; i < g.nemitters; i++)
        c.k = g.emitters[i].kind == SPM_LIGHT_SPOT ? (spm_u32)i : c.k;
    /* b1 = normalise(axis x y), b2 = axis x b1 */
    double a[3] = {spot_axis[0], spot_axis[1], spot_axis[2]}, y[3] = {0, 1, 0};
    c.b1[0] = a[1] * y[2] - a[2] * y[1], c.b1[1] = a[2] * y[0] - a[0] * y[2];
    c.b1[2] = a[0] * y[1] - a[1] * y[0];
    double n = sqrt(c.b1[0] * c.b1[0] + c.b1[1] * c.b1[1] + c.b1[2] * c.b1[2]);
    for (int i = 0; i < 3; i++)
        c.b1[i] /= n;
    c.b2[0] = a[1] * c.b1[2] - a[2] * c.b1[1], c.b2[1] = a[2] * c.b1[0] - a[0] * c.b1[2];
    c.b2[2] = a[0] * c.b1[1] - a[1] * c.b1[0];
    double wo[3] = {0.0, 0.0, 1.0};
    chi2_sampler smp = {"spot light_sample_emission", &c, spot_sample, spot_pdf, NULL};
    chi2_run(&smp, wo, 400000L, 7, alpha_test);
    scene_free(&s, &g, &t);
}

/* ---- the distant light's emission disc ------------------------------------ */

/* Its rays leave from the disc of the scene's bounding sphere (centre c,
 * radius r) one radius before c, along its direction w: each origin o has
 * (o - c).w = -r and |o - c + r w| <= r, and the origins are uniform on the
 * disc: counts in 8 rings of equal area x 16 sectors against n / 128,
 * Pearson's chi-squared; pdf_pos 1 / (pi r^2). */
/* an empty scene of 4 x 4 pixels seen from 3 above the origin, looking down */
static void small_scene(spm_scene *s)
{
    ts_init(s);
    s->width = s->height = 4;
    s->fov_deg = 60.0f;
    memcpy(s->eye, (float[]){0.0f, 3.0f, 0.0f}, sizeof s->eye);
    memcpy(s->dir, (float[]){0.0f, -1.0f, 0.0f}, sizeof s->dir);
}

#define DISC_RINGS 8
#define DISC_SECTORS 16
static void distant_disc(double alpha_test)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    small_scene(&s);
    int m = ts_material(&s, ts_colour(&s, SPM_KIND_REFLECTANCE, RHO), -1);
    ts_quad(&s, m, (float[]){-1, 0, -2}, (float[]){-1, 0, 2}, (float[]){3, 0, 2},
            (float[]){3, 0, -2});
    static spm_scene_light dl;
    dl = (spm_scene_light){.kind = SPM_LIGHT_DISTANT, .colour = ts_colour(&s, SPM_KIND_EMISSION, 1.0)};
    const double w[3] = {0.48, -0.8, 0.36}; /* unit */
    for (int i = 0; i < 3; i++)
        dl.p[SPM_LIGHT_P_DIR + i] = (float)w[i];
    dl.p[SPM_LIGHT_P_SCALE] = 2.0f;
    s.lights = &dl;
    s.nlights = 1;
    spm_error err;
    if (spm_geometry_build(&s, &g, &err)) {
        CHECK(0, "build: %s", err.msg);
        return;
    }
    ts_tables(&s, &t);
    /* the box [-1, 3] x [0, 0] x [-2, 2]: centre (1, 0, 0), r = sqrt(8) */
    const double c[3] = {1.0, 0.0, 0.0}, r = sqrt(8.0);
    /* a frame of the disc's plane: b1 = normalise(w x y), b2 = w x b1 */
    double b1[3] = {-w[2], 0.0, w[0]}, nb = sqrt(w[0] * w[0] + w[2] * w[2]);
    for (int i = 0; i < 3; i++)
        b1[i] /= nb;
    double b2[3] = {w[1] * b1[2] - w[2] * b1[1], w[2] * b1[0] - w[0] * b1[2],
                    w[0] * b1[1] - w[1] * b1[0]};
    static double cnt[DISC_RINGS * DISC_SECTORS];
    const long n = 256000;
    uint64_t seed = 5;
    double worst_plane = 0.0, worst_pdf = 0.0;
    long outside = 0;
    for (long k = 0; k < n; k++) {
        float u[4] = {(float)chi2_u01(&seed), (float)chi2_u01(&seed), 0.5f, 0.5f}, o[3], d[3],
              pp, pd;
        spm_ref_light_sample_emission(&g, 0, u, o, d, &pp, &pd);
        double v[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]}, along = 0.0, x = 0.0, y = 0.0;
        for (int i = 0; i < 3; i++)
            along += v[i] * w[i], x += v[i] * b1[i], y += v[i] * b2[i];
        worst_plane = fmax(worst_plane, fabs(along + r) / r);
        worst_pdf = fmax(worst_pdf, fabs(pp * M_PI * r * r - 1.0));
        double q = (x * x + y * y) / (r * r), phi = atan2(y, x) + M_PI;
        outside += q > 1.0 + 1e-5;
        int ring = (int)(fmin(q, 0.999999) * DISC_RINGS);
        int sec = (int)fmin(phi / (2.0 * M_PI) * DISC_SECTORS, DISC_SECTORS - 1);
        cnt[ring * DISC_SECTORS + sec] += 1.0;
    }
    double e = (double)n / (DISC_RINGS * DISC_SECTORS), stat = 0.0;
    for (int i = 0; i < DISC_RINGS * DISC_SECTORS; i++)
        stat += (cnt[i] - e) * (cnt[i] - e) / e;
    double pval = st_chi2_sf(stat, DISC_RINGS * DISC_SECTORS - 1);
    printf("distant light's disc: %ld origins, chi2 %.1f over %d cells, p %.3g; off its plane "
           "%.2g r, pdf_pos off %.2g, %ld outside\n", n, stat, DISC_RINGS * DISC_SECTORS, pval,
           worst_plane, worst_pdf, outside);
    CHECK(pval >= alpha_test, "the disc's origins not uniform: p %.3g", pval);
    /* float positions of size r: measured 1e-7 r; bound 1e-5 */
    CHECK(worst_plane <= 1e-5 && outside == 0, "origins off the disc (%.2g r, %ld outside)",
          worst_plane, outside);
    CHECK(worst_pdf <= 1e-5, "pdf_pos off 1 / (pi r^2) by %.2g", worst_pdf);
    s.lights = NULL;
    spm_tables_free(&t);
    spm_geometry_free(&g);
    ts_free(&s);
}

/* ---- chi-squared of a two-sided area light's emission directions --------- */

typedef struct {
    const spm_geometry *g;
    float pdf_off; /* light_pdf_emission's density against the sample's, worst relative */
} two_ctx;

/* the lamp's directions in its triangle's frame (t, n x t, n) */
static int two_sample(void *ctx, const double wo[3], const double u[3], double wi[3],
                      double *pdf, double *w)
{
    (void)wo;
    two_ctx *c = ctx;
    const spm_tri *tr = &c->g->tris[c->g->emitters[0].tri];
    float uf[4] = {0.5f, 0.5f, (float)u[0], (float)u[1]}, o[3], d[3], pp, pd, qp, qd, b[3];
    spm_ref_light_sample_emission(c->g, 0, uf, o, d, &pp, &pd);
    spm_ref_light_pdf_emission(c->g, 0, o, d, &qp, &qd);
    c->pdf_off = fmaxf(c->pdf_off, fabsf(qd / pd - 1.0f));
    b[0] = tr->n[1] * tr->t[2] - tr->n[2] * tr->t[1];
    b[1] = tr->n[2] * tr->t[0] - tr->n[0] * tr->t[2];
    b[2] = tr->n[0] * tr->t[1] - tr->n[1] * tr->t[0];
    wi[0] = wi[1] = wi[2] = 0.0;
    for (int i = 0; i < 3; i++) {
        wi[0] += d[i] * tr->t[i];
        wi[1] += d[i] * b[i];
        wi[2] += d[i] * tr->n[i];
    }
    *pdf = pd;
    *w = 0.0;
    return pp > 0.0f;
}

/* cosine-weighted about either face, each half the time, written here:
 * |cos| / (2 pi) */
static double two_pdf(void *ctx, const double wo[3], const double wi[3])
{
    (void)ctx, (void)wo;
    return fabs(wi[2]) / (2.0 * M_PI);
}

/* 'emit ... twosided': its emission rays leave both faces, each half the
 * time, and light_pdf_emission gives each ray its sampled density */
static void chi2_twosided_emission(double alpha_test)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    small_scene(&s);
    int m = ts_material(&s, -1, ts_colour(&s, SPM_KIND_EMISSION, 1.0));
    s.materials[m].flags |= 1u << SPM_AREA_FLAG_TWOSIDED;
    ts_tri(&s, m, (float[]){-1, 1, -1}, (float[]){1, 1.2f, -1}, (float[]){0, 0.9f, 1});
    spm_error err;
    if (spm_geometry_build(&s, &g, &err)) {
        CHECK(0, "build: %s", err.msg);
        return;
    }
    ts_tables(&s, &t);
    two_ctx c = {&g, 0.0f};
    double wo[3] = {0.0, 0.0, 1.0};
    chi2_sampler smp = {"two-sided light_sample_emission", &c, two_sample, two_pdf, NULL};
    chi2_run(&smp, wo, 400000L, 11, alpha_test);
    printf("  light_pdf_emission against the sample's density: worst %.2g relative\n",
           (double)c.pdf_off);
    /* the same float cosine two ways (sqrt(1 - u) and d.n): measured 5.2e-6; bound 1e-4 */
    CHECK(c.pdf_off <= 1e-4f, "light_pdf_emission off the sample's density by %.2g",
          (double)c.pdf_off);
    spm_tables_free(&t);
    spm_geometry_free(&g);
    ts_free(&s);
}

int main(void)
{
    chi2_light_sample(st_sidak(ALPHA, 5), 0);
    chi2_light_sample(st_sidak(ALPHA, 5), 1);
    chi2_spot_emission(st_sidak(ALPHA, 5));
    distant_disc(st_sidak(ALPHA, 5));
    chi2_twosided_emission(st_sidak(ALPHA, 5));
    light_tracer();
    TEST_END();
}
