/* A mesh's triangles into a scene: file materials bound to scene materials or
 * lifted from their RGB, the statement's transform, degenerate triangles
 * skipped and counted. */
#include "mesh.h"
#include "interrupt.h"
#include "mesh_texture.h"
#include "materials.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* m <- a m for affine 3x4 matrices (x' = A x + a_t after x' = M x + m_t). */
static void compose(double m[3][4], const double a[3][3], const double at[3])
{
    double r[3][4];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++) {
            double v = a[i][0] * m[0][j] + a[i][1] * m[1][j] + a[i][2] * m[2][j];
            r[i][j] = j == 3 ? v + at[i] : v;
        }
    memcpy(m, r, sizeof r);
}

void spm_mesh_identity(double m[3][4])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            m[i][j] = i == j;
}

void spm_mesh_scale(double m[3][4], const double scale[3])
{
    const double s[3][3] = {{scale[0], 0, 0}, {0, scale[1], 0}, {0, 0, scale[2]}};
    const double zero[3] = {0, 0, 0};
    compose(m, s, zero);
}

void spm_mesh_rotate(double m[3][4], const double axis[3], double degrees)
{
    double len = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    double x = axis[0] / len, y = axis[1] / len, z = axis[2] / len;
    double a = degrees * (M_PI / 180.0), c = cos(a), s = sin(a), t = 1.0 - c;
    /* Rodrigues' rotation matrix */
    const double r[3][3] = {{t * x * x + c, t * x * y - s * z, t * x * z + s * y},
                            {t * x * y + s * z, t * y * y + c, t * y * z - s * x},
                            {t * x * z - s * y, t * y * z + s * x, t * z * z + c}};
    const double zero[3] = {0, 0, 0};
    compose(m, r, zero);
}

void spm_mesh_translate(double m[3][4], const double translate[3])
{
    const double one[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    compose(m, one, translate);
}

void spm_mesh_transform(const double scale[3], const double axis[3], double degrees,
                        const double translate[3], double m[3][4])
{
    spm_mesh_identity(m);
    spm_mesh_scale(m, scale);
    spm_mesh_rotate(m, axis, degrees);
    spm_mesh_translate(m, translate);
}

void spm_mesh_cache_init(spm_mesh_cache *c) { spm_names_init(&c->rgb); }
void spm_mesh_cache_free(spm_mesh_cache *c) { spm_names_free(&c->rgb); }

static int finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* A lifted colour (spm_sb_rgb_colour); a reflectance is clamped to [0, 1]
 * first, as the fit would. Index, -1 for black, -2 on error. */
static int rgb_colour(spm_scene_builder *b, spm_mesh_cache *cache, const float rgbf[3],
                      spm_kind kind, const char *where, spm_error *err)
{
    double rgb[3] = {rgbf[0], rgbf[1], rgbf[2]};
    if (kind == SPM_KIND_REFLECTANCE)
        for (int i = 0; i < 3; i++)
            rgb[i] = rgb[i] < 0 ? 0 : rgb[i] > 1 ? 1 : rgb[i];
    return spm_sb_rgb_colour(b, &cache->rgb, rgb, kind, where, err);
}

/* The determinant of the transform's 3x3 part. */
static double det3(const double m[3][4])
{
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Whether material i's name is that of an earlier material (files such as
 * exported glTF repeat names: a list names each once). */
static int named_before(const spm_mesh_data *d, uint32_t i)
{
    for (uint32_t k = 0; k < i; k++)
        if (!strcmp(d->mats[k].name, d->mats[i].name))
            return 1;
    return 0;
}

static int is_gltf(const char *file)
{
    size_t n = strlen(file);
    return (n > 4 && !strcasecmp(file + n - 4, ".glb")) ||
           (n > 5 && !strcasecmp(file + n - 5, ".gltf"));
}

/* glTF 2.0's default material, for its triangles without one: base colour
 * 1, metallicFactor 1, roughnessFactor 1 (the specification's defaults): a
 * rough white metal, mapped as any glTF material is (mesh_pbr.c). */
static int gltf_default(spm_scene_builder *b, spm_mesh_cache *cache, double scale,
                        const char *file, const char *where, spm_error *err)
{
    spm_mesh_material g;
    memset(&g, 0, sizeof g);
    snprintf(g.name, sizeof g.name, "glTF default");
    g.format = SPM_MESH_FMT_GLTF;
    g.has = SPM_MESH_HAS_METALLIC | SPM_MESH_HAS_ROUGHNESS;
    g.diffuse[0] = g.diffuse[1] = g.diffuse[2] = 1.0f;
    g.metallic = g.roughness = 1.0f;
    g.opacity = 1.0f;
    char mwhere[700];
    snprintf(mwhere, sizeof mwhere, "%s: %s: triangles without a material", where, file);
    spm_warnf("%s take glTF's default material (base colour 1, metallic 1, roughness 1: a "
              "rough white metal, as glTF 2.0 defines it)", mwhere);
    int r = rgb_colour(b, cache, g.diffuse, SPM_KIND_REFLECTANCE, mwhere, err);
    return r < -1 ? -1 : spm_mesh_map_material(b, &g, r, -1, scale, mwhere, err);
}

/* The scene material of each file material that a triangle uses (-1 unused). */
static int bind_materials(spm_scene_builder *b, spm_mesh_cache *cache, const spm_mesh_data *d,
                          const spm_mesh_opts *o, const char *file, const char *where,
                          int *map, spm_error *err)
{
    for (uint32_t i = 0; i < d->nmats; i++)
        map[i] = -2;
    for (uint64_t t = 0; t < d->ntris; t++)
        map[d->tris[t].mat] = -1;
    for (int j = 0; j < o->nbinds; j++) {
        int found = 0;
        for (uint32_t i = 0; i < d->nmats; i++)
            if (d->mats[i].name[0] && !strcmp(d->mats[i].name, o->binds[j].file_mat)) {
                found = 1;
                if (map[i] != -2)
                    map[i] = o->binds[j].material;
            }
        if (!found) {
            char names[400] = "";
            size_t n = 0;
            for (uint32_t i = 0; i < d->nmats && n < sizeof names - 80; i++)
                if (d->mats[i].name[0] && !named_before(d, i))
                    n += (size_t)snprintf(names + n, sizeof names - n, "%s'%s'", n ? ", " : "",
                                          d->mats[i].name);
            spm_errorf(err, "%s: bind: %s has no material '%s' (it has %s)", where, file,
                       o->binds[j].file_mat, n ? names : "none");
            return 1;
        }
    }
    /* the statement's length scale: cbrt |det M| (a uniform scale's factor; of
     * a non-uniform one, the mean by volume) */
    double scale = cbrt(fabs(det3(o->m)));
    for (uint32_t i = 0; i < d->nmats; i++) {
        if (map[i] != -1)
            continue;
        if (o->material >= 0) {
            map[i] = o->material;
            continue;
        }
        const spm_mesh_material *m = &d->mats[i];
        if (!m->name[0] && is_gltf(file)) {
            if ((map[i] = gltf_default(b, cache, scale, file, where, err)) < 0)
                return 1;
            continue;
        }
        if (!m->name[0] && o->fallback > 0) {
            map[i] = o->fallback - 1;
            continue;
        }
        if (!m->name[0]) {
            spm_errorf(err, "%s: %s has triangles without a material: give the mesh one with "
                            "'material NAME'", where, file);
            return 1;
        }
        char mwhere[700];
        snprintf(mwhere, sizeof mwhere, "%s: %s: material '%s'", where, file, m->name);
        if (!finite3(m->diffuse) || !finite3(m->emission) || m->emission[0] < 0 ||
            m->emission[1] < 0 || m->emission[2] < 0) {
            spm_errorf(err, "%s: colours must be finite and emissions not negative", mwhere);
            return 1;
        }
        int r = rgb_colour(b, cache, m->diffuse, SPM_KIND_REFLECTANCE, mwhere, err);
        int e = r < -1 ? -2 : rgb_colour(b, cache, m->emission, SPM_KIND_EMISSION, mwhere, err);
        if (e < -1)
            return 1;
        map[i] = spm_mesh_map_material(b, m, r, e, scale, mwhere, err);
        if (map[i] >= 0)
            map[i] = spm_mesh_texture_bind(b, d, m, map[i], mwhere, err);
        if (map[i] >= 0)
            map[i] = spm_mesh_etexture_bind(b, d, m, map[i], mwhere, err);
        if (map[i] >= 0)
            map[i] = spm_mesh_alpha_bind(b, d, m, map[i], mwhere, err);
        if (map[i] >= 0)
            map[i] = spm_mesh_mix_bind(b, d, m, map[i], mwhere, err);
        if (map[i] >= 0)
            map[i] = spm_mesh_nmap_bind(b, d, m, map[i], mwhere, err);
        if (map[i] < 0)
            return 1;
    }
    return 0;
}

/* The normals' map of the statement's transform x' = M x + t: the inverse
 * transpose of M, cofactor(M) / det(M). */
static void normal_matrix(const double m[3][4], double det, double out[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            out[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) / det;
        }
}

/* A triangle's vertex normals in scene coordinates, unit length and
 * oriented to its front face (the side of (p1 - p0) x (p2 - p0)): all three
 * are turned when their sum points to the back, as a file may wind its faces
 * against its normals. q[v] is the file's normal of scene vertex v. Returns 0
 * (flat) when one is zero or not finite, or their sum is perpendicular to the
 * face. */
static int tri_normals(const double nm[3][3], const float *q[3], const double p[3][3],
                       float out[9])
{
    double n[3][3], sum[3] = {0, 0, 0}, e1[3], e2[3], g[3];
    for (int v = 0; v < 3; v++) {
        double len = 0;
        for (int i = 0; i < 3; i++) {
            n[v][i] = nm[i][0] * q[v][0] + nm[i][1] * q[v][1] + nm[i][2] * q[v][2];
            len += n[v][i] * n[v][i];
        }
        len = sqrt(len);
        if (!(len > 0) || !isfinite(len))
            return 0;
        for (int i = 0; i < 3; i++) {
            n[v][i] /= len;
            sum[i] += n[v][i];
        }
    }
    for (int i = 0; i < 3; i++) {
        e1[i] = p[1][i] - p[0][i];
        e2[i] = p[2][i] - p[0][i];
    }
    g[0] = e1[1] * e2[2] - e1[2] * e2[1];
    g[1] = e1[2] * e2[0] - e1[0] * e2[2];
    g[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double side = g[0] * sum[0] + g[1] * sum[1] + g[2] * sum[2];
    if (!(side != 0) || !isfinite(side))
        return 0;
    for (int v = 0; v < 3; v++)
        for (int i = 0; i < 3; i++)
            out[3 * v + i] = (float)(side < 0 ? -n[v][i] : n[v][i]);
    return 1;
}

/* A triangle's smooth shading: its vertex normals sn (the file's, or computed
 * by `smooth`), used if `smooth` or its material's type says so, unless
 * `flat`. 1 smooth, 0 flat, -1 flat as its normals are unusable. */
static int add_normals(spm_scene_builder *b, const spm_mesh_opts *o, const spm_mesh_normals *sn,
                       int material, const double nm[3][3], int flip, const double p[3][3])
{
    int tsmooth = spm_material_types[b->s->materials[material].type].smooth;
    int want = sn && o->shading != SPM_MESH_SHADE_FLAT && tsmooth >= 0 &&
               (o->shading == SPM_MESH_SHADE_SMOOTH || tsmooth);
    if (!want || !(sn->n[0][0] != 0 || sn->n[0][1] != 0 || sn->n[0][2] != 0 ||
                   sn->n[1][0] != 0 || sn->n[1][1] != 0 || sn->n[1][2] != 0 ||
                   sn->n[2][0] != 0 || sn->n[2][1] != 0 || sn->n[2][2] != 0))
        return 0;
    const float *q[3];
    for (int v = 0; v < 3; v++)
        q[v] = sn->n[flip && v ? 3 - v : v];
    float vn[9];
    if (!tri_normals(nm, q, p, vn))
        return -1;
    spm_sb_tri_normals(b, vn);
    return 1;
}

/* A triangle's tangents from the file, for its normal map (scene.h
 * tangents): each vertex's T through the statement's M, as a direction on
 * the surface, its handedness reversed by a mirror (mesh_import.c
 * face_tangents says why), the vertices in the order the triangle took.
 * None (made instead, geometry_nmap.c) where the file gives none for it, or
 * one that is not finite or zero, or a handedness that is not +-1. */
static void add_tangents(spm_scene_builder *b, const spm_mesh_tangents *ft, const double (*m)[4],
                         int flip)
{
    float t[12];
    for (int v = 0; v < 3; v++) {
        const float *q = ft->t[flip && v ? 3 - v : v];
        double len = 0;
        for (int i = 0; i < 3; i++) {
            t[4 * v + i] = (float)(m[i][0] * q[0] + m[i][1] * q[1] + m[i][2] * q[2]);
            len += (double)t[4 * v + i] * t[4 * v + i];
        }
        if (!(len > 0 && isfinite(len)) || (q[3] != 1.0f && q[3] != -1.0f))
            return;
        t[4 * v + 3] = flip ? -q[3] : q[3];
    }
    spm_sb_tri_tangents(b, t);
}

/* The statement's triangles, for the set-up's hints (scene_hints.h). */
static void record_mesh(spm_scene *s, const char *file, const char *where, int first,
                        const double lo[3], const double hi[3])
{
    s->meshes = spm_xrealloc(s->meshes, ((size_t)s->nmeshes + 1) * sizeof *s->meshes);
    spm_scene_mesh *m = &s->meshes[s->nmeshes++];
    const char *base = strrchr(file, '/');
    snprintf(m->name, sizeof m->name, "%.63s", base ? base + 1 : file);
    snprintf(m->where, sizeof m->where, "%.127s", where);
    m->first = first;
    m->n = s->ntris - first;
    for (int i = 0; i < 3; i++) {
        m->lo[i] = (float)lo[i];
        m->hi[i] = (float)hi[i];
    }
}

/* the box lo..hi grown to hold the triangle's corners f */
static void grow_box(double lo[3], double hi[3], float f[3][3])
{
    for (int v = 0; v < 3; v++)
        for (int i = 0; i < 3; i++) {
            lo[i] = fmin(lo[i], f[v][i]);
            hi[i] = fmax(hi[i], f[v][i]);
        }
}

/* What the file held that is not rendered: once per run and feature (nearly
 * every model has vertex normals), and a glTF's extensions per statement. */
static void warn_ignored(const spm_mesh_data *d, const spm_mesh_opts *o, int any_smooth,
                         const char *where, const char *file)
{
    static uint32_t said;
    uint32_t ignored = d->ignored;
    if (d->normals && !any_smooth && o->shading != SPM_MESH_SHADE_FLAT)
        ignored |= SPM_MESH_IGN_NORMALS;
    for (int bit = 0; bit < SPM_MESH_IGN_COUNT; bit++)
        if (ignored & ~said & (1u << bit))
            spm_warnf("%s: %s: %s ignored (%s; said once per run)", where, file,
                      spm_mesh_ignored_name(bit),
                      bit == 0 ? "diffuse materials shade flat unless the mesh statement says "
                                 "'smooth'"
                               : "not rendered");
    said |= ignored;
    if (d->extensions[0])
        spm_warnf("%s: %s: glTF extension%s %s not rendered (specmip leaves %s effect out)",
                  where, file, strchr(d->extensions, ',') ? "s" : "", d->extensions,
                  strchr(d->extensions, ',') ? "their" : "its");
}

int spm_mesh_add(spm_scene_builder *b, spm_mesh_cache *cache, const spm_mesh_data *d,
                 const spm_mesh_opts *o, const char *file, const char *where, spm_error *err)
{
    if ((uint64_t)b->s->ntris + d->ntris > SPM_SCENE_MAX_TRIS) {
        spm_errorf(err, "%s: %s: %llu triangles: more than %d in the scene", where, file,
                   (unsigned long long)d->ntris, SPM_SCENE_MAX_TRIS);
        return 1;
    }
    int *map = spm_xmalloc(((size_t)d->nmats + 1) * sizeof *map);
    if (bind_materials(b, cache, d, o, file, where, map, err)) {
        free(map);
        return 1;
    }
    const double (*m)[4] = o->m;
    double det = det3(m);
    int flip = det < 0; /* a mirror keeps each face's front side */
    double nm[3][3];
    normal_matrix(m, det, nm);
    uint64_t skipped = 0, kept = 0, smooth = 0, unusable = 0, made = 0;
    spm_mesh_normals *computed = NULL;
    if (o->shading == SPM_MESH_SHADE_SMOOTH && o->crease > 0)
        computed = spm_mesh_smooth_normals(d, o->m, o->crease, &made);
    const spm_mesh_normals *normals = computed ? computed : d->normals;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    int rc = 0, first = b->s->ntris;
    for (uint64_t t = 0; t < d->ntris && !rc; t++) {
        if ((t & 0xffff) == 0 && spm_stop_requested()) {
            spm_errorf(err, "interrupted while loading %s", file);
            rc = 1;
            break;
        }
        const spm_mesh_tri *src = &d->tris[t];
        double p[3][3];
        for (int v = 0; v < 3; v++) {
            const float *q = src->p[flip && v ? 3 - v : v];
            if (!finite3(q)) {
                spm_errorf(err, "%s: %s: triangle %llu has a coordinate that is not a finite "
                                "number", where, file, (unsigned long long)t + 1);
                rc = 1;
                break;
            }
            for (int i = 0; i < 3; i++)
                p[v][i] = m[i][0] * q[0] + m[i][1] * q[1] + m[i][2] * q[2] + m[i][3];
        }
        if (rc)
            break;
        float f[3][3];
        int far = 0;
        for (int v = 0; v < 3; v++)
            for (int i = 0; i < 3; i++) {
                far |= !(fabs(p[v][i]) <= SPM_SCENE_MAX_COORD);
                f[v][i] = (float)p[v][i];
            }
        if (!far && spm_sb_degenerate(f)) {
            skipped++;
            continue;
        }
        if (spm_sb_tri(b, p, map[src->mat], o->line, where, err)) {
            spm_error inner = *err;
            spm_errorf(err, "%.600s (%.300s, triangle %llu, after the transform)", inner.msg,
                       file, (unsigned long long)t + 1);
            rc = 1;
            break;
        }
        kept++;
        const spm_scene_material *sm = &b->s->materials[map[src->mat]];
        if (sm->tex || sm->etex || sm->alpha_map || sm->mix_mmap || sm->mix_rmap || sm->nmap) {
            float uv[6] = {0, 0, 0, 0, 0, 0};
            for (int v = 0; v < 3 && d->uvs; v++)
                memcpy(uv + 2 * v, d->uvs[t].uv[flip && v ? 3 - v : v], sizeof(float[2]));
            spm_sb_tri_uv(b, uv);
        }
        if (sm->nmap && d->tangents)
            add_tangents(b, &d->tangents[t], m, flip);
        int r = add_normals(b, o, normals ? &normals[t] : NULL, map[src->mat], nm, flip, p);
        smooth += r > 0;
        unusable += r < 0;
        grow_box(lo, hi, f);
    }
    free(map);
    free(computed);
    if (rc)
        return 1;
    if (kept == 0) {
        spm_errorf(err, "%s: %s: all of its %llu triangles are degenerate", where, file,
                   (unsigned long long)d->ntris);
        return 1;
    }
    if (skipped)
        spm_warnf("%s: %s: %llu degenerate triangle%s skipped (zero area: vertices that "
                  "coincide or lie on one line)", where, file, (unsigned long long)skipped,
                  skipped == 1 ? "" : "s");
    if (unusable)
        spm_warnf("%s: %s: %llu triangle%s shade flat: a vertex normal is zero or not a finite "
                  "number, or the three are perpendicular to the face", where, file,
                  (unsigned long long)unusable, unusable == 1 ? "" : "s");
    if (made)
        spm_notef("%s: %s: 'smooth': vertex normals computed for %llu triangle%s the file "
                  "gives none (crease %g degrees)", where, file, (unsigned long long)made,
                  made == 1 ? "" : "s", o->crease);
    warn_ignored(d, o, smooth || unusable, where, file);
    if (spm_mesh_add_lights(b, cache, d, o, file, where, err))
        return 1;
    record_mesh(b->s, file, where, first, lo, hi);
    spm_notef("%s: %s: %llu triangles, bounding box (%g %g %g) to (%g %g %g)", where, file,
              (unsigned long long)kept, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    return 0;
}
