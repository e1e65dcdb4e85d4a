/* The sensor (perspective, thinlens) with its hdrfilm and sampler, and the
 * integrator. Mitsuba's camera space looks along +z with y up and x to the
 * image's left; `to_world` places it. Its `fov` spans the axis `fov_axis`
 * names (x by default; y, diagonal, smaller, larger): specmip's camera
 * takes the fov across the image's shorter side, converted here from the
 * file's width and height. */
#include "mitsuba.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* tan(fov_x / 2) from fov (degrees) across `axis` of a w x h image. */
static int tan_half_x(double fov, const char *axis, double w, double h, double *tx)
{
    double t = tan(fov * PI / 360.0);
    int x_smaller = w <= h;
    if (!strcmp(axis, "x") || (!strcmp(axis, "smaller") && x_smaller) ||
        (!strcmp(axis, "larger") && !x_smaller))
        *tx = t;
    else if (!strcmp(axis, "y") || !strcmp(axis, "smaller") || !strcmp(axis, "larger"))
        *tx = t * w / h;
    else if (!strcmp(axis, "diagonal"))
        *tx = t / sqrt(1.0 + (h / w) * (h / w));
    else
        return 1;
    return 0;
}

static int film(mi_node *f, int *w, int *h, spm_error *err)
{
    int bad = 0;
    *w = mi_int(f, "width", 768, &bad, err);
    *h = mi_int(f, "height", 576, &bad, err);
    /* how the image is stored: -o and its extension decide */
    static const char *const quiet[] = {"pixel_format", "component_format", "file_format",
                                        "banner", "sample_border", "compensate", NULL};
    for (int i = 0; quiet[i]; i++)
        mi_prop(f, quiet[i], "string|boolean", &bad, err);
    if (bad)
        return 1;
    if (!(*w >= 1 && *w <= SPM_SCENE_MAX_SIDE && *h >= 1 && *h <= SPM_SCENE_MAX_SIDE)) {
        spm_errorf(err, "%s: a film of %d x %d (each side 1..%d)", f->where, *w, *h,
                   SPM_SCENE_MAX_SIDE);
        return 1;
    }
    for (int i = 0; i < f->nkids; i++) {
        mi_node *k = f->kids[i];
        const char *t = mi_attr(k, "type");
        if (strcmp(k->tag, "rfilter"))
            continue;
        k->used = 1;
        if (t && strcmp(t, "box") &&
            pbrt_warn(k->where, "<rfilter> other than \"box\"",
                      "specmip's pixels are box-filtered", err))
            return 1;
    }
    return mi_unused(f, "<film type=\"hdrfilm\">", err);
}

static int sampler(mi_node *s, int *spp, spm_error *err)
{
    int bad = 0;
    *spp = mi_int(s, "sample_count", 4, &bad, err);
    mi_int(s, "seed", 0, &bad, err); /* the pattern changes the noise, not the image */
    mi_bool(s, "jitter", 1, &bad, err);
    if (bad)
        return 1;
    if (!(*spp >= 1 && *spp <= SPM_SCENE_MAX_SPP)) {
        spm_errorf(err, "%s: sample_count %d (1..%d)", s->where, *spp, SPM_SCENE_MAX_SPP);
        return 1;
    }
    return mi_unused(s, "<sampler>", err);
}

/* The sensor's children: film and sampler (the defaults when absent). */
static int sensor_parts(mi_node *s, int *w, int *h, int *spp, spm_error *err)
{
    *w = 768, *h = 576, *spp = 4;
    for (int i = 0; s && i < s->nkids; i++) {
        mi_node *k = s->kids[i];
        int rc = 0;
        if (!strcmp(k->tag, "film")) {
            k->used = 1;
            const char *t = mi_attr(k, "type");
            if (t && strcmp(t, "hdrfilm") &&
                pbrt_warn(k->where, "<film> other than \"hdrfilm\"", "read as hdrfilm", err))
                return 1;
            rc = film(k, w, h, err);
        } else if (!strcmp(k->tag, "sampler")) {
            k->used = 1;
            rc = sampler(k, spp, err);
        }
        if (rc)
            return 1;
    }
    return 0;
}

/* The lens and the options of a perspective camera specmip has no use for. */
static int sensor_params(mi_node *s, const char *type, double *fov, const char **axis,
                         spm_error *err)
{
    int bad = 0;
    *fov = mi_float(s, "fov", -1, &bad, err);
    *axis = mi_string(s, "fov_axis", "x", &bad, err);
    const char *fl = mi_string(s, "focal_length", NULL, &bad, err);
    mi_float(s, "near_clip", 0.01, &bad, err); /* clipping: not modelled, nothing is that near */
    mi_float(s, "far_clip", 1e4, &bad, err);
    mi_float(s, "focus_distance", 0, &bad, err); /* a pinhole's: no effect */
    if (bad)
        return 1;
    if (*fov < 0 && fl) { /* "50mm": of a 36 x 24 mm frame, across its diagonal */
        double mm = strtod(fl, NULL);
        if (!(mm > 0)) {
            spm_errorf(err, "%s: focal_length \"%s\"", s->where, fl);
            return 1;
        }
        *fov = 2 * atan(sqrt(36.0 * 36 + 24.0 * 24) / (2 * mm)) * 180 / PI;
        *axis = "diagonal";
    } else if (*fov < 0) {
        *fov = 2 * atan(sqrt(36.0 * 36 + 24.0 * 24) / 100.0) * 180 / PI;
        *axis = "diagonal";
    }
    char w[128];
    snprintf(w, sizeof w, "<sensor type=\"%.40s\">", type);
    if (strcmp(type, "perspective") && strcmp(type, "thinlens") &&
        pbrt_warn(s->where, w, "rendered as a perspective camera of the same fov", err))
        return 1;
    double ar = mi_float(s, "aperture_radius", 0, &bad, err);
    if (!bad && ar > 0 &&
        pbrt_warn(s->where, "<sensor type=\"thinlens\">: aperture_radius (depth of field)",
                  "specmip has no thin lens yet: a pinhole", err))
        return 1;
    for (const char *const *o = (const char *const[]){"principal_point_offset_x",
                                                     "principal_point_offset_y", NULL};
         *o; o++)
        if (mi_float(s, *o, 0, &bad, err) != 0 &&
            pbrt_warn(s->where, "<sensor>: principal_point_offset", "not applied", err))
            return 1;
    return bad;
}

int mi_sensor(mi_node *s, spm_scene_builder *b, spm_error *err)
{
    int w, h, spp;
    double fov = 45, m[4][4], tx;
    const char *axis = "x", *where = s ? s->where : b->s->path;
    if (sensor_parts(s, &w, &h, &spp, err))
        return 1;
    if (s && (sensor_params(s, mi_attr(s, "type") ? mi_attr(s, "type") : "", &fov, &axis,
                            err) || mi_to_world(s, m, err)))
        return 1;
    if (!s)
        pbrt_mat_identity(m);
    if (tan_half_x(fov, axis, w, h, &tx) || !(fov > 0 && fov < 180)) {
        spm_errorf(err, "%s: fov %g across \"%s\" (x, y, diagonal, smaller or larger; 0..180)",
                   where, fov, axis);
        return 1;
    }
    double eye[3], dir[3], up[3], left[3], z[3] = {0, 0, 0};
    pbrt_mat_apply(m, z, 1.0, eye);
    pbrt_mat_apply(m, (double[]){0, 0, 1}, 0.0, dir);
    pbrt_mat_apply(m, (double[]){0, 1, 0}, 0.0, up);
    pbrt_mat_apply(m, (double[]){1, 0, 0}, 0.0, left);
    /* the image's right is camera -x: mirrored (scene.h) unless that is dir x up */
    double c[3] = {dir[1] * up[2] - dir[2] * up[1], dir[2] * up[0] - dir[0] * up[2],
                   dir[0] * up[1] - dir[1] * up[0]};
    int mirror = -(left[0] * c[0] + left[1] * c[1] + left[2] * c[2]) > 0;
    double shorter = w >= h ? 2 * atan(tx * h / w) : 2 * atan(tx);
    b->s->width = w;
    b->s->height = h;
    b->s->spp = spp;
    return spm_sb_camera_frame(b, eye, dir, up, mirror, shorter * 180 / PI, where, err) ||
           (s && mi_unused(s, "<sensor>", err));
}

/* The integrator: Mitsuba's path tracers converge to what specmip renders;
 * a finite max_depth cuts paths specmip follows to the end (Russian
 * roulette): warned. Wrappers (moment, aov) hold the one that renders. */
int mi_integrator(mi_node *n, spm_error *err)
{
    const char *t = mi_attr(n, "type");
    char what[128];
    snprintf(what, sizeof what, "<integrator type=\"%.40s\">", t ? t : "");
    n->used = 1;
    if (t && (!strcmp(t, "moment") || !strcmp(t, "aov")))
        for (int i = 0; i < n->nkids; i++)
            if (!strcmp(n->kids[i]->tag, "integrator"))
                return mi_integrator(n->kids[i], err);
    static const char *const paths[] = {"path", "volpath", "volpathmis", "prb", "prbvolpath",
                                        "ptracer", "bdpt", NULL};
    int known = 0, bad = 0;
    for (int i = 0; t && paths[i]; i++)
        known |= !strcmp(paths[i], t);
    if (!known)
        return pbrt_warn(n->where, what, "specmip renders full light transport (a path tracer)",
                         err);
    int depth = mi_int(n, "max_depth", -1, &bad, err);
    mi_int(n, "rr_depth", 5, &bad, err); /* roulette's start: the same image */
    int hide = mi_bool(n, "hide_emitters", 0, &bad, err);
    if (bad)
        return 1;
    char w[200];
    snprintf(w, sizeof w, "%s: max_depth %d", what, depth);
    if (depth >= 0 && pbrt_warn(n->where, w, "specmip's paths end by Russian roulette, not at "
                                             "a set depth: the image holds every bounce", err))
        return 1;
    if (hide && pbrt_warn(n->where, "<integrator>: hide_emitters", "emitters are seen", err))
        return 1;
    return mi_unused(n, what, err);
}
