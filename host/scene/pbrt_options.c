/* The rendering options before WorldBegin: the camera (pbrt's camera space
 * is left-handed: x right, y up, z forward, and the camera-from-world
 * transform is the current transform at the Camera directive), the film's
 * resolution, the sampler's count; what else they say is warned about. */
#include "pbrt_parser.h"
#include <math.h>
#include <string.h>

/* `Directive "type" params`: the type and the parameters read, `what`
 * the directive and type for messages. */
static int typed(pbrt_parser *p, const char *dname, char *what, size_t size, pbrt_params *ps)
{
    char type[64];
    if (pbrt_arg_string(p, "a type name", type, sizeof type) || pbrt_arg_params(p, ps))
        return 1;
    snprintf(what, size, "%s \"%.40s\"", dname, type);
    return 0;
}

/* The end of a directive: its parameters no code read warned about, freed. */
static int done(pbrt_parser *p, pbrt_params *ps, const char *what, int rc)
{
    rc = rc || pbrt_params_unused(ps, what, p->err);
    pbrt_params_free(ps);
    return rc;
}

static int dir_camera(pbrt_parser *p, const char *where)
{
    char what[128];
    pbrt_params ps;
    if (typed(p, "Camera", what, sizeof what, &ps))
        return 1;
    memcpy(p->cam_ctm, p->gs.ctm, sizeof p->cam_ctm);
    p->have_camera = 1;
    snprintf(p->cam_where, sizeof p->cam_where, "%s", where);
    int bad = 0, rc = 0;
    p->fov = pbrt_param_float(&ps, "fov", 90.0, &bad, p->err);
    p->lens_radius = pbrt_param_float(&ps, "lensradius", 0.0, &bad, p->err);
    p->focal_distance = pbrt_param_float(&ps, "focaldistance", 1e6, &bad, p->err);
    p->ortho = !strcmp(what, "Camera \"orthographic\"");
    if (bad)
        rc = 1;
    else if (!(p->lens_radius >= 0.0 && p->focal_distance > 0.0))
        rc = (spm_errorf(p->err, "%s: %s: lensradius must be >= 0 and focaldistance > 0", where,
                         what), 1);
    else if (strcmp(what, "Camera \"perspective\"") && !p->ortho)
        rc = pbrt_warn(where, what, "rendered as a perspective camera of the same fov", p->err);
    /* pbrt-v4 names the camera's space "camera" */
    double inv[4][4];
    if (!rc && !pbrt_mat_inverse(p->cam_ctm, inv))
        pbrt_coordsys_set(p, "camera", inv);
    return done(p, &ps, what, rc);
}

static int dir_film(pbrt_parser *p, const char *where)
{
    char what[128];
    pbrt_params ps;
    if (typed(p, "Film", what, sizeof what, &ps))
        return 1;
    int bad = 0;
    p->width = pbrt_param_int(&ps, "xresolution", 1280, &bad, p->err);
    p->height = pbrt_param_int(&ps, "yresolution", 720, &bad, p->err);
    pbrt_param_string(&ps, "filename", "", &bad, p->err); /* the command line names the output */
    int rc = bad;
    if (!rc && !(p->width >= 1 && p->width <= SPM_SCENE_MAX_SIDE && p->height >= 1 &&
                 p->height <= SPM_SCENE_MAX_SIDE)) {
        spm_errorf(p->err, "%s: a resolution of %d x %d (each side 1..%d)", where, p->width,
                   p->height, SPM_SCENE_MAX_SIDE);
        rc = 1;
    }
    return done(p, &ps, what, rc);
}

static int dir_sampler(pbrt_parser *p, const char *where)
{
    char what[128];
    pbrt_params ps;
    if (typed(p, "Sampler", what, sizeof what, &ps))
        return 1;
    int bad = 0;
    p->spp = pbrt_param_int(&ps, "pixelsamples", 16, &bad, p->err);
    int rc = bad;
    if (!rc && !(p->spp >= 1 && p->spp <= SPM_SCENE_MAX_SPP)) {
        spm_errorf(p->err, "%s: pixelsamples %d (1..%d)", where, p->spp, SPM_SCENE_MAX_SPP);
        rc = 1;
    }
    /* the sampler's pattern changes the noise, not the image it converges to */
    for (const char *const *u = (const char *const[]){"seed", "randomization", "dimension",
                                                      "jitter", "xsamples", "ysamples", NULL};
         *u; u++)
        pbrt_param_find(&ps, *u, ~0u, &bad, p->err);
    return done(p, &ps, what, rc);
}

static int dir_integrator(pbrt_parser *p, const char *where)
{
    char what[128];
    pbrt_params ps;
    if (typed(p, "Integrator", what, sizeof what, &ps))
        return 1;
    int bad = 0, rc = 0;
    int depth = pbrt_param_int(&ps, "maxdepth", 5, &bad, p->err);
    static const char *const same[] = {"path", "volpath", "bdpt", "mlt", "sppm", "simplepath",
                                       "lightpath", NULL};
    int known = 0;
    for (int i = 0; same[i]; i++) {
        char w[64];
        snprintf(w, sizeof w, "Integrator \"%s\"", same[i]);
        known |= !strcmp(w, what);
    }
    if (bad)
        rc = 1;
    else if (!known)
        rc = pbrt_warn(where, what, "specmip renders full light transport (a path tracer)",
                       p->err);
    static int said;
    if (!bad && !said++) /* a note, not a warning: the image converges to the same */
        spm_warnf("%s: note: Integrator maxdepth %d: specmip's paths end by Russian roulette, "
                  "not at a set depth (docs/PBRT.md)", where, depth);
    for (const char *const *u = (const char *const[]){"lightsampler", "regularize", NULL}; *u; u++)
        pbrt_param_find(&ps, *u, ~0u, &bad, p->err);
    return done(p, &ps, what, rc);
}

/* Directives whose content does not change what the image converges to
 * (Accelerator), or that specmip does not render (the others: warned). */
static int dir_other(pbrt_parser *p, const char *where, const char *dname, int quiet)
{
    char what[128];
    pbrt_params ps;
    if (typed(p, dname, what, sizeof what, &ps))
        return 1;
    int rc = quiet ? 0 : pbrt_warn(where, what, "not rendered", p->err);
    pbrt_params_free(&ps);
    return rc;
}

static int dir_accelerator(pbrt_parser *p, const char *where)
{
    return dir_other(p, where, "Accelerator", 1);
}

static int dir_filter(pbrt_parser *p, const char *where)
{
    pbrt_lexer *lx = pbrt_lx(p);
    int box = lx->type == PT_STRING && !strcmp(lx->text, "box");
    return dir_other(p, where, "PixelFilter", box);
}

static int dir_medium(pbrt_parser *p, const char *where)
{
    char name[SPM_NAME_MAX];
    pbrt_params ps;
    if (pbrt_arg_string(p, "a medium name", name, sizeof name) || pbrt_arg_params(p, &ps))
        return 1;
    pbrt_params_free(&ps);
    return pbrt_warn(where, "MakeNamedMedium (participating media)", "not rendered", p->err);
}

static int dir_medium_interface(pbrt_parser *p, const char *where)
{
    char a[SPM_NAME_MAX], b[SPM_NAME_MAX];
    if (pbrt_arg_string(p, "an interior medium's name", a, sizeof a))
        return 1;
    if (pbrt_lx(p)->type == PT_STRING && pbrt_arg_string(p, "an exterior medium's name", b,
                                                         sizeof b))
        return 1;
    return pbrt_warn(where, "MediumInterface", "media are not rendered", p->err);
}

static int dir_colorspace(pbrt_parser *p, const char *where)
{
    char name[64];
    if (pbrt_arg_string(p, "a colour space's name", name, sizeof name))
        return 1;
    return strcmp(name, "srgb") ? pbrt_warn(where, "ColorSpace other than \"srgb\"",
                                            "rgb values are read as linear sRGB", p->err)
                                : 0;
}

static int dir_option(pbrt_parser *p, const char *where)
{
    pbrt_params ps;
    if (pbrt_arg_params(p, &ps))
        return 1;
    int rc = 0;
    for (int i = 0; i < ps.n && !rc; i++) {
        char what[128];
        snprintf(what, sizeof what, "Option \"%s\"", ps.p[i].name);
        rc = pbrt_warn(where, what, "not applied", p->err);
    }
    pbrt_params_free(&ps);
    return rc;
}

int pbrt_options_finish(pbrt_parser *p, const char *where)
{
    double inv[4][4], eye[3], dir[3], up[3], right[3], z[3] = {0, 0, 0};
    if (pbrt_mat_inverse(p->cam_ctm, inv)) {
        spm_errorf(p->err, "%s: the camera's transform is singular", p->cam_where[0] ? p->cam_where
                                                                                   : where);
        return 1;
    }
    pbrt_mat_apply(inv, z, 1.0, eye);
    pbrt_mat_apply(inv, (double[]){0, 0, 1}, 0.0, dir);
    pbrt_mat_apply(inv, (double[]){0, 1, 0}, 0.0, up);
    pbrt_mat_apply(inv, (double[]){1, 0, 0}, 0.0, right);
    /* the image's x runs along camera x: mirrored when that is not up x dir */
    double c[3] = {up[1] * dir[2] - up[2] * dir[1], up[2] * dir[0] - up[0] * dir[2],
                   up[0] * dir[1] - up[1] * dir[0]};
    int mirror = right[0] * c[0] + right[1] * c[1] + right[2] * c[2] < 0;
    spm_scene *s = p->b.s;
    s->width = p->width;
    s->height = p->height;
    s->spp = p->spp;
    /* pbrt-v4's thin lens (its radius), and its orthographic screen window
     * [-1, 1] across the shorter image side */
    s->aperture = (float)(2.0 * p->lens_radius);
    s->focus = (float)p->focal_distance;
    s->projection = p->ortho ? SPM_PROJ_ORTHOGRAPHIC : SPM_PROJ_PERSPECTIVE;
    s->ortho_size = 2.0f;
    return spm_sb_camera_view(&p->b, eye, dir, up, mirror, p->ortho ? 90.0 : p->fov,
                              SPM_FOV_SHORTER, p->cam_where[0] ? p->cam_where : where, p->err);
}

static int dir_world_begin(pbrt_parser *p, const char *where)
{
    if (p->world) {
        spm_errorf(p->err, "%s: WorldBegin given twice", where);
        return 1;
    }
    p->world = 1;
    pbrt_mat_identity(p->gs.ctm);
    pbrt_coordsys_set(p, "world", p->gs.ctm);
    return pbrt_options_finish(p, where);
}

static int dir_world_end(pbrt_parser *p, const char *where)
{
    (void)p, (void)where; /* pbrt-v3's; v4 ends the world at the end of the file */
    return 0;
}

const pbrt_directive pbrt_option_directives[] = {
    {"Camera", dir_camera},
    {"Film", dir_film},
    {"Sampler", dir_sampler},
    {"Integrator", dir_integrator},
    {"PixelFilter", dir_filter},
    {"Accelerator", dir_accelerator},
    {"MakeNamedMedium", dir_medium},
    {"MediumInterface", dir_medium_interface},
    {"ColorSpace", dir_colorspace},
    {"Option", dir_option},
    {"WorldBegin", dir_world_begin},
    {"WorldEnd", dir_world_end},
    {NULL, NULL},
};
