/* LightSource: pbrt-v4's point, spot and distant lights as specmip's (lights.h),
 * a constant "infinite" light as a uniform background; the rest warned
 * about by name (docs/PBRT.md, Lights). pbrt-v4 divides every light's
 * spectrum by its photometric value before `scale` (pbrt_spectrum_colour
 * does the same), then multiplies by `power` / k_e or `illuminance`. */
#include "pbrt_parser.h"
#include "envmap.h"
#include "lights.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

int pbrt_light_colour(pbrt_parser *p, pbrt_params *ps, const char *name, double scale,
                      const char *where)
{
    int bad = 0;
    pbrt_param *s = pbrt_param_find(ps, name, 1u << PP_RGB | 1u << PP_SPECTRUM |
                                                  1u << PP_BLACKBODY, &bad, p->err);
    pbrt_param white = {.type = PP_SPECTRUM, .type_name = "spectrum", .nstr = 1,
                        .str = (char *[]){"stdillum-D65"}};
    snprintf(white.name, sizeof white.name, "%s", name);
    snprintf(white.where, sizeof white.where, "%s", where);
    if (bad)
        return -2;
    p->sp.err = p->err;
    return pbrt_spectrum_colour(&p->sp, s ? s : &white, PBRT_ILLUMINANT, scale);
}

/* A point3 parameter, else def: 0, or 1 with err (not three numbers). */
static int param_point(pbrt_parser *p, pbrt_params *ps, const char *name, const double def[3],
                       double out[3])
{
    int bad = 0;
    pbrt_param *a = pbrt_param_find(ps, name, 1u << PP_POINT3, &bad, p->err);
    if (bad)
        return 1;
    if (a && a->nnum != 3) {
        spm_errorf(p->err, "%s: '%s' needs 3 numbers (got %zu)", a->where, name, a->nnum);
        return 1;
    }
    for (int i = 0; i < 3; i++)
        out[i] = a ? a->num[i] : def[i];
    return 0;
}

/* `scale` (not negative) and the factor of a photometric parameter `unit`
 * (power, illuminance: used when above 0, as pbrt-v4 does) over k. */
static int light_scale(pbrt_parser *p, pbrt_params *ps, const char *unit, double k,
                       const char *where, double *scale, double *factor)
{
    int bad = 0;
    *scale = pbrt_param_float(ps, "scale", 1.0, &bad, p->err);
    double v = unit ? pbrt_param_float(ps, unit, -1.0, &bad, p->err) : -1.0;
    if (!bad && !(*scale >= 0.0 && isfinite(*scale) && isfinite(v))) {
        spm_errorf(p->err, "%s: scale %g and %s %g must be finite, scale not negative", where,
                   *scale, unit ? unit : "power", v);
        return 1;
    }
    *factor = v > 0.0 ? v / k : 1.0;
    return bad;
}

static void add_light(pbrt_parser *p, spm_scene_light *l, const char *where)
{
    snprintf(l->where, sizeof l->where, "%.127s", where);
    spm_scene *s = p->b.s;
    s->lights = spm_xrealloc(s->lights, ((size_t)s->nlights + 1) * sizeof *s->lights);
    s->lights[s->nlights++] = *l;
}

/* point: I (W/sr at luminance scale), at the CTM's image of `from`;
 * `power` P sets the intensity to P / (4 pi) (pbrt-v4's k_e = 4 pi). */
static int light_point(pbrt_parser *p, pbrt_params *ps, const char *where)
{
    double scale, f, from[3], zero[3] = {0, 0, 0};
    if (light_scale(p, ps, "power", 4.0 * M_PI, where, &scale, &f) ||
        param_point(p, ps, "from", zero, from))
        return 1;
    int c = pbrt_light_colour(p, ps, "I", scale, where);
    if (c < -1)
        return 1;
    if (c == -1)
        return 0; /* black: no light */
    spm_scene_light l = {.kind = SPM_LIGHT_POINT, .colour = c};
    double pos[3];
    pbrt_mat_apply(p->gs.ctm, from, 1.0, pos);
    for (int i = 0; i < 3; i++)
        l.p[SPM_LIGHT_P_POS + i] = (float)pos[i];
    l.p[SPM_LIGHT_P_SCALE] = (float)f;
    add_light(p, &l, where);
    return 0;
}

/* spot: I (W/sr at luminance scale) at the CTM's image of `from`, aimed at
 * `to` (defaults 0 0 0 and 0 0 1), falling from 1 at coneangle - conedelta
 * to 0 at coneangle (degrees, defaults 30 and 5) as a smoothstep in the
 * cosine (specmip's spot of shape smoothstep); `power` P sets the intensity
 * to P over the falloff's solid angle, as pbrt-v4's k_e does. */
static int light_spot(pbrt_parser *p, pbrt_params *ps, const char *where)
{
    int bad = 0;
    double cone = pbrt_param_float(ps, "coneangle", 30.0, &bad, p->err);
    double delta = bad ? 0.0 : pbrt_param_float(ps, "conedelta", 5.0, &bad, p->err);
    double from[3], to[3], zero[3] = {0, 0, 0}, z[3] = {0, 0, 1}, scale, f;
    if (bad || param_point(p, ps, "from", zero, from) || param_point(p, ps, "to", z, to))
        return 1;
    if (!(cone > 0.0 && cone <= 90.0) || !(delta >= 0.0 && delta <= cone)) {
        spm_errorf(p->err, "%s: LightSource \"spot\": coneangle %g must be above 0 and at most "
                   "90 degrees, conedelta %g from 0 to it", where, cone, delta);
        return 1;
    }
    spm_scene_light l = {.kind = SPM_LIGHT_SPOT};
    double d[3] = {to[0] - from[0], to[1] - from[1], to[2] - from[2]}, w[3], pos[3];
    pbrt_mat_apply(p->gs.ctm, d, 0.0, w);
    pbrt_mat_apply(p->gs.ctm, from, 1.0, pos);
    double n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (!(n > 0.0) || !isfinite(n)) {
        spm_errorf(p->err, "%s: LightSource \"spot\": 'from' and 'to' give no direction", where);
        return 1;
    }
    for (int i = 0; i < 3; i++) {
        l.p[SPM_LIGHT_P_POS + i] = (float)pos[i];
        l.p[SPM_LIGHT_P_DIR + i] = (float)(w[i] / n);
    }
    l.p[SPM_LIGHT_P_A] = (float)(cone * M_PI / 180.0);
    l.p[SPM_LIGHT_P_B] = (float)((cone - delta) * M_PI / 180.0);
    l.p[SPM_LIGHT_P_C] = (float)cos(cone * M_PI / 180.0);
    l.p[SPM_LIGHT_P_D] = SPM_SPOT_SMOOTHSTEP;
    l.p[SPM_LIGHT_P_SCALE] = 1.0f;
    double k_e = spm_light_kinds[SPM_LIGHT_SPOT].power(p->b.s, l.p);
    if (light_scale(p, ps, "power", k_e, where, &scale, &f))
        return 1;
    if ((l.colour = pbrt_light_colour(p, ps, "I", scale, where)) < -1)
        return 1;
    if (l.colour == -1)
        return 0; /* black: no light */
    l.p[SPM_LIGHT_P_SCALE] = (float)f;
    add_light(p, &l, where);
    return 0;
}

/* distant: L the irradiance on a surface facing it (at luminance scale),
 * travelling from `from` toward `to` (defaults 0 0 0 and 0 0 1) through the
 * CTM; `illuminance` E sets it to E. */
static int light_distant(pbrt_parser *p, pbrt_params *ps, const char *where)
{
    double scale, f, from[3], to[3], zero[3] = {0, 0, 0}, z[3] = {0, 0, 1};
    if (light_scale(p, ps, "illuminance", 1.0, where, &scale, &f) ||
        param_point(p, ps, "from", zero, from) || param_point(p, ps, "to", z, to))
        return 1;
    double d[3] = {to[0] - from[0], to[1] - from[1], to[2] - from[2]}, w[3];
    pbrt_mat_apply(p->gs.ctm, d, 0.0, w);
    double n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (!(n > 0.0) || !isfinite(n)) {
        spm_errorf(p->err, "%s: LightSource \"distant\": 'from' and 'to' give no direction",
                   where);
        return 1;
    }
    int c = pbrt_light_colour(p, ps, "L", scale, where);
    if (c < -1)
        return 1;
    if (c == -1)
        return 0;
    spm_scene_light l = {.kind = SPM_LIGHT_DISTANT, .colour = c};
    for (int i = 0; i < 3; i++)
        l.p[SPM_LIGHT_P_DIR + i] = (float)(w[i] / n);
    l.p[SPM_LIGHT_P_SCALE] = (float)f;
    add_light(p, &l, where);
    return 0;
}

/* infinite: a constant L (radiance at luminance scale; `illuminance` E sets
 * it to E / pi, the irradiance of the upper hemisphere E) is the background
 * in every direction. pbrt-v4 reads `filename` as an equal-area octahedral
 * map (it refuses other layouts), which specmip's equirectangular
 * `background map` is not: warned by name, no background from it. */
static int light_infinite(pbrt_parser *p, pbrt_params *ps, const char *where)
{
    int bad = 0;
    const char *fn = pbrt_param_string(ps, "filename", NULL, &bad, p->err);
    if (bad)
        return 1;
    if (fn) {
        for (int k = 0; k < ps->n; k++)
            ps->p[k].used = 1;
        return pbrt_warn(where, "LightSource \"infinite\" with a 'filename'",
                         "pbrt-v4's maps are equal-area octahedral images; specmip reads "
                         "equirectangular maps ('background map'): convert it", p->err);
    }
    double scale, f;
    if (light_scale(p, ps, "illuminance", M_PI, where, &scale, &f))
        return 1;
    int c = pbrt_light_colour(p, ps, "L", scale * f, where);
    if (c < -1)
        return 1;
    spm_scene *s = p->b.s;
    if ((s->bg_up >= 0 || s->env) &&
        pbrt_warn(where, "a second LightSource \"infinite\"", "the last one is the background",
                  p->err))
        return 1;
    s->bg_up = s->bg_down = c;
    spm_envmap_free(s->env);
    s->env = NULL;
    return 0;
}

int pbrt_light_make(pbrt_parser *p, const char *type, pbrt_params *ps, const char *where)
{
    static const struct {
        const char *type;
        int (*fn)(pbrt_parser *, pbrt_params *, const char *);
    } kinds[] = {{"point", light_point},
                 {"spot", light_spot},
                 {"distant", light_distant},
                 {"infinite", light_infinite}};
    char what[128];
    snprintf(what, sizeof what, "LightSource \"%.40s\"", type);
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
        if (!strcmp(type, kinds[i].type))
            return kinds[i].fn(p, ps, where) || pbrt_params_unused(ps, what, p->err);
    for (int k = 0; k < ps->n; k++)
        ps->p[k].used = 1;
    return pbrt_warn(where, what, "a light type specmip does not render", p->err);
}
