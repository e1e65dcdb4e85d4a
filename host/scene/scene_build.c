/* The scene builder both parsers (scene_parse.c, scene_minilight.c) and the
 * mesh statements (mesh_build.c) build through: colours and materials shared
 * by content, triangle checks, light checks, pruning of what no triangle
 * uses; and freeing the scene it made. */
#include "scene_build.h"
#include "colour.h"
#include "materials.h"
#include "texture.h"
#include "envmap.h"
#include "sky.h"
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void spm_scene_free(spm_scene *s)
{
    free(s->colours);
    free(s->materials);
    free(s->tris);
    free(s->vnormals);
    free(s->uvs);
    for (int i = 0; i < s->ntextures; i++)
        spm_texture_free(&s->textures[i]);
    free(s->textures);
    free(s->palette);
    for (int i = 0; i < s->nalphas; i++)
        free(s->alphas[i].a);
    free(s->alphas);
    for (int i = 0; i < s->nnmaps; i++)
        free(s->nmaps[i].q);
    free(s->nmaps);
    free(s->tangents);
    free(s->meshes);
    free(s->lights);
    free(s->rerad);
    free(s->disp);
    spm_envmap_free(s->env);
    memset(s, 0, sizeof *s);
    s->bg_up = s->bg_down = -1;
}

/* ---- builder --------------------------------------------------------------- */

void spm_sb_init(spm_scene_builder *b, spm_scene *s, const char *path)
{
    memset(b, 0, sizeof *b);
    memset(s, 0, sizeof *s);
    b->s = s;
    snprintf(s->path, sizeof s->path, "%s", path);
    s->bg_up = s->bg_down = -1;
    spm_names_init(&b->colour_index);
    spm_names_init(&b->material_index);
}

void spm_sb_done(spm_scene_builder *b, int ok)
{
    spm_names_free(&b->colour_index);
    spm_names_free(&b->material_index);
    if (!ok)
        spm_scene_free(b->s);
}

/* Grows an array to hold one more element. */
static void *reserve(void *p, int count, int *cap, size_t elem)
{
    if (count < *cap)
        return p;
    while (*cap <= count) /* a part that grew the array itself leaves cap behind */
        *cap = *cap ? *cap * 2 : 16;
    return spm_xrealloc(p, (size_t)*cap * elem);
}

static void spectrum_key(const spm_spectrum *sp, char *key, size_t size)
{
    uint64_t h = spm_fnv1a64(SPM_FNV1A64_BASIS, sp->nm1, sizeof sp->nm1); /* the bins' bytes */
    snprintf(key, size, "%d:%016llx", (int)sp->kind, (unsigned long long)h);
}

/* An emission becomes float tables on the device: its bins (truth and level
 * means, no larger than its peak) and, for the rgb mode, its XYZ turned to
 * linear sRGB. A value beyond FLT_MAX there is infinite in every sample it
 * lights, and those samples are dropped: the light would vanish. At the other
 * end, a peak below FLT_MIN is subnormal in float: products with path weights
 * lose their digits or flush to zero (devices may flush subnormals), so the
 * image is black or off-colour; that is a warning, as the scene is valid. */
static int check_emission_range(const spm_spectrum *sp, const char *where, spm_error *err)
{
    double peak = spm_spectrum_max(sp), xyz[3], rgb[3], big = peak;
    spm_xyz_emission(sp, xyz);
    spm_xyz_to_linear_srgb(xyz, rgb);
    for (int i = 0; i < 3; i++)
        big = fmax(big, fmax(fabs(xyz[i]), fabs(rgb[i])));
    if (!(big <= FLT_MAX)) {
        spm_errorf(err, "%s: emission too bright for float arithmetic: its spectrum, XYZ or "
                        "linear sRGB reaches %.3g, beyond float's largest value %.3g; lower its "
                        "scale", where, big, FLT_MAX);
        return 1;
    }
    if (peak > 0.0 && peak < FLT_MIN)
        spm_warnf("%s: emission so faint that float cannot hold it: its spectrum peaks at %.3g, "
                  "below float's smallest normal value %.3g, so the image will be black or "
                  "off-colour; raise its scale", where, peak, FLT_MIN);
    return 0;
}

int spm_sb_colour(spm_scene_builder *b, const char *name, const spm_spectrum *sp,
                  const char *where, spm_error *err)
{
    spm_scene *s = b->s;
    char key[64];
    spectrum_key(sp, key, sizeof key);
    int i = spm_names_get(&b->colour_index, key);
    if (i >= 0 && s->colours[i].s.kind == sp->kind &&
        memcmp(s->colours[i].s.nm1, sp->nm1, sizeof sp->nm1) == 0)
        return i;
    if (s->ncolours >= SPM_SCENE_MAX_COLOURS) {
        spm_errorf(err, "%s: more than %d distinct colours", where, SPM_SCENE_MAX_COLOURS);
        return -1;
    }
    if (sp->kind == SPM_KIND_EMISSION && check_emission_range(sp, where, err))
        return -1;
    s->colours = reserve(s->colours, s->ncolours, &b->cap_colours, sizeof *s->colours);
    spm_colour *c = &s->colours[s->ncolours];
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "%s", name);
    c->s = *sp;
    if (i < 0) /* on a (freak) hash collision the first colour keeps the key */
        spm_names_put(&b->colour_index, key, s->ncolours);
    return s->ncolours++;
}

int spm_sb_material(spm_scene_builder *b, const char *name, int refl, int emit,
                    const char *where, spm_error *err)
{
    spm_scene_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.refl = refl;
    m.emit = emit;
    m.type = SPM_MAT_LAMBERT;
    m.etype = SPM_EMIT_AREA;
    m.col2 = m.col3 = m.diag = -1;
    return spm_sb_material_typed(b, &m, where, err);
}

int spm_sb_material_typed(spm_scene_builder *b, const spm_scene_material *proto,
                          const char *where, spm_error *err)
{
    spm_scene *s = b->s;
    char key[256];
    int n = snprintf(key, sizeof key, "%d %d", proto->refl, proto->emit);
    if (proto->type != SPM_MAT_LAMBERT || proto->etype != SPM_EMIT_AREA || proto->col2 >= 0) {
        n += snprintf(key + n, sizeof key - (size_t)n, " %d %d %d", proto->type, proto->etype,
                      proto->col2);
        if (proto->col3 >= 0)
            n += snprintf(key + n, sizeof key - (size_t)n, " c%d", proto->col3);
        for (int i = 0; i < SPM_MAT_PARAMS; i++)
            n += snprintf(key + n, sizeof key - (size_t)n, " %a", proto->p[i]);
    }
    if (proto->tex) /* a textured reflectance is not its mean */
        n += snprintf(key + n, sizeof key - (size_t)n, " t%d", proto->tex);
    if (proto->etex) /* nor a textured emission */
        n += snprintf(key + n, sizeof key - (size_t)n, " e%d %a", proto->etex, proto->escale);
    if (proto->alpha_mode) /* a cut-out is not the opaque surface */
        n += snprintf(key + n, sizeof key - (size_t)n, " a%d %a %a %d", proto->alpha_mode,
                      proto->alpha_cutoff, proto->alpha_factor, proto->alpha_map);
    if (proto->mix_metal) /* a metallic-roughness mix is not its coated base */
        n += snprintf(key + n, sizeof key - (size_t)n, " m%d %a %a %d %d", proto->mix_metal,
                      proto->mix_metallic, proto->mix_rough, proto->mix_mmap, proto->mix_rmap);
    if (proto->nmap) /* a bumped surface is not the smooth one */
        n += snprintf(key + n, sizeof key - (size_t)n, " n%d %a", proto->nmap, proto->nmap_scale);
    if (proto->flags) /* a two-sided light is not a one-sided one */
        n += snprintf(key + n, sizeof key - (size_t)n, " f%x", proto->flags);
    int i = spm_names_get(&b->material_index, key);
    if (i >= 0)
        return i;
    if (s->nmaterials >= SPM_SCENE_MAX_MATERIALS) {
        spm_errorf(err, "%s: more than %d distinct materials", where, SPM_SCENE_MAX_MATERIALS);
        return -1;
    }
    s->materials = reserve(s->materials, s->nmaterials, &b->cap_materials, sizeof *s->materials);
    s->materials[s->nmaterials] = *proto;
    spm_names_put(&b->material_index, key, s->nmaterials);
    return s->nmaterials++;
}

int spm_sb_degenerate(const float p[3][3])
{
    double e1[3], e2[3], c[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)p[1][k] - p[0][k];
        e2[k] = (double)p[2][k] - p[0][k];
    }
    c[0] = e1[1] * e2[2] - e1[2] * e2[1];
    c[1] = e1[2] * e2[0] - e1[0] * e2[2];
    c[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double cross = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    double l2 = sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
    /* The sine of the angle between the edges below ~1e-6 leaves no usable
     * normal in float arithmetic (a relative bound). The area bound is the one
     * absolute one, float's range: below 1e-24 (edges of 1e-12) the products
     * of the triangle test (edge functions ~ area, t's numerator ~ area x
     * distance) fall towards float's smallest normal numbers (1.2e-38) and
     * lose their precision; any triangle above it is hit as in any other unit. */
    return !(cross > 1e-6 * l1 * l2) || 0.5 * cross < 1e-24;
}

int spm_sb_tri(spm_scene_builder *b, const double p[3][3], int material, int line,
               const char *where, spm_error *err)
{
    spm_scene *s = b->s;
    if (s->ntris >= SPM_SCENE_MAX_TRIS) {
        spm_errorf(err, "%s: more than %d triangles", where, SPM_SCENE_MAX_TRIS);
        return 1;
    }
    spm_scene_tri t;
    memset(&t, 0, sizeof t);
    for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++) {
            if (!(fabs(p[v][k]) <= SPM_SCENE_MAX_COORD)) {
                spm_errorf(err, "%s: coordinate %g is beyond +-%g", where, p[v][k],
                           SPM_SCENE_MAX_COORD);
                return 1;
            }
            t.p[v][k] = (float)p[v][k];
        }
    /* Judge the triangle the renderer will see: the float vertices. */
    if (spm_sb_degenerate(t.p)) {
        spm_errorf(err, "%s: degenerate triangle (zero area: its vertices coincide or lie on "
                        "one line)", where);
        return 1;
    }
    t.material = material;
    t.line = line;
    s->tris = reserve(s->tris, s->ntris, &b->cap_tris, sizeof *s->tris);
    s->tris[s->ntris++] = t;
    return 0;
}

int spm_sb_tri_normals(spm_scene_builder *b, const float n[9])
{
    spm_scene *s = b->s;
    if (s->ntris < 1 || s->tris[s->ntris - 1].vn)
        return 1;
    s->vnormals = reserve(s->vnormals, s->nvnormals, &b->cap_vnormals, sizeof *s->vnormals);
    memcpy(s->vnormals[s->nvnormals++], n, sizeof *s->vnormals);
    s->tris[s->ntris - 1].vn = s->nvnormals;
    return 0;
}

int spm_sb_tri_uv(spm_scene_builder *b, const float uv[6])
{
    spm_scene *s = b->s;
    if (s->ntris < 1 || s->tris[s->ntris - 1].uv)
        return 1;
    s->uvs = reserve(s->uvs, s->nuvs, &b->cap_uvs, sizeof *s->uvs);
    memcpy(s->uvs[s->nuvs++], uv, sizeof *s->uvs);
    s->tris[s->ntris - 1].uv = s->nuvs;
    return 0;
}

int spm_sb_texture(spm_scene_builder *b, spm_texture *t)
{
    spm_scene *s = b->s;
    s->textures = reserve(s->textures, s->ntextures, &b->cap_textures, sizeof *s->textures);
    s->textures[s->ntextures] = *t;
    memset(t, 0, sizeof *t);
    return s->ntextures++;
}

int spm_sb_alpha_pixels(spm_scene_builder *b, const float *a, int w, int h, int wrap_u,
                        int wrap_v)
{
    spm_scene *s = b->s;
    spm_alpha_map m = {w, h, {wrap_u, wrap_v}, spm_xmalloc((size_t)w * h), {{0}, 0}};
    for (size_t i = 0; i < (size_t)w * h; i++) /* round(clamp(a, 0, 1) 255) */
        m.a[i] = (unsigned char)lrintf(255.0f * (a[i] > 0.0f ? (a[i] < 1.0f ? a[i] : 1.0f) : 0.0f));
    s->alphas = reserve(s->alphas, s->nalphas, &b->cap_alphas, sizeof *s->alphas);
    s->alphas[s->nalphas] = m;
    return s->nalphas++;
}

int spm_sb_tri_tangents(spm_scene_builder *b, const float t[12])
{
    spm_scene *s = b->s;
    if (s->ntris < 1 || s->tris[s->ntris - 1].tg)
        return 1;
    s->tangents = reserve(s->tangents, s->ntangents, &b->cap_tangents, sizeof *s->tangents);
    memcpy(s->tangents[s->ntangents++], t, sizeof *s->tangents);
    s->tris[s->ntris - 1].tg = s->ntangents;
    return 0;
}

/* a component m in [-1, 1] (clamped; NaN 0) on the codes 0 .. 1022, m = 0 at 511 */
static unsigned nmap_code(float m)
{
    m = m > -1.0f ? (m < 1.0f ? m : 1.0f) : (m == m ? -1.0f : 0.0f);
    return (unsigned)lrintf(SPM_NMAP_CODE * (1.0f + m));
}

int spm_sb_nmap_pixels(spm_scene_builder *b, const float *rgb, int w, int h, int wrap_u,
                       int wrap_v)
{
    spm_scene *s = b->s;
    spm_normal_map m = {w, h, {wrap_u, wrap_v}, spm_xmalloc((size_t)w * h * sizeof *m.q),
                        {{0}, 0}};
    for (size_t i = 0; i < (size_t)w * h; i++) /* m = 2 c - 1 */
        m.q[i] = nmap_code(2.0f * rgb[3 * i] - 1.0f) | nmap_code(2.0f * rgb[3 * i + 1] - 1.0f) << 10 |
                 nmap_code(2.0f * rgb[3 * i + 2] - 1.0f) << 20;
    s->nmaps = reserve(s->nmaps, s->nnmaps, &b->cap_nmaps, sizeof *s->nmaps);
    s->nmaps[s->nnmaps] = m;
    return s->nnmaps++;
}

int spm_sb_camera(spm_scene_builder *b, const double eye[3], const double dir[3], double fov,
                  const char *where, spm_error *err)
{
    spm_scene *s = b->s;
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(len > 0.0) || !isfinite(len)) {
        spm_errorf(err, "%s: the camera direction must be a non-zero vector", where);
        return 1;
    }
    double clamped = fov < SPM_FOV_MIN ? SPM_FOV_MIN : fov > SPM_FOV_MAX ? SPM_FOV_MAX : fov;
    if (clamped != fov)
        spm_warnf("%s: field of view %g degrees clamped to %g (range %g..%g, as MiniLight)",
                  where, fov, clamped, SPM_FOV_MIN, SPM_FOV_MAX);
    for (int k = 0; k < 3; k++) {
        s->eye[k] = (float)eye[k];
        s->dir[k] = (float)(dir[k] / len);
    }
    s->fov_deg = (float)clamped;
    return 0;
}

void spm_sb_index_table(spm_scene_builder *b, const double n[SPM_TRUTH_BINS],
                        spm_scene_material *m)
{
    spm_scene *s = b->s;
    s->disp = spm_xrealloc(s->disp, (size_t)(s->ndisp + 1) * SPM_TRUTH_BINS * sizeof *s->disp);
    memcpy(s->disp + (size_t)s->ndisp * SPM_TRUTH_BINS, n, SPM_TRUTH_BINS * sizeof *n);
    m->p[SPM_DIEL_P_DISP] = ++s->ndisp;
}

int spm_sb_camera_view(spm_scene_builder *b, const double eye[3], const double dir[3],
                       const double up[3], int mirror, double fov, int axis, const char *where,
                       spm_error *err)
{
    if (!(fov > 0.0 && fov < 180.0)) {
        spm_errorf(err, "%s: a field of view of %g degrees (it must be inside 0..180)", where,
                   fov);
        return 1;
    }
    if (spm_sb_camera(b, eye, dir, 90.0, where, err))
        return 1;
    spm_scene *s = b->s;
    s->fov_deg = (float)fov;
    s->fov_axis = axis;
    if (!up)
        return 0;
    double c[3] = {up[1] * dir[2] - up[2] * dir[1], up[2] * dir[0] - up[0] * dir[2],
                   up[0] * dir[1] - up[1] * dir[0]};
    double lu = sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
    double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(lc > 1e-9 * lu) || !isfinite(lc)) {
        spm_errorf(err, "%s: the camera's up vector is zero or parallel to its direction", where);
        return 1;
    }
    /* up made normal to dir: (dir x up) x dir over its length */
    double d[3] = {s->dir[0], s->dir[1], s->dir[2]}, u[3];
    u[0] = (d[1] * up[2] - d[2] * up[1]);
    u[1] = (d[2] * up[0] - d[0] * up[2]);
    u[2] = (d[0] * up[1] - d[1] * up[0]);
    double v[3] = {u[1] * d[2] - u[2] * d[1], u[2] * d[0] - u[0] * d[2], u[0] * d[1] - u[1] * d[0]};
    double lv = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++)
        s->up[k] = (float)(v[k] / lv);
    s->mirror = mirror != 0;
    return 0;
}

int spm_sb_reflectance(const spm_spectrum *shape, double scale, const char *where,
                       spm_spectrum *out, spm_error *err)
{
    *out = *shape;
    out->kind = SPM_KIND_REFLECTANCE;
    spm_spectrum_scale(out, scale);
    int imax = 0;
    for (int i = 1; i < SPM_TRUTH_BINS; i++)
        imax = out->nm1[i] > out->nm1[imax] ? i : imax;
    if (out->nm1[imax] > 1.0) {
        spm_errorf(err, "%s: reflectance reaches %g at %d nm with scale %g; a reflectance must "
                        "not exceed 1", where, out->nm1[imax], SPM_LAMBDA_MIN + imax, scale);
        return 1;
    }
    return 0;
}

int spm_sb_optical(const spm_spectrum *shape, double scale, spm_spectrum *out)
{
    *out = *shape; /* loaded as a reflectance: extended by its end values */
    out->kind = SPM_KIND_REFLECTANCE;
    spm_spectrum_scale(out, scale);
    return 0;
}

int spm_sb_emission(const spm_spectrum *shape, double luminance, const char *where,
                    spm_spectrum *out, spm_error *err)
{
    double xyz[3];
    spm_xyz_emission(shape, xyz);
    if (!(xyz[1] > 0.0) || !isfinite(xyz[1])) {
        spm_errorf(err, "%s: the emission has no luminance inside %d-%d nm", where,
                   SPM_LAMBDA_MIN, SPM_LAMBDA_MAX);
        return 1;
    }
    *out = *shape;
    out->kind = SPM_KIND_EMISSION;
    spm_spectrum_scale(out, luminance / xyz[1]);
    return 0;
}

/* Drops materials no triangle uses and colours nothing refers to. */
static void prune(spm_scene *s)
{
    int *mmap = spm_xmalloc(((size_t)s->nmaterials + 1) * sizeof *mmap);
    int *cmap = spm_xmalloc(((size_t)s->ncolours + 1) * sizeof *cmap);
    for (int i = 0; i < s->nmaterials; i++)
        mmap[i] = -1;
    for (int i = 0; i < s->ncolours; i++)
        cmap[i] = -1;
    for (int t = 0; t < s->ntris; t++)
        mmap[s->tris[t].material] = 0;
    for (int i = 0; i < s->nmaterials; i++) /* a used mix's metal (a conductor: no mix) */
        if (mmap[i] == 0 && s->materials[i].mix_metal > 0)
            mmap[s->materials[i].mix_metal - 1] = 0;
    int nm = 0;
    for (int i = 0; i < s->nmaterials; i++)
        if (mmap[i] == 0) {
            mmap[i] = nm;
            s->materials[nm++] = s->materials[i];
        }
    s->nmaterials = nm;
    for (int i = 0; i < nm; i++)
        if (s->materials[i].mix_metal > 0)
            s->materials[i].mix_metal = 1 + mmap[s->materials[i].mix_metal - 1];
    for (int t = 0; t < s->ntris; t++)
        s->tris[t].material = mmap[s->tris[t].material];
    /* Colours in order of first use, so the numbering does not depend on leftovers. */
    int nc = 0;
    spm_colour *kept = spm_xmalloc(((size_t)s->ncolours + 1) * sizeof *kept);
    int *refs[] = {&s->bg_up, &s->bg_down};
    for (int i = 0; i < 4 * s->nmaterials + 2 + s->nlights; i++) {
        spm_scene_material *m = i < 4 * s->nmaterials ? &s->materials[i / 4] : NULL;
        int nb = i - 4 * s->nmaterials; /* the background's two, then the lights' */
        int *r = m ? (i % 4 == 0 ? &m->refl : i % 4 == 1 ? &m->emit : i % 4 == 2 ? &m->col2 : &m->col3)
                   : nb < 2 ? refs[nb] : &s->lights[nb - 2].colour;
        if (*r < 0)
            continue;
        if (cmap[*r] < 0) {
            kept[nc] = s->colours[*r];
            cmap[*r] = nc++;
        }
        *r = cmap[*r];
    }
    free(s->colours);
    s->colours = kept;
    s->ncolours = nc;
    free(mmap);
    free(cmap);
}

/* Prunes once; prune's array holds the colours kept and no more, so the
 * capacity follows it (a colour added after prune grows it). */
static int prune_once(spm_scene_builder *b, const char *where, spm_error *err)
{
    spm_scene *s = b->s;
    if (s->ntris == 0) {
        spm_errorf(err, "%s: end of file: the scene has no triangles", where);
        return 1;
    }
    if (!b->pruned)
        prune(s);
    b->pruned = 1;
    b->cap_colours = s->ncolours;
    return 0;
}

int spm_sb_prune(spm_scene_builder *b, const char *where, spm_error *err)
{
    if (b->pruned)
        return 0;
    if (prune_once(b, where, err))
        return 1;
    spm_scene *s = b->s;
    spm_names_free(&b->colour_index); /* the kept colours' new indices, for sharing */
    spm_names_init(&b->colour_index);
    for (int i = 0; i < s->ncolours; i++) {
        char key[64];
        spectrum_key(&s->colours[i].s, key, sizeof key);
        if (spm_names_get(&b->colour_index, key) < 0)
            spm_names_put(&b->colour_index, key, i);
    }
    return 0;
}

int spm_sb_finish(spm_scene_builder *b, const char *where, spm_error *err)
{
    spm_scene *s = b->s;
    if (prune_once(b, where, err))
        return 1;
    /* the map's colours, after the scene's own (a daylight sky's: sky.h) */
    if (spm_sky_palette(s, err) || spm_envmap_palette(s, err))
        return 1;
    /* colours a type derives, last (materials.h derive) */
    for (int i = 0; i < s->nmaterials; i++) {
        const spm_mtype_desc *t = &spm_material_types[s->materials[i].type];
        s->materials[i].diag = -1;
        if (t->derive && t->derive(s, &s->materials[i], err)) {
            char msg[sizeof err->msg]; /* the message names the file */
            snprintf(msg, sizeof msg, "%s", err->msg);
            spm_errorf(err, "%s: %s", where, msg);
            return 1;
        }
    }
    int lit = s->bg_up >= 0 || s->bg_down >= 0 || s->nlights > 0 || s->env;
    for (int i = 0; i < s->nmaterials && !lit; i++)
        lit = s->materials[i].emit >= 0;
    if (!lit) {
        spm_errorf(err, "%s: end of file: the scene has no light (no triangle has an emitting "
                        "material, no light and no background)", where);
        return 1;
    }
    return 0;
}
