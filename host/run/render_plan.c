/* The render plan shared by the backends (render_plan.h). */
#include "render_plan.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "lights.h"
#include "materials.h"

static int colour_start(const uint8_t *lvlk, spm_u32 c, int start)
{
    if (c == SPM_NONE)
        return start;
    int l = lvlk[c * SPM_PRETEST_KMAX]; /* k = 1: a colour's coarsest level */
    return l > start ? l : start;
}

int spm_plan_level_start(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                         const spm_trace_params *p)
{
    int start = 0;
    if (!lvlk)
        return 0;
    for (int i = 0; i < g->ntris; i++) {
        const spm_material *m = &mats[g->tris[i].material];
        start = colour_start(lvlk, m->refl, start);
        start = colour_start(lvlk, m->emit, start);
        start = colour_start(lvlk, m->col2, start); /* a type's second colour */
    }
    for (int i = 0; i < g->nemitters; i++) /* the lights not of a triangle */
        if (g->emitters[i].kind != SPM_LIGHT_AREA)
            start = colour_start(lvlk, g->emitters[i].colour, start);
    for (size_t i = 0; g->ntex && i < g->tex[SPM_TEXD_NPAL] * (size_t)SPM_TEX_NODES_ALL; i++)
        start = colour_start(lvlk, g->tex[g->tex[SPM_TEXD_PALETTE] + i], start);
    start = colour_start(lvlk, p->bg_up, start);
    return colour_start(lvlk, p->bg_down, start);
}

/* A levelled mode's paths get the start level or a finer per-occurrence level
 * of a colour in use: those slots are used. */
static void use_colour(spm_render_plan *p, spm_u32 c)
{
    if (c == SPM_NONE || (int)c >= p->tables->ncolours)
        return;
    for (int k = 0; k < SPM_PRETEST_KMAX; k++) {
        spm_u32 l = p->lvlk[c * SPM_PRETEST_KMAX + (spm_u32)k];
        if (l <= p->start_level)
            p->used[l] = 1;
    }
}

static void used_slots(spm_render_plan *p)
{
    const spm_tables *t = p->tables;
    memset(p->used, 0, sizeof p->used);
    if (!p->mode->levelled) {
        p->used[0] = 1;
        return;
    }
    p->used[p->start_level] = 1;
    use_colour(p, t->bg_up);
    use_colour(p, t->bg_down);
    for (int i = 0; i < p->geom->nemitters; i++)
        if (p->geom->emitters[i].kind != SPM_LIGHT_AREA)
            use_colour(p, p->geom->emitters[i].colour);
    const spm_geometry *g = p->geom; /* the colours textured vertices record */
    for (size_t i = 0; g->ntex && i < g->tex[SPM_TEXD_NPAL] * (size_t)SPM_TEX_NODES_ALL; i++)
        use_colour(p, g->tex[g->tex[SPM_TEXD_PALETTE] + i]);
    for (int m = 0; m < t->nmaterials; m++) {
        use_colour(p, t->materials[m].refl);
        use_colour(p, t->materials[m].emit);
        use_colour(p, t->materials[m].col2);
    }
}

int spm_render_plan_init(spm_render_plan *p, const spm_geometry *g, const spm_tables *t, int mode,
                         spm_u32 seed, spm_error *err)
{
    memset(p, 0, sizeof *p);
    if (!(p->mode = spm_mode(mode))) {
        spm_errorf(err, "unknown render mode %d", mode);
        return 1;
    }
    if (g->nnodes < 1 || g->cam.width < 1 || g->cam.height < 1) {
        spm_errorf(err, "nothing to render (empty BVH or image size %dx%d)", g->cam.width,
                   g->cam.height);
        return 1;
    }
    if (spm_mode_check(p->mode, t, err))
        return 1;
    p->geom = g;
    p->tables = t;
    p->lvlk = spm_mode_lvlk(p->mode, t);
    p->npix = (size_t)g->cam.width * (size_t)g->cam.height;
    spm_trace_params *tp = &p->params;
    tp->cam = g->cam;
    tp->ntris = (spm_u32)g->ntris;
    tp->nemitters = (spm_u32)g->nemitters;
    tp->emit_power = (spm_u32)g->emit_power;
    tp->light_tree = g->ntree > 0;
    tp->bg_up = t->bg_up;
    tp->bg_down = t->bg_down;
    tp->seed = seed;
    int start = spm_plan_level_start(g, t->materials, p->lvlk, tp);
    p->start_level = (spm_u32)(start < SPM_NUM_LEVELS ? start : SPM_NUM_LEVELS - 1);
    p->nslots = spm_mode_nslots(p->mode);
    used_slots(p);
    int nd = spm_material_defines(t->materials, t->nmaterials, p->type_defines,
                                  sizeof p->type_defines);
    if (nd < (int)sizeof p->type_defines) /* the light kinds in the selection */
        nd += spm_light_defines(g->emitters, g->nemitters, p->type_defines + nd,
                                sizeof p->type_defines - (size_t)nd);
    if (g->cam.ortho && nd < (int)sizeof p->type_defines) /* kernels/camera.clh */
        nd += snprintf(p->type_defines + nd, sizeof p->type_defines - (size_t)nd,
                       "-DSPM_WITH_ORTHO ");
    if (g->cam.lens_radius > 0.0f && nd < (int)sizeof p->type_defines)
        nd += snprintf(p->type_defines + nd, sizeof p->type_defines - (size_t)nd,
                       "-DSPM_WITH_LENS ");
    int nmap = g->ntex && g->tex[SPM_TEXD_NMAP];
    if ((g->nvn || nmap) && nd < (int)sizeof p->type_defines) /* kernels/shading.clh */
        nd += snprintf(p->type_defines + nd, sizeof p->type_defines - (size_t)nd,
                       "-DSPM_WITH_SMOOTH ");
    if (nmap && nd < (int)sizeof p->type_defines) /* normal maps: shading.clh */
        nd += snprintf(p->type_defines + nd, sizeof p->type_defines - (size_t)nd,
                       "-DSPM_WITH_NMAP ");
    if (g->ntex && nd < (int)sizeof p->type_defines) /* textured materials: kernels/texture.clh */
        nd += snprintf(p->type_defines + nd, sizeof p->type_defines - (size_t)nd,
                       "-DSPM_WITH_TEXTURE ");
    if (spm_geometry_has_alpha(g) && nd < (int)sizeof p->type_defines) /* kernels/alpha.clh */
        nd += snprintf(p->type_defines + nd, sizeof p->type_defines - (size_t)nd,
                       "-DSPM_WITH_ALPHA ");
    /* dispersive glass: committed paths, in both stages (docs/METHODS.md "Dispersion");
     * a mode whose lanes are no wavelengths traces it at n_d and commits none */
    tp->disperse = g->ndisp && !p->mode->one_index;
    if (g->ndisp && nd < (int)sizeof p->type_defines)
        nd += snprintf(p->type_defines + nd, sizeof p->type_defines - (size_t)nd,
                       "-DSPM_WITH_DISPERSION ");
    if (t->nfluor && nd < (int)sizeof p->type_defines) /* where the shade stage finds them */
        snprintf(p->type_defines + nd, sizeof p->type_defines - (size_t)nd,
                 "-DSPM_FLUOR_FIRST=%du -DSPM_FLUOR_NCOL=%du ", t->fluor_first, t->ncolours);
    p->vertex_bytes = spm_material_vertex_bytes(t->materials, t->nmaterials);
    for (int s = 0; s < p->nslots; s++)
        spm_shade_table_build(p->mode, t, s, &p->shade[s]);
    p->pix_ch = 3;
    return 0;
}

static const char *const integrator_names[SPM_INTEGRATOR_COUNT] = {"path", "light", "bdpt"};

const char *spm_integrator_name(int integrator)
{
    return integrator >= 0 && integrator < SPM_INTEGRATOR_COUNT ? integrator_names[integrator]
                                                                : "?";
}

int spm_integrator_parse(const char *name)
{
    for (int i = 0; i < SPM_INTEGRATOR_COUNT; i++)
        if (!strcmp(name, integrator_names[i]))
            return i;
    return -1;
}

/* A type whose descriptor is not `connectable` (its vertex picks one of its
 * terms by a random number: the coated lobes, the rough diffuse terms, the
 * fluorescent ones): the first in the scene, by keyword. */
static const char *picking_type(const spm_tables *t)
{
    for (int m = 0; m < t->nmaterials; m++) {
        spm_u32 tag = SPM_MAT_TAG(t->materials[m]);
        if (!spm_material_types[tag].connectable)
            return spm_material_types[tag].keyword ? spm_material_types[tag].keyword : "?";
    }
    return NULL;
}

/* What the bidirectional integrator refuses beyond the light integrator. */
static const char *bdpt_why(const spm_render_plan *p)
{
    static char why[160];
    const char *type = picking_type(p->tables);
    for (size_t e = 0; e < (size_t)p->geom->nemitters; e++)
        if (p->geom->emitters[e].kind != SPM_LIGHT_AREA &&
            p->geom->emitters[e].kind != SPM_LIGHT_POINT &&
            p->geom->emitters[e].kind != SPM_LIGHT_SPOT &&
            p->geom->emitters[e].kind != SPM_LIGHT_DISTANT)
            return "it joins camera vertices to area, point, spot and distant lights only (a "
                   "sun or a map is a light at infinity a camera path meets by escaping, whose "
                   "vertex MIS does not weigh yet)";
    if (type) {
        snprintf(why, sizeof why, "material type '%s' picks one of its terms per vertex, and "
                                  "MIS needs its density as a function of the two directions",
                 type);
        return why;
    }
    return NULL;
}

/* 1 when an area light's material has an opacity: a light subpath leaves
 * its every point, where a ray meets only the part of it that is there. */
static int emitter_opacity(const spm_geometry *g)
{
    if (!spm_geometry_has_alpha(g))
        return 0;
    for (int e = 0; e < g->nemitters; e++)
        if (g->emitters[e].kind == SPM_LIGHT_AREA &&
            g->tex[g->tex[SPM_TEXD_ALPHA] + g->tris[g->emitters[e].tri].material])
            return 1;
    return 0;
}

/* What the light integrators do not render yet, each with its reason. */
int spm_render_plan_integrator(spm_render_plan *p, int i, spm_error *err)
{
    const spm_trace_params *tp = &p->params;
    const char *why = NULL;
    if (i != SPM_INTEGRATOR_PATH) {
        if (tp->cam.ortho)
            why = "an orthographic camera sees along one direction only, which no vertex's "
                  "connection to the camera meets";
        else if (tp->bg_up != SPM_NONE || tp->bg_down != SPM_NONE || p->geom->env)
            why = "the background is no light a subpath starts from yet (a sky's or a map's "
                  "emission would leave a disc of the scene's bounding sphere along a direction "
                  "its own sampling draws, and a camera vertex escaping to it would be a light "
                  "vertex at infinity, which MIS does not weigh yet)";
        else if (emitter_opacity(p->geom))
            why = "a light subpath starts on an emitter's every point, which its opacity "
                  "would thin (an opaque emitter with a textured emission it renders)";
        else if (tp->nemitters == 0)
            why = "the scene has no light to start a subpath from";
    }
    if (!why && i == SPM_INTEGRATOR_BDPT)
        why = bdpt_why(p);
    if (why) {
        spm_errorf(err, "--integrator %s cannot render this scene: %s", spm_integrator_name(i),
                   why);
        return 1;
    }
    p->integrator = i;
    return 0;
}

int spm_render_plan_spectral(spm_render_plan *p, int nm, spm_error *err)
{
    if (!spm_mode_spec_ok(p->mode, nm)) {
        if (!p->mode->spec_nm[0])
            spm_errorf(err, "%s mode has no spectrum to write: a spectral image needs a "
                            "spectral mode", p->mode->name);
        else
            spm_errorf(err, "%s mode writes spectral images of %d nm bins%s, not %d nm",
                       p->mode->name, p->mode->spec_nm[0], p->mode->spec_nm[1] ? " or 1 nm" : "",
                       nm);
        return 1;
    }
    p->spec_nm = nm;
    p->nspec = (SPM_LAMBDA_MAX - SPM_LAMBDA_MIN) / nm;
    p->pix_ch = 3 + p->nspec;
    for (int s = 0; s < p->nslots; s++)
        spm_spec_map_build(p->mode, p->tables, s, nm, &p->spec[s]);
    return 0;
}

size_t spm_plan_batch_paths(size_t base, int pix_ch, size_t vertex_bytes)
{
    if (pix_ch <= 3)
        return base;
    /* a path's vertex record, and its record and batch-image floats */
    size_t xyz = SPM_MAX_DEPTH * vertex_bytes + 2 * 3 * sizeof(float);
    size_t spec = SPM_MAX_DEPTH * vertex_bytes + 2 * (size_t)pix_ch * sizeof(float);
    size_t n = base / spec * xyz;
    return n ? n : 1;
}

void spm_render_plan_free(spm_render_plan *p)
{
    for (int s = 0; s < SPM_NUM_LEVELS; s++) {
        spm_shade_table_free(&p->shade[s]);
        spm_spec_map_free(&p->spec[s]);
    }
    memset(p, 0, sizeof *p);
}

spm_trace_params spm_plan_pass_params(const spm_render_plan *p, spm_u32 first_sample, spm_u32 spp)
{
    spm_trace_params tp = p->params;
    tp.first_sample = first_sample;
    tp.spp_per_pass = spp;
    return tp;
}

size_t spm_batch_pixels(size_t npix, size_t spp, size_t batch_paths)
{
    size_t b = spp ? batch_paths / spp : npix;
    if (b < 1)
        b = 1;
    return b < npix ? b : npix;
}

size_t spm_batch_room(size_t npix, size_t spp, size_t batch_paths)
{
    /* bpix: pixels a batch; n: their paths */
    size_t bpix = spm_batch_pixels(npix, spp, batch_paths), n = bpix * (spp ? spp : 1);
    return bpix < npix && n < batch_paths ? batch_paths : n;
}

void spm_pass_stats_add(spm_pass_stats *a, const spm_pass_stats *s)
{
    a->trace_s += s->trace_s;
    a->shade_s += s->shade_s;
    a->accum_s += s->accum_s;
    a->paths += s->paths;
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        for (int k = 0; k < 3; k++)
            a->level_paths[l][k] += s->level_paths[l][k];
    a->truncated += s->truncated;
    a->nonfinite += s->nonfinite;
    a->untimed += s->untimed;
}

void spm_count_levels_hist(const spm_mode_desc *m, const size_t hist[256], size_t n,
                           spm_pass_stats *st)
{
    st->paths += n;
    if (!m->levelled) {
        st->level_paths[0][SPM_SETBY_NONE] += n;
        return;
    }
    for (int b = 0; b < 256; b++) {
        spm_u32 by = ((spm_u32)b >> SPM_SETBY_SHIFT) & 3u;
        st->level_paths[spm_mode_slot(m, (uint8_t)b)][by > 2 ? 0 : by] += hist[b];
    }
}

void spm_count_levels(const spm_mode_desc *m, const spm_path *paths, const uint8_t *levels,
                      size_t n, spm_pass_stats *st)
{
    size_t hist[256] = {0};
    for (size_t i = 0; i < n; i++) {
        hist[levels[i]]++;
        st->truncated += paths[i].h.end == SPM_END_TRUNCATED;
    }
    spm_count_levels_hist(m, hist, n, st);
}

void spm_accumulate_pass_ch(const float *rec, size_t npix, spm_u32 spp, int ch, float *pass,
                            spm_pass_stats *st)
{
    if (ch == 3) {
        spm_accumulate_pass(rec, npix, spp, pass, st);
        return;
    }
    for (size_t p = 0; p < npix; p++) {
        float *out = &pass[p * (size_t)ch];
        for (int c = 0; c < ch; c++)
            out[c] = 0.0f;
        for (spm_u32 k = 0; k < spp; k++) {
            const float *x = &rec[(p * spp + k) * (size_t)ch];
            if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) {
                st->nonfinite++;
                continue;
            }
            for (int c = 0; c < ch; c++)
                out[c] += x[c];
        }
    }
}

void spm_accumulate_pass(const float *xyz, size_t npix, spm_u32 spp, float *pass_xyz,
                         spm_pass_stats *st)
{
    for (size_t p = 0; p < npix; p++) {
        float s[3] = {0.0f, 0.0f, 0.0f};
        for (spm_u32 k = 0; k < spp; k++) {
            const float *x = &xyz[(p * spp + k) * 3];
            if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) {
                st->nonfinite++;
                continue;
            }
            s[0] += x[0];
            s[1] += x[1];
            s[2] += x[2];
        }
        memcpy(&pass_xyz[p * 3], s, sizeof s);
    }
}
