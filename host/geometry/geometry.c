/* Scene triangles in MiniLight's form, the emitter list and the camera. */
#include "geometry.h"
#include "colour.h"
#include "envmap.h"
#include "lights.h"
#include "materials.h"
#include "util.h"
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* MiniLight clamps the view angle to this range (degrees). */
#define VIEW_ANGLE_MIN 10.0
#define VIEW_ANGLE_MAX 160.0

static void dsub(double o[3], const float a[3], const float b[3])
{
    for (int i = 0; i < 3; i++)
        o[i] = (double)a[i] - (double)b[i];
}

static void dcross(double o[3], const double a[3], const double b[3])
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2],
           z = a[0] * b[1] - a[1] * b[0];
    o[0] = x, o[1] = y, o[2] = z;
}

static double dlen(const double a[3])
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

/* The scene's float vertices as they are; the shading data computed in
 * double from them and stored as float: with e1 = v1 - v0, e2 = v2 - v0, the
 * unit normal of e1 x e2, the unit tangent along e1, half the cross
 * product's length. */
static int make_tri(const spm_scene *sc, const spm_scene_tri *st, spm_tri *t, spm_error *err)
{
    double e1[3], e2[3], cr[3];
    dsub(e1, st->p[1], st->p[0]);
    dsub(e2, st->p[2], st->p[0]);
    dcross(cr, e1, e2);
    double len = dlen(cr), l1 = dlen(e1);
    if (!isfinite(len) || !isfinite(l1)) {
        spm_errorf(err, "%s:%d: triangle has a vertex that is not a finite number", sc->path,
                   st->line);
        return 1;
    }
    if (!((float)(0.5 * len) > 0.0f)) {
        spm_errorf(err, "%s:%d: triangle has zero area (its vertices are collinear)", sc->path,
                   st->line);
        return 1;
    }
    if (st->material < 0 || st->material >= sc->nmaterials) {
        spm_errorf(err, "%s:%d: triangle refers to material %d, the scene has %d", sc->path,
                   st->line, st->material, sc->nmaterials);
        return 1;
    }
    memset(t, 0, sizeof *t);
    for (int i = 0; i < 3; i++) {
        t->v0[i] = st->p[0][i];
        t->v1[i] = st->p[1][i];
        t->v2[i] = st->p[2][i];
        t->n[i] = (float)(cr[i] / len);
        t->t[i] = (float)(e1[i] / l1);
    }
    t->area = (float)(0.5 * len);
    t->material = (spm_u32)st->material;
    t->vn = st->vn > 0 && st->vn <= sc->nvnormals ? (spm_u32)st->vn : 0u;
    return 0;
}

/* MiniLight: a triangle emits if its emission is non-zero (and its area is,
 * which make_tri guarantees). */
static int material_emits(const spm_scene *sc, int m)
{
    int c = sc->materials[m].emit;
    if (c < 0 || c >= sc->ncolours)
        return 0;
    const spm_spectrum *s = &sc->colours[c].s;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        if (s->nm1[i] > 0.0)
            return 1;
    return 0;
}

int spm_emitter_table_build(spm_emitter *em, const double *w, int n)
{
    double total = 0.0, wmin = HUGE_VAL, wmax = 0.0;
    int big = 0;
    for (int i = 0; i < n; i++) {
        total += w[i];
        wmin = w[i] < wmin ? w[i] : wmin;
        if (w[i] > wmax)
            wmax = w[i], big = i;
    }
    if (n == 0 || wmax <= wmin * (1.0 + SPM_EMIT_EQUAL_REL) || n > (int)(SPM_EMIT_CDF_ONE / 2u)) {
        for (int i = 0; i < n; i++) { /* MiniLight's uniform pick: k = (uint)(u * n) */
            em[i].cdf = 0;
            em[i].pdf = (float)(1.0 / n);
            em[i].inv_pdf = (float)n;
        }
        return 0;
    }
    /* count_i = 1 + floor(w_i / W * (2^24 - n)), the rest of 2^24 to the
     * strongest: every emitter reachable, the counts summing to 2^24 */
    spm_u32 *count = spm_xcalloc((size_t)n, sizeof *count), sum = 0;
    for (int i = 0; i < n; i++) {
        count[i] = 1u + (spm_u32)floor(w[i] / total * (double)(SPM_EMIT_CDF_ONE - (spm_u32)n));
        sum += count[i];
    }
    count[big] += SPM_EMIT_CDF_ONE - sum;
    spm_u32 cdf = 0;
    for (int i = 0; i < n; i++) {
        em[i].cdf = cdf;
        em[i].pdf = (float)count[i] / (float)SPM_EMIT_CDF_ONE; /* exact: both powers of two apart */
        em[i].inv_pdf = (float)((double)SPM_EMIT_CDF_ONE / count[i]);
        cdf += count[i];
    }
    free(count);
    return 1;
}

/* An emitter's power for the pick: area * Y of its emission (CIE 1931 Y over
 * the truth bins, the scale included), twice that when both faces emit. */
static double emitter_power(const spm_scene *sc, const spm_tri *t)
{
    double xyz[3];
    spm_xyz_emission(&sc->colours[sc->materials[t->material].emit].s, xyz);
    double faces = spm_material_faces(&sc->materials[t->material]);
    return faces * (double)t->area * (xyz[1] > 0.0 ? xyz[1] : 0.0);
}

/* The environment map's light, the next entry of the selection: its
 * buffer, and its weight *w in the area lights' unit (radiant power over
 * pi): pbrt-v4's, the power the map sends through a disk of the scene's
 * radius r, pi r^2 times the integral of Y over the sphere, over pi:
 *   r^2 2 pi^2 mean(Y sin(theta)). */
static void add_envmap(const spm_scene *sc, spm_geometry *g, double *w)
{
    const spm_scene_envmap *m = sc->env;
    double mean, lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    g->env = spm_envmap_tables(m, &g->nenv, &mean);
    if (!(mean > 0.0)) /* black: escaping rays meet it, nothing to sample */
        return;
    for (int i = 0; i < g->ntris; i++)
        for (int k = 0; k < 3; k++) {
            const float *v[3] = {g->tris[i].v0, g->tris[i].v1, g->tris[i].v2};
            for (int q = 0; q < 3; q++) {
                lo[k] = fmin(lo[k], v[q][k]);
                hi[k] = fmax(hi[k], v[q][k]);
            }
        }
    spm_emitter *e = &g->emitters[g->nemitters++];
    double r2 = 0.0;
    for (int k = 0; k < 3; k++) {
        e->p[SPM_LIGHT_P_POS + k] = (float)(0.5 * (lo[k] + hi[k]));
        r2 += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    double r = sqrt(r2) > 0.0 ? sqrt(r2) : 1.0, rot = m->rotate * M_PI / 180.0;
    e->kind = SPM_LIGHT_ENVMAP;
    e->tri = 0xFFFFFFFFu;
    e->colour = SPM_NONE; /* per texel */
    e->p[SPM_LIGHT_P_DIR] = (float)cos(rot);
    e->p[SPM_LIGHT_P_DIR + 1] = (float)sin(rot);
    e->p[SPM_LIGHT_P_DIR + 2] = (float)r;
    e->p[SPM_LIGHT_P_A] = (float)m->w;
    e->p[SPM_LIGHT_P_B] = (float)m->h;
    e->p[SPM_LIGHT_P_SCALE] = 1.0f; /* in the texels' luminance */
    *w = r * r * 2.0 * M_PI * M_PI * mean;
}

static void list_emitters(const spm_scene *sc, spm_geometry *g)
{
    size_t cap = (size_t)g->ntris + (size_t)sc->nlights + 2;
    g->emitters = spm_xcalloc(cap, sizeof *g->emitters);
    g->light_pdf = spm_xcalloc((size_t)g->ntris + 1, sizeof *g->light_pdf);
    double *w = spm_xcalloc(cap, sizeof *w);
    g->nemitters = 0;
    for (int i = 0; i < g->ntris; i++)
        if (material_emits(sc, (int)g->tris[i].material) && g->tris[i].area > 0.0f) {
            w[g->nemitters] = emitter_power(sc, &g->tris[i]);
            g->emitters[g->nemitters].kind = SPM_LIGHT_AREA;
            g->emitters[g->nemitters].colour = SPM_NONE; /* its material's */
            /* its emission rays leave both faces (spm_lights.h AREA) */
            g->emitters[g->nemitters].p[SPM_LIGHT_P_D] =
                (float)(spm_material_faces(&sc->materials[g->tris[i].material]) == 2);
            g->emitters[g->nemitters++].tri = (spm_u32)i;
        }
    /* the `light` statements' (lights.h), then the sun, next to the map: the
     * trace stage finds both at the table's end (kernels/lights.clh) */
    for (int i = 0; i < 2 * sc->nlights; i++) {
        const spm_scene_light *l = &sc->lights[i % sc->nlights];
        if ((l->kind == SPM_LIGHT_SUN) != (i >= sc->nlights))
            continue;
        spm_emitter *e = &g->emitters[g->nemitters];
        e->kind = (spm_u32)l->kind;
        e->tri = 0xFFFFFFFFu;
        e->colour = (spm_u32)l->colour;
        spm_light_place(sc, l, e->p);
        w[g->nemitters++] = spm_light_power(sc, l);
    }
    if (sc->env) /* last: the trace stage finds it there */
        add_envmap(sc, g, &w[g->nemitters]);
    /* an emission whose Y is 0 (all beyond the CMF's reach) still lights by its
     * other wavelengths: it keeps the smallest share, as a power of 0 would
     * make it unreachable */
    for (int i = 0; i < g->nemitters; i++)
        w[i] = w[i] > 0.0 ? w[i] : 1e-300;
    g->emit_power = spm_emitter_table_build(g->emitters, w, g->nemitters);
    for (int i = 0; i < g->nemitters; i++)
        if (g->emitters[i].kind == SPM_LIGHT_AREA)
            g->light_pdf[g->emitters[i].tri] = g->emitters[i].pdf;
    g->light_w = w; /* the light tree's (light_tree.h) */
}

typedef struct {
    void (*fn)(const spm_scene *);
    const spm_scene *scene;
} beside_task;

static void *run_beside(void *arg)
{
    const beside_task *b = arg;
    b->fn(b->scene);
    return NULL;
}

static int build(spm_scene *owned, void (*beside)(const spm_scene *), const spm_scene *scene,
                 spm_geometry *g, spm_error *err)
{
    memset(g, 0, sizeof *g);
    beside_task task = {beside, scene};
    pthread_t th;
    int threaded = beside && pthread_create(&th, NULL, run_beside, &task) == 0;
    if (beside && !threaded)
        beside(scene);
    int rc = 0;
    g->ntris = scene->ntris;
    g->tris = spm_xcalloc((size_t)scene->ntris + 1, sizeof *g->tris);
    for (int i = 0; i < scene->ntris && !rc; i++)
        rc = make_tri(scene, &scene->tris[i], &g->tris[i], err);
    if (threaded)
        pthread_join(th, NULL);
    if (!rc)
        spm_geometry_textures(scene, g);
    if (rc) {
        spm_geometry_free(g);
        return 1;
    }
    g->nvn = scene->nvnormals;
    if (g->nvn) { /* the smooth triangles' normals, indexed by vn: the BVH's order does not move them */
        g->vnormals = spm_xmalloc((size_t)g->nvn * 9 * sizeof *g->vnormals);
        memcpy(g->vnormals, scene->vnormals, (size_t)g->nvn * 9 * sizeof *g->vnormals);
    }
    g->ndisp = scene->ndisp;
    if (g->ndisp) { /* the trace stage's n(lambda) of each dispersive glass */
        g->disp = spm_xmalloc((size_t)g->ndisp * SPM_TRUTH_BINS * sizeof *g->disp);
        for (size_t i = 0; i < (size_t)g->ndisp * SPM_TRUTH_BINS; i++)
            g->disp[i] = (float)scene->disp[i];
    }
    if (owned) { /* the scene's copy is not needed again: not held through the BVH build */
        spm_light_bounding_sphere(owned, owned->sphere, &owned->sphere[3]);
        owned->have_sphere = 1; /* the lights' place and power hooks read it */
        free(owned->tris);
        owned->tris = NULL;
        owned->ntris = 0;
    }
    /* the camera first: the BVH pads its boxes by the eye's magnitude too */
    g->cam = spm_camera_of_scene(scene);
    if (spm_bvh_build(g, err)) {
        spm_geometry_free(g);
        return 1;
    }
    list_emitters(scene, g); /* after the BVH reordered the triangles */
    return 0;
}

int spm_geometry_build(const spm_scene *scene, spm_geometry *g, spm_error *err)
{
    return build(NULL, NULL, scene, g, err);
}

int spm_geometry_build_consume(spm_scene *scene, void (*beside)(const spm_scene *),
                               spm_geometry *g, spm_error *err)
{
    return build(scene, beside, scene, g, err);
}

void spm_geometry_free(spm_geometry *g)
{
    free(g->tris);
    free(g->nodes);
    free(g->wide);
    free(g->emitters);
    free(g->light_pdf);
    free(g->light_w);
    free(g->vnormals);
    free(g->disp);
    free(g->uvs);
    free(g->tex);
    free(g->env);
    memset(g, 0, sizeof *g);
}

static void dnormalise(double v[3])
{
    double l = dlen(v);
    if (l > 0.0)
        for (int i = 0; i < 3; i++)
            v[i] /= l;
}

/* MiniLight's camera frame: up is Y unless the view is vertical, then Z for a
 * downward view and -Z for an upward one; right = up x dir, up = dir x right. */
spm_camera spm_camera_make(const float eye[3], const float dir[3], float fov_deg, int w, int h)
{
    spm_camera c;
    memset(&c, 0, sizeof c);
    double d[3] = {dir[0], dir[1], dir[2]}, up[3] = {0.0, 1.0, 0.0}, right[3];
    dnormalise(d);
    if (d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0)
        d[2] = 1.0; /* degenerate direction: MiniLight looks along Z */
    dcross(right, up, d);
    if (dlen(right) > 0.0) {
        dnormalise(right);
        dcross(up, d, right);
        dnormalise(up);
    } else {
        up[0] = 0.0, up[1] = 0.0, up[2] = d[1] < 0.0 ? 1.0 : -1.0;
        dcross(right, up, d);
        dnormalise(right);
    }
    double angle = fov_deg;
    if (!(angle >= VIEW_ANGLE_MIN))
        angle = VIEW_ANGLE_MIN; /* also catches NaN */
    if (angle > VIEW_ANGLE_MAX)
        angle = VIEW_ANGLE_MAX;
    for (int i = 0; i < 3; i++) {
        c.eye[i] = eye[i];
        c.dir[i] = (float)d[i];
        c.right[i] = (float)right[i];
        c.up[i] = (float)up[i];
    }
    c.tan_half = (float)tan(angle * 0.5 * (3.14159265358979323846 / 180.0));
    c.width = w;
    c.height = h;
    return c;
}

/* tan_half of the horizontal: t the half extent across axis (fov_axis),
 * times w / h when that axis is the vertical (or the shorter, w >= h). */
static double horizontal_half(double t, int axis, int w, int h)
{
    if (axis == SPM_FOV_VERTICAL || (axis == SPM_FOV_SHORTER && w >= h))
        t *= (double)w / h;
    return t;
}

/* A scene's camera. Without an up vector, MiniLight's frame; with one,
 * right = up x dir, or dir x up for a mirrored camera (pbrt-v4). The field
 * of view (or an orthographic view's extent) lies across the axis fov_axis
 * names; the thin lens is a disk of the aperture's diameter. */
spm_camera spm_camera_of_scene(const spm_scene *s)
{
    spm_camera c = spm_camera_make(s->eye, s->dir, 90.0f, s->width, s->height);
    if (s->up[0] != 0.0f || s->up[1] != 0.0f || s->up[2] != 0.0f) {
        double d[3] = {s->dir[0], s->dir[1], s->dir[2]}, up[3] = {s->up[0], s->up[1], s->up[2]};
        double right[3];
        dnormalise(d);
        dcross(right, up, d);
        dnormalise(right);
        dcross(up, d, right); /* re-orthogonalised: float storage left it a little off */
        dnormalise(up);
        for (int i = 0; i < 3; i++) {
            c.dir[i] = (float)d[i];
            c.right[i] = (float)(s->mirror ? -right[i] : right[i]);
            c.up[i] = (float)up[i];
        }
    }
    double t = s->projection == SPM_PROJ_ORTHOGRAPHIC
                   ? 0.5 * s->ortho_size
                   : tan(s->fov_deg * 0.5 * (3.14159265358979323846 / 180.0));
    c.tan_half = (float)horizontal_half(t, s->fov_axis, s->width, s->height);
    c.ortho = s->projection == SPM_PROJ_ORTHOGRAPHIC;
    c.lens_radius = 0.5f * s->aperture;
    c.focus = s->focus;
    return c;
}
