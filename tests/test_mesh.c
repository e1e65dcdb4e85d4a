/* Meshes: every format tools/gen_meshes.py writes imports to the same
 * triangles (glTF's node hierarchy flattened); the importer's failures are
 * errors naming the file (bad files, a crash, the memory limit); the child's
 * answer is checked before use; binding, the statement's transform, mirroring
 * and degenerate filtering. */
#include "mesh.h"
#include "materials.h"
#include "rgb2spec.h"
#include "testutil.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[256];

typedef struct {
    float v[9];
} tri9;

/* Rotate so the smallest vertex comes first (keeps the winding), for sorting. */
static void canon(tri9 *t)
{
    int best = 0;
    for (int i = 1; i < 3; i++)
        {
            const float *a = &t->v[3 * i], *b = &t->v[3 * best];
            int less = a[0] != b[0] ? a[0] < b[0] : a[1] != b[1] ? a[1] < b[1] : a[2] < b[2];
            if (less)
                best = i;
        }
    tri9 r;
    for (int i = 0; i < 9; i++)
        r.v[i] = t->v[(3 * best + i) % 9];
    *t = r;
}

static int cmp_tri(const void *a, const void *b)
{
    const float *x = ((const tri9 *)a)->v, *y = ((const tri9 *)b)->v;
    for (int i = 0; i < 9; i++)
        if (x[i] != y[i])
            return x[i] < y[i] ? -1 : 1;
    return 0;
}

static size_t read_tris(const char *name, tri9 *out, size_t cap)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    size_t n = 0;
    while (f && n < cap) {
        tri9 t;
        int k = 0;
        for (; k < 9 && fscanf(f, "%f", &t.v[k]) == 1; k++)
            ;
        if (k < 9)
            break;
        canon(&t);
        out[n++] = t;
    }
    if (f)
        fclose(f);
    qsort(out, n, sizeof *out, cmp_tri);
    return n;
}

static int import(const char *name, spm_mesh_data *d, spm_error *err)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    spm_file file; /* as a scene in that folder names it */
    return spm_paths_set_root(path, &file, err) || spm_mesh_import(&file, d, err);
}

/* The file's triangles equal the expected ones to `tol` (0: bit for bit). */
static void check_same(const char *name, const char *expected, double tol)
{
    tri9 want[64], got[64];
    size_t n = read_tris(expected, want, 64);
    spm_mesh_data d;
    spm_error err;
    if (import(name, &d, &err)) {
        CHECK(0, "%s imports: %s", name, err.msg);
        return;
    }
    CHECK(d.ntris == n, "%s: %llu triangles, expected %zu", name, (unsigned long long)d.ntris,
          n);
    size_t m = d.ntris < 64 ? d.ntris : 64;
    for (size_t i = 0; i < m; i++) {
        memcpy(got[i].v, d.tris[i].p, sizeof got[i].v);
        canon(&got[i]);
    }
    qsort(got, m, sizeof *got, cmp_tri);
    double worst = 0;
    for (size_t i = 0; i < m && i < n; i++)
        for (int k = 0; k < 9; k++)
            worst = fmax(worst, fabs((double)got[i].v[k] - want[i].v[k]));
    CHECK(worst <= tol, "%s: triangles differ from %s by %g", name, expected, worst);
    spm_mesh_free(&d);
}

/* The +x and -x faces (4 triangles) are 'red', the rest 'white'. */
static void check_materials(const char *name)
{
    spm_mesh_data d;
    spm_error err;
    if (import(name, &d, &err)) {
        CHECK(0, "%s imports: %s", name, err.msg);
        return;
    }
    int red = 0, white = 0, wrong = 0;
    for (uint64_t t = 0; t < d.ntris; t++) {
        const spm_mesh_material *m = &d.mats[d.tris[t].mat];
        int side = d.tris[t].p[0][0] == d.tris[t].p[1][0] && d.tris[t].p[1][0] == d.tris[t].p[2][0];
        if (!strcmp(m->name, "red") && m->diffuse[0] == 0.8f && m->diffuse[1] == 0.1f)
            red++, wrong += !side;
        else if (!strcmp(m->name, "white") && m->diffuse[0] == 0.7f && m->diffuse[2] == 0.7f)
            white++, wrong += side;
        else
            wrong++;
    }
    CHECK(red == 4 && white == 8 && wrong == 0, "%s: %d red, %d white, %d wrong", name, red,
          white, wrong);
    spm_mesh_free(&d);
}

static void check_fails(const char *name, const char *needle)
{
    spm_mesh_data d;
    spm_error err;
    int rc = import(name, &d, &err);
    CHECK(rc != 0, "%s is refused", name);
    if (rc) {
        CHECK(strstr(err.msg, name) != NULL, "the error names %s: %s", name, err.msg);
        CHECK(!needle || strstr(err.msg, needle), "the error says '%s': %s", needle, err.msg);
    } else {
        spm_mesh_free(&d);
    }
}

static void write_file(const char *name, const void *data, size_t n)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    fwrite(data, 1, n, f);
    fclose(f);
}

/* ---- PLY triangle strips (mesh_ply.c) ---- */

/* Two files import to the same triangles, bit for bit and winding kept. */
static void check_same_files(const char *a, const char *b)
{
    spm_mesh_data d[2];
    spm_error err;
    const char *names[2] = {a, b};
    tri9 *t[2] = {NULL, NULL};
    for (int f = 0; f < 2; f++) {
        if (import(names[f], &d[f], &err)) {
            CHECK(0, "%s imports: %s", names[f], err.msg);
            if (f)
                spm_mesh_free(&d[0]);
            free(t[0]);
            return;
        }
        t[f] = malloc((d[f].ntris + 1) * sizeof *t[f]);
        for (uint64_t i = 0; i < d[f].ntris; i++) {
            memcpy(t[f][i].v, d[f].tris[i].p, sizeof t[f][i].v);
            canon(&t[f][i]);
        }
        qsort(t[f], d[f].ntris, sizeof *t[f], cmp_tri);
    }
    CHECK(d[0].ntris == d[1].ntris && d[0].ntris > 100, "%s: %llu triangles, %s: %llu", a,
          (unsigned long long)d[0].ntris, b, (unsigned long long)d[1].ntris);
    uint64_t differ = 0;
    for (uint64_t i = 0; i < d[0].ntris && i < d[1].ntris; i++)
        differ += cmp_tri(&t[0][i], &t[1][i]) != 0;
    CHECK(differ == 0, "%s and %s: %llu triangles differ", a, b, (unsigned long long)differ);
    for (int f = 0; f < 2; f++) {
        free(t[f]);
        spm_mesh_free(&d[f]);
    }
}

/* A bad strips file: refused, the error naming the file, where (needle) and what. */
static void check_ply_bad(const char *name, const char *body, const char *where,
                          const char *what)
{
    char text[2048];
    snprintf(text, sizeof text,
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
             "end_header\n%s", body);
    write_file(name, text, strlen(text));
    check_fails(name, where);
    check_fails(name, what);
}

static void check_strips(void)
{
    check_same("cube_strips.ply", "cube.tris", 0);
    check_same("cube_strips_be.ply", "cube.tris", 0);
    /* the same height field as faces (through Assimp) and as strips (ours) */
    check_same_files("grid_strips.ply", "grid_faces.ply");
    const char *v = "0 0 0\n1 0 0\n0 1 0\n";
    char body[256];
    snprintf(body, sizeof body, "%s4 0 1 2 7\n", v);
    check_ply_bad("strip_range.ply", body, "strip_range.ply:13: element tristrips item 1",
                  "vertex index 7 is out of range (3 vertices");
    snprintf(body, sizeof body, "%s4 0 1 2 -2\n", v);
    check_ply_bad("strip_negative.ply", body, ":13: element tristrips", "vertex index -2");
    snprintf(body, sizeof body, "%s5 0 1 2\n", v);
    check_ply_bad("strip_short.ply", body, "strip_short.ply:", "the file ends");
    snprintf(body, sizeof body, "0 0 0\n1 zero 0\n");
    check_ply_bad("strip_word.ply", body, "strip_word.ply:11: element vertex item 2",
                  "'zero' is not a float");
    snprintf(body, sizeof body, "%s3 0 1 1\n", v);
    check_ply_bad("strip_degenerate.ply", body, "strip_degenerate.ply", "no triangles");
    static const char hdr[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty quad z\nelement tristrips 1\n"
                              "property list int int vertex_indices\nend_header\n";
    write_file("strip_type.ply", hdr, sizeof hdr - 1);
    check_fails("strip_type.ply", "strip_type.ply:6: unknown property type 'quad'");
    /* binary: the element, item and byte offset */
    static const char bin[] = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
                              "property uchar x\nproperty uchar y\nproperty uchar z\n"
                              "element tristrips 1\nproperty list uchar uchar vertex_indices\n"
                              "end_header\n\1\2\3\3\0\0\x09";
    write_file("strip_bin.ply", bin, sizeof bin - 1);
    char want[128];
    snprintf(want, sizeof want, "element tristrips item 1 (byte %d): vertex index 9",
             (int)(sizeof bin - 1));
    check_fails("strip_bin.ply", want);
}

/* A PLY face of more than three vertices goes to Assimp's triangulation
 * (mesh_ply.h): a concave quad (its vertex 3 reflex) comes out as two
 * triangles covering its area of 1.5, where a fan from vertex 0 would cover
 * 2.5 (its first triangle spans the notch). */
static void check_ply_polygons(void)
{
    static const char quad[] = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                               "property float y\nproperty float z\nelement face 1\n"
                               "property list uchar int vertex_indices\nend_header\n"
                               "0 0 0\n2 1 0\n0 2 0\n0.5 1 0\n4 0 1 2 3\n";
    write_file("concave.ply", quad, sizeof quad - 1);
    spm_mesh_data d;
    spm_error err;
    int rc = import("concave.ply", &d, &err);
    CHECK(rc == 0 && d.ntris == 2, "the concave quad imports as two triangles (rc %d: %s)", rc,
          rc ? err.msg : "");
    if (rc)
        return;
    double area = 0;
    for (uint64_t t = 0; t < d.ntris; t++) {
        const float(*p)[3] = d.tris[t].p;
        area += 0.5 * fabs((double)(p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                           (double)(p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
    }
    CHECK(fabs(area - 1.5) < 1e-6, "its triangles cover the quad's area 1.5 (got %g)", area);
    spm_mesh_free(&d);
}

/* ---- textured materials: the mean colour ---- */

/* The textured 'red' of NAME: its colour is the factor (0.9 0.6 0.3, as
 * gen_meshes.py writes it) times tex.mean (the mean of the texture's decoded
 * pixels, computed there in double precision), or the factor alone when
 * mean_used is 0; 'white' has no texture and keeps 0.7. */
static void check_textured(const char *name, int mean_used, const char *tex_name)
{
    static const float factor[3] = {0.9f, 0.6f, 0.3f};
    double mean[3] = {1, 1, 1};
    char path[512];
    snprintf(path, sizeof path, "%s/tex.mean", dir);
    FILE *f = fopen(path, "r");
    int got = f ? fscanf(f, "%lf %lf %lf", &mean[0], &mean[1], &mean[2]) : 0;
    if (f)
        fclose(f);
    CHECK(got == 3, "tex.mean read");
    spm_mesh_data d;
    spm_error err;
    if (import(name, &d, &err)) {
        CHECK(0, "%s imports: %s", name, err.msg);
        return;
    }
    int red = 0, white = 0;
    for (uint32_t i = 0; i < d.nmats; i++) {
        const spm_mesh_material *m = &d.mats[i];
        if (!strcmp(m->name, "red")) {
            red++;
            CHECK(m->texture == (mean_used ? SPM_MESH_TEX_MEAN : SPM_MESH_TEX_UNREAD) &&
                      !strcmp(m->texture_name, tex_name),
                  "%s: red's texture: state %d, '%s' (want '%s')", name, (int)m->texture,
                  m->texture_name, tex_name);
            for (int c = 0; c < 3; c++) {
                double want = factor[c] * (mean_used ? mean[c] : 1.0);
                /* 1e-6: the float mean and the float product round at 6e-8
                 * relative each; measured: at most 1.2e-7 */
                CHECK(fabs(m->diffuse[c] - want) <= 1e-6 * want,
                      "%s: red's colour %d: %.9g, want %.9g", name, c, m->diffuse[c], want);
            }
        } else if (!strcmp(m->name, "white")) {
            white++;
            CHECK(m->texture == SPM_MESH_TEX_NONE && m->diffuse[0] == 0.7f &&
                      m->diffuse[2] == 0.7f,
                  "%s: white untextured (state %d, %g)", name, (int)m->texture, m->diffuse[0]);
        }
    }
    CHECK(red == 1 && white >= 1, "%s: materials red (%d) and white (%d)", name, red, white);
    CHECK(!(d.ignored & SPM_MESH_IGN_TEXTURES), "%s: no other texture said ignored", name);
    spm_mesh_free(&d);
}

/* ---- vertex normals ---- */

/* The sphere of gen_meshes.py (sphere_n.*): every vertex's normal is its
 * position, so the imported normal, made unit, is unit(S^-2 p) for a file whose
 * node scales the sphere by S (glTF: S = diag(1, 2, 1): the inverse transpose
 * of S maps the normals, so n' = S^-1 n = S^-2 p'). A vertex's normal is
 * written as the same floats as its position and S's entries are powers of
 * two, so the expected normal is exact (measured: 0 in every format); the
 * bound, 1e-5 rad, is a few float ulps of Assimp's float matrix products. */
static void check_normals(const char *name, double sy)
{
    spm_mesh_data d;
    spm_error err;
    if (import(name, &d, &err)) {
        CHECK(0, "%s: %s", name, err.msg);
        return;
    }
    CHECK(d.normals != NULL, "%s: vertex normals imported", name);
    CHECK(d.ntris == 224, "%s: 224 triangles (%llu)", name, (unsigned long long)d.ntris);
    CHECK(!(d.ignored & SPM_MESH_IGN_NORMALS), "%s: normals not counted as ignored", name);
    double worst = 0;
    for (uint64_t t = 0; d.normals && t < d.ntris; t++)
        for (int v = 0; v < 3; v++) {
            const float *p = d.tris[t].p[v], *n = d.normals[t].n[v];
            double w[3] = {p[0], p[1] / (sy * sy), p[2]}, dot = 0, cr[3];
            for (int i = 0; i < 3; i++)
                dot += w[i] * n[i];
            cr[0] = w[1] * n[2] - w[2] * n[1];
            cr[1] = w[2] * n[0] - w[0] * n[2];
            cr[2] = w[0] * n[1] - w[1] * n[0];
            worst = fmax(worst, atan2(sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]), dot));
        }
    printf("%s: worst normal angle %.3g rad\n", name, worst);
    CHECK(worst < 1e-5, "%s: normals off by %.3g rad", name, worst);
    spm_mesh_free(&d);
}

/* ---- materials of mesh files (mesh_pbr.c) ---- */

static const spm_scene_material *find_mat(const spm_scene *s, const char *name)
{
    for (int i = 0; i < s->nmaterials; i++)
        if (!strcmp(s->materials[i].name, name))
            return &s->materials[i];
    return NULL;
}

/* A conductor's normal-incidence reflectance, the exact Fresnel of its eta
 * and k per 1 nm bin, against the file's F0: ΔE00 under D65 between that
 * reflectance and the RGB. The lift of the RGB to a spectrum is a fit
 * (rgb2spec.c) and F0 is clamped to 0.999 per bin (mesh_pbr.c): measured
 * ΔE00 1.6e-6 (gold, 1 0.78 0.34), 1e-6 (steel), 2.5e-6 (copper's Ks);
 * bound 0.01, far below a visible difference (1). */
static void check_f0(const spm_scene *s, const spm_scene_material *m, const double rgb[3],
                     double alpha, const char *what)
{
    CHECK(m && m->type == SPM_MAT_CONDUCTOR, "%s: a conductor", what);
    if (!m || m->type != SPM_MAT_CONDUCTOR)
        return;
    CHECK(fabs(m->p[SPM_COND_P_ALPHA] - alpha) < 1e-6, "%s: alpha %g, not %g", what,
          m->p[SPM_COND_P_ALPHA], alpha);
    spm_spectrum f;
    f.kind = SPM_KIND_REFLECTANCE;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        f.nm1[i] = spm_conductor_fresnel(s->colours[m->refl].s.nm1[i], s->colours[m->col2].s.nm1[i],
                                         1.0);
    double de = spm_rgb2spec_delta_e(&f, rgb);
    printf("%s: normal-incidence reflectance vs F0 (%g %g %g): ΔE00 %.3g\n", what, rgb[0], rgb[1],
           rgb[2], de);
    CHECK(de < 0.01, "%s: F0 off by ΔE00 %.3g", what, de);
}

static void check_pbr(void)
{
    const char *files[2] = {"metal.gltf", "metal.obj"};
    for (int fi = 0; fi < 2; fi++) {
        spm_mesh_data d;
        spm_error err;
        if (import(files[fi], &d, &err)) {
            CHECK(0, "%s: %s", files[fi], err.msg);
            continue;
        }
        char path[512];
        snprintf(path, sizeof path, "%s/%s", dir, files[fi]);
        spm_file file;
        CHECK(spm_paths_set_root(path, &file, &err) == 0, "%s", err.msg);
        spm_mesh_obj_mtl_check(&file, "t", &d);
        spm_scene s;
        spm_scene_builder b;
        spm_mesh_cache cache;
        spm_sb_init(&b, &s, "<test>");
        spm_mesh_cache_init(&cache);
        spm_mesh_opts o;
        memset(&o, 0, sizeof o);
        o.material = -1;
        spm_mesh_identity(o.m);
        int rc = spm_mesh_add(&b, &cache, &d, &o, files[fi], "t", &err);
        CHECK(rc == 0, "%s maps: %s", files[fi], rc ? err.msg : "");
        if (fi == 0 && !rc) {
            const double gold[3] = {1.0, 0.78, 0.34}, steel[3] = {0.56, 0.57, 0.58};
            check_f0(&s, find_mat(&s, "gold"), gold, 0.0, "glTF gold (metallic 1, roughness 0)");
            check_f0(&s, find_mat(&s, "steel"), steel, 0.25, "glTF steel (roughness 0.5: alpha 0.25)");
            const spm_scene_material *h = find_mat(&s, "half"), *g = find_mat(&s, "glass");
            CHECK(h && h->type == SPM_MAT_COATED, "glTF metallic 0.3: coated (below 0.5)");
            CHECK(g && g->type == SPM_MAT_DIELECTRIC, "glTF transmission 1: dielectric");
        }
        if (fi == 1 && !rc) {
            const double cu[3] = {0.95, 0.64, 0.54};
            check_f0(&s, find_mat(&s, "copper"), cu, sqrt(2.0 / 202.0),
                     "MTL copper (Kd 0, Ks, Ns 200)");
            const spm_scene_material *p = find_mat(&s, "paint");
            CHECK(p && p->type == SPM_MAT_COATED, "MTL Kd with Ks: coated");
        }
        spm_mesh_cache_free(&cache);
        spm_sb_done(&b, 0);
        spm_mesh_free(&d);
    }
    /* Gulbrandsen's n, k at a grey F0 of 0.5: ((n-1)^2 + k^2) / ((n+1)^2 + k^2) = 0.5 */
    spm_spectrum f0, eta, k;
    spm_spectrum_constant(0.5, SPM_KIND_REFLECTANCE, &f0);
    spm_mesh_gulbrandsen(&f0, &eta, &k);
    double n = eta.nm1[0], kk = k.nm1[0];
    CHECK(fabs(((n - 1) * (n - 1) + kk * kk) / ((n + 1) * (n + 1) + kk * kk) - 0.5) < 1e-12,
          "Gulbrandsen's n %g, k %g give F0 0.5", n, kk);
}

/* The scene a generated file maps to, its statement scaled by `scale`. */
static int map_file(const char *name, double scale, spm_scene *s)
{
    spm_mesh_data d;
    spm_error err;
    if (import(name, &d, &err)) {
        CHECK(0, "%s: %s", name, err.msg);
        return 1;
    }
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    spm_file file;
    CHECK(spm_paths_set_root(path, &file, &err) == 0, "%s", err.msg);
    spm_mesh_obj_mtl_check(&file, "t", &d);
    spm_scene_builder b;
    spm_mesh_cache cache;
    spm_sb_init(&b, s, "<test>");
    spm_mesh_cache_init(&cache);
    spm_mesh_opts o;
    memset(&o, 0, sizeof o);
    o.material = -1;
    spm_mesh_identity(o.m);
    const double sc[3] = {scale, scale, scale};
    spm_mesh_scale(o.m, sc);
    int rc = spm_mesh_add(&b, &cache, &d, &o, name, "t", &err);
    CHECK(rc == 0, "%s maps: %s", name, rc ? err.msg : "");
    spm_mesh_cache_free(&cache);
    spm_sb_done(&b, rc == 0);
    spm_mesh_free(&d);
    return rc;
}

/* A material's type, index and GGX width against the file's values (the
 * width from the file's roughness or Ns by the table's formula, computed
 * here). */
static void check_glassy(const spm_scene_material *m, int type, double ior, double alpha,
                         const char *what)
{
    CHECK(m && m->type == type, "%s: type %d, not %d", what, m ? m->type : -1, type);
    if (!m || m->type != type)
        return;
    int pi = type == SPM_MAT_DIELECTRIC ? SPM_DIEL_P_IOR : SPM_COAT_P_ETA;
    int pa = type == SPM_MAT_DIELECTRIC ? SPM_DIEL_P_ALPHA : SPM_COAT_P_ALPHA;
    /* the file's floats: 1e-6 relative holds their rounding */
    CHECK(fabs(m->p[pi] - ior) <= 1e-6 * ior, "%s: ior %.9g, not %.9g", what, m->p[pi], ior);
    CHECK(fabs(m->p[pa] - alpha) <= 1e-6, "%s: alpha %.9g, not %.9g", what, m->p[pa], alpha);
}

/* A coated material's base: the file's colour lifted (the same fit of the
 * file's float values, bin by bin within 1e-6: the fit is iterative and the
 * import's lift lands within 2.3e-8 of this one, measured) and, independently
 * of the fit, within ΔE00 0.01 of the RGB under D65 (the fit's residual is
 * ~1e-6, check_f0's). */
static void check_base(const spm_scene *s, const spm_scene_material *m, const double rgb[3],
                       const char *what)
{
    if (!m || m->type != SPM_MAT_COATED)
        return;
    CHECK(m->refl >= 0, "%s: a base colour", what);
    if (m->refl < 0)
        return;
    spm_spectrum want;
    spm_error err;
    const double rgbf[3] = {(float)rgb[0], (float)rgb[1], (float)rgb[2]};
    CHECK(spm_rgb_to_reflectance(rgbf, &want, NULL, &err) == 0, "lift: %s", err.msg);
    double worst = 0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        worst = fmax(worst, fabs(s->colours[m->refl].s.nm1[i] - want.nm1[i]));
    double de = spm_rgb2spec_delta_e(&s->colours[m->refl].s, rgb);
    printf("%s: base colour vs the lifted RGB %g %g %g: %.3g at most, ΔE00 %.3g\n", what, rgb[0],
           rgb[1], rgb[2], worst, de);
    CHECK(worst <= 1e-6, "%s: base colour off the lifted RGB by %g", what, worst);
    CHECK(de < 0.01, "%s: base colour off the RGB by ΔE00 %g", what, de);
}

/* The rows of docs/SCENE_FORMAT.md's mesh-material table on pbr.gltf and
 * pbr.obj (tools/gen_meshes.py), each against the file's numbers; the glTF
 * statement scaled by 3, so its attenuation distance 2 is 6 scene units. */
static void check_pbr_rows(void)
{
    spm_scene s;
    const double scale = 3.0;
    if (!map_file("pbr.gltf", scale, &s)) {
        const spm_scene_material *m = find_mat(&s, "solid");
        check_glassy(m, SPM_MAT_DIELECTRIC, 1.33, 0.3 * 0.3, "glTF solid (transmission 1, ior 1.33, roughness 0.3)");
        /* absorb: T(lambda) over the attenuation distance is the lifted
         * attenuation colour, so sigma = -ln(c(lambda)) / (2 scale) */
        const double atten[3] = {0.9f, 0.5f, 0.2f}; /* the file's floats */
        spm_spectrum c;
        spm_error err;
        CHECK(spm_rgb_to_reflectance(atten, &c, NULL, &err) == 0, "lift: %s", err.msg);
        CHECK(m && m->col2 >= 0, "glTF solid: absorbs");
        if (m && m->type == SPM_MAT_DIELECTRIC && m->col2 >= 0) {
            const int nm[] = {450, 550, 650};
            for (int i = 0; i < 3; i++) {
                int b = nm[i] - (int)SPM_LAMBDA_MIN;
                double want = -log(c.nm1[b]) / (2.0f * scale), got = s.colours[m->col2].s.nm1[b];
                printf("glTF solid: sigma(%d nm) %.9g per scene unit, -ln(c)/d %.9g\n", nm[i], got,
                       want);
                CHECK(fabs(got - want) <= 1e-9 * want, "glTF solid: sigma(%d nm) %.9g, not %.9g",
                      nm[i], got, want);
            }
            /* an orange attenuation colour passes red: sigma falls from blue to red */
            CHECK(s.colours[m->col2].s.nm1[650 - (int)SPM_LAMBDA_MIN] <
                      s.colours[m->col2].s.nm1[450 - (int)SPM_LAMBDA_MIN],
                  "glTF solid: sigma(650) below sigma(450)");
        }
        m = find_mat(&s, "thin");
        check_glassy(m, SPM_MAT_DIELECTRIC, 1.5, 0.0, "glTF thin (transmission 1, no volume)");
        CHECK(m && m->col2 < 0, "glTF thin: clear (no volume, no absorb)");
        check_glassy(find_mat(&s, "part"), SPM_MAT_DIELECTRIC, 1.5, 0.1 * 0.1,
                     "glTF transmission 0.7 (taken as 1), roughness 0.1");
        m = find_mat(&s, "low");
        check_glassy(m, SPM_MAT_COATED, 1.5, 0.0, "glTF transmission 0.3 (below 0.5: coated)");
        const double low[3] = {0.3, 0.6, 0.3}, plastic[3] = {0.2, 0.4, 0.8};
        check_base(&s, m, low, "glTF low");
        m = find_mat(&s, "plastic");
        check_glassy(m, SPM_MAT_COATED, 1.7, 0.6 * 0.6, "glTF plastic (metallic 0, roughness 0.6, ior 1.7)");
        check_base(&s, m, plastic, "glTF plastic");
        spm_scene_free(&s);
    }
    if (!map_file("pbr.obj", 1.0, &s)) {
        const spm_scene_material *m = find_mat(&s, "paint");
        check_glassy(m, SPM_MAT_COATED, 1.6, sqrt(2.0 / (50 + 2)), "MTL paint (Kd, Ks 0.04, Ns 50, Ni 1.6)");
        const double paint[3] = {0.5, 0.1, 0.1};
        check_base(&s, m, paint, "MTL paint");
        check_glassy(find_mat(&s, "glass"), SPM_MAT_DIELECTRIC, 1.45, sqrt(2.0 / (1000 + 2)),
                     "MTL glass (illum 7, Ni 1.45, Ns 1000)");
        m = find_mat(&s, "veil");
        CHECK(m && m->type == SPM_MAT_LAMBERT, "MTL veil (Kd, no Ks, d 0.5): diffuse, opaque");
        spm_scene_free(&s);
    }
}

/* ---- the answer's decoder ---- */

/* Embedded images after the lights: their bytes and hints as encoded, a
 * map's reference checked against their count, sizes against the total. */
static void check_decode_images(spm_mesh_data *d)
{
    static const unsigned char png[5] = {0x89, 'P', 'N', 'G', 1}, jpg[3] = {0xff, 0xd8, 0xff};
    spm_mesh_image imgs[3] = {{sizeof png, "png", png}, {0, "", NULL}, {sizeof jpg, "jpg", jpg}};
    spm_mesh_data out;
    spm_error err;
    size_t n;
    d->images = imgs;
    d->nimages = 3;
    d->mats[1].texture_embed = 3;
    d->mats[0].nmap_embed = 1;
    unsigned char *buf = spm_mesh_encode(d, &n);
    unsigned char *copy = spm_xmalloc(n);
    memcpy(copy, buf, n);
    CHECK(spm_mesh_decode(copy, n, "x", &out, &err) == 0 && out.nimages == 3 &&
              out.images[0].size == 5 && !memcmp(out.images[0].data, png, 5) &&
              out.images[1].size == 0 && !strcmp(out.images[2].hint, "jpg") &&
              out.images[2].size == 3 && !memcmp(out.images[2].data, jpg, 3) &&
              out.mats[1].texture_embed == 3 && out.nlights == 2 &&
              !strcmp(out.lights[1].name, "sun") && ((uintptr_t)out.images & 7) == 0,
          "embedded images decode as encoded, after the lights");
    spm_mesh_free(&out);
    uint32_t fields[] = {offsetof(spm_mesh_material, texture_embed),
                         offsetof(spm_mesh_material, etexture_embed),
                         offsetof(spm_mesh_material, mr_embed),
                         offsetof(spm_mesh_material, nmap_embed)};
    int32_t beyond = 4, negative = -1;
    for (size_t i = 0; i < 8; i++) {
        copy = spm_xmalloc(n);
        memcpy(copy, buf, n);
        memcpy(copy + SPM_MESH_WIRE_HEAD + fields[i / 2], i % 2 ? &negative : &beyond, 4);
        CHECK(spm_mesh_decode(copy, n, "x", &out, &err) != 0,
              "a map naming embedded image %d of 3 refused (field %zu)", i % 2 ? -1 : 4, i / 2);
        free(copy);
    }
    size_t at_images = n - sizeof png - sizeof jpg - 3 * sizeof(spm_mesh_image);
    uint64_t big = 7, total = 9;
    copy = spm_xmalloc(n);
    memcpy(copy, buf, n);
    memcpy(copy + at_images, &big, 8);
    CHECK(spm_mesh_decode(copy, n, "x", &out, &err) != 0, "image sizes over the total refused");
    free(copy);
    copy = spm_xmalloc(n);
    memcpy(copy, buf, n);
    memcpy(copy + 40, &total, 8);
    CHECK(spm_mesh_decode(copy, n, "x", &out, &err) != 0, "image bytes announced but not sent "
                                                          "refused");
    free(copy);
    free(buf);
    d->mats[1].texture_embed = d->mats[0].nmap_embed = 0;
    d->images = NULL;
    d->nimages = 0;
}

static void check_decode(void)
{
    spm_mesh_material mats[2] = {{.name = "a", .diffuse = {0.5f, 0.5f, 0.5f}, .emission = {0, 0, 0}},
                                 {.name = "b", .diffuse = {1, 0, 0}, .emission = {0, 0, 0}}};
    spm_mesh_tri tris[2] = {{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1}, {{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}, 0}};
    spm_mesh_data d = {0, 2, 2, mats, tris, NULL, NULL, NULL, "", NULL, 0, 0, NULL, NULL}, out;
    spm_error err;
    size_t n;
    unsigned char *buf = spm_mesh_encode(&d, &n);
    unsigned char *copy = spm_xmalloc(n);
    memcpy(copy, buf, n);
    CHECK(spm_mesh_decode(copy, n, "x", &out, &err) == 0 && out.ntris == 2 &&
              out.tris[0].mat == 1 && !strcmp(out.mats[1].name, "b"),
          "a well-formed answer decodes");
    spm_mesh_free(&out);
    struct {
        size_t off, len;
        uint64_t value;
        const char *what;
    } bad[] = {{0, 4, 0x12345678, "a bad magic"},
               {12, 4, 5000, "too many materials"},
               {16, 8, (uint64_t)1 << 40, "too many triangles"},
               {16, 8, 3, "a count that does not match the size"},
               {16, 8, 0, "no triangles"},
               {24, 4, 4, "an unknown flag"},
               {24, 4, SPM_MESH_WIRE_NORMALS, "normals announced but not sent"},
               {24, 4, SPM_MESH_WIRE_UVS, "texture coordinates announced but not sent"},
               {SPM_MESH_WIRE_HEAD + 2 * sizeof(spm_mesh_material) + offsetof(spm_mesh_tri, mat), 4, 2,
                "a material index out of range"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        copy = spm_xmalloc(n);
        memcpy(copy, buf, n);
        memcpy(copy + bad[i].off, &bad[i].value, bad[i].len);
        int rc = spm_mesh_decode(copy, n, "x", &out, &err);
        CHECK(rc != 0, "an answer with %s is refused", bad[i].what);
        free(copy);
    }
    copy = spm_xmalloc(n);
    memcpy(copy, buf, n);
    CHECK(spm_mesh_decode(copy, n - 1, "x", &out, &err) != 0, "a truncated answer is refused");
    free(copy);
    free(buf);
    /* texture coordinates after the normals, per triangle in order */
    spm_mesh_normals nrm[2] = {{{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}}, {{{0, 1, 0}, {0, 1, 0}, {0, 1, 0}}}};
    spm_mesh_uvs uvs[2] = {{{{0, 0}, {1, 0}, {0, 1}}}, {{{0.25f, 0.5f}, {0.75f, 0.5f}, {0.5f, 0.125f}}}};
    d.normals = nrm;
    d.uvs = uvs;
    buf = spm_mesh_encode(&d, &n);
    CHECK(spm_mesh_decode(buf, n, "x", &out, &err) == 0 && out.uvs && out.normals &&
              out.uvs[1].uv[2][1] == 0.125f && out.uvs[0].uv[1][0] == 1.0f &&
              out.normals[1].n[0][1] == 1.0f,
          "texture coordinates and normals decode as encoded");
    spm_mesh_free(&out);
    /* the file's tangents after the texture coordinates, the lights after them */
    spm_mesh_tangents tgs[2] = {{{{1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}}},
                                {{{0, 0, 1, -1}, {0, 0, 1, -1}, {0, 0.5f, 1, -1}}}};
    d.tangents = tgs;
    spm_mesh_light lamp = {.name = "lamp", .type = SPM_MESH_LIGHT_POINT};
    d.lights = &lamp;
    d.nlights = 1;
    buf = spm_mesh_encode(&d, &n);
    CHECK(n == spm_mesh_wire_size(2, 2, 7, 1, 0, 0) &&
              spm_mesh_decode(buf, n, "x", &out, &err) == 0 && out.tangents && out.uvs &&
              out.tangents[1].t[2][1] == 0.5f && out.tangents[1].t[0][3] == -1.0f &&
              out.uvs[1].uv[2][1] == 0.125f && out.nlights == 1 &&
              !strcmp(out.lights[0].name, "lamp"),
          "tangents decode as encoded, between the texture coordinates and the lights");
    spm_mesh_free(&out);
    d.tangents = NULL;
    d.lights = NULL;
    d.nlights = 0;
    /* lights after the texture coordinates; a bad type or a count not sent refused */
    spm_mesh_light lights[2] = {{.name = "lamp", .type = SPM_MESH_LIGHT_SPOT, .inner = 0.25f},
                                {.name = "sun", .type = SPM_MESH_LIGHT_DIRECTIONAL}};
    d.lights = lights;
    d.nlights = 2;
    buf = spm_mesh_encode(&d, &n);
    copy = spm_xmalloc(n);
    memcpy(copy, buf, n);
    CHECK(spm_mesh_decode(copy, n, "x", &out, &err) == 0 && out.nlights == 2 && out.uvs &&
              out.uvs[1].uv[2][1] == 0.125f && out.lights[0].inner == 0.25f &&
              !strcmp(out.lights[1].name, "sun"),
          "lights decode as encoded, after the texture coordinates");
    spm_mesh_free(&out);
    int32_t bad_type = 7;
    uint32_t more = 3;
    copy = spm_xmalloc(n);
    memcpy(copy, buf, n);
    size_t at_lights = SPM_MESH_WIRE_HEAD + 2 * (sizeof(spm_mesh_material) + sizeof(spm_mesh_tri) +
                                                 sizeof(spm_mesh_normals) + sizeof(spm_mesh_uvs));
    memcpy(copy + at_lights + sizeof(spm_mesh_light) + offsetof(spm_mesh_light, type), &bad_type,
           4);
    CHECK(spm_mesh_decode(copy, n, "x", &out, &err) != 0, "a light of an unknown type refused");
    free(copy);
    copy = spm_xmalloc(n);
    memcpy(copy, buf, n);
    memcpy(copy + 28, &more, 4);
    CHECK(spm_mesh_decode(copy, n, "x", &out, &err) != 0, "lights announced but not sent refused");
    free(copy);
    free(buf);
    check_decode_images(&d);
}

/* ---- building ---- */

typedef struct {
    spm_scene s;
    spm_scene_builder b;
    spm_mesh_cache cache;
    int grey, lamp;
} bscene;

static void bs_open(bscene *x)
{
    spm_sb_init(&x->b, &x->s, "<test>");
    spm_mesh_cache_init(&x->cache);
    spm_spectrum sp;
    spm_error err;
    spm_spectrum_constant(0.5, SPM_KIND_REFLECTANCE, &sp);
    int c = spm_sb_colour(&x->b, "grey", &sp, "t", &err);
    x->grey = spm_sb_material(&x->b, "grey", c, -1, "t", &err);
    spm_spectrum_constant(1.0, SPM_KIND_EMISSION, &sp);
    c = spm_sb_colour(&x->b, "lamp", &sp, "t", &err);
    x->lamp = spm_sb_material(&x->b, "lamp", -1, c, "t", &err);
}

static void bs_close(bscene *x)
{
    spm_mesh_cache_free(&x->cache);
    spm_sb_done(&x->b, 0);
}

static void identity(spm_mesh_opts *o)
{
    double one[3] = {1, 1, 1}, axis[3] = {0, 0, 1}, zero[3] = {0, 0, 0};
    memset(o, 0, sizeof *o);
    o->material = -1;
    spm_mesh_transform(one, axis, 0, zero, o->m);
}

/* The statement's transform maps vertex normals by its inverse transpose and
 * a mirror's reversed winding takes them along; they are stored unit length,
 * turned to the front face; `smooth` makes a diffuse mesh smooth, which by
 * default (and with `flat`) it is not. */
static void check_build_normals(void)
{
    spm_mesh_material mats[1] = {{.name = "a", .diffuse = {0.5f, 0.5f, 0.5f}}};
    spm_mesh_tri tris[1] = {{{{1, 0, 0}, {1, 1, 0}, {1, 0, 1}}, 0}}; /* front face +x */
    spm_mesh_normals nrm[1] = {{{{1, 1, 0}, {1, 0, 0}, {1, 0, 1}}}};
    spm_mesh_data d = {0, 1, 1, mats, tris, nrm, NULL, NULL, "", NULL, 0, 0, NULL, NULL};
    spm_error err;
    spm_quiet_warnings = 1;
    struct {
        double s[3];
        int shading, expect;
        float want[9]; /* before normalising */
    } cases[] = {
        {{1, 3, 1}, SPM_MESH_SHADE_SMOOTH, 1, {1, 1.0f / 3, 0, 1, 0, 0, 1, 0, 1}},
        {{-1, 1, 1}, SPM_MESH_SHADE_SMOOTH, 1, {-1, 1, 0, -1, 0, 1, -1, 0, 0}}, /* v1, v2 swapped */
        {{1, 1, 1}, SPM_MESH_SHADE_DEFAULT, 0, {0}},
        {{1, 1, 1}, SPM_MESH_SHADE_FLAT, 0, {0}}};
    for (int c = 0; c < 4; c++) {
        bscene x;
        bs_open(&x);
        spm_mesh_opts o;
        identity(&o);
        spm_mesh_scale(o.m, cases[c].s);
        o.material = x.grey;
        o.shading = cases[c].shading;
        int rc = spm_mesh_add(&x.b, &x.cache, &d, &o, "m", "t", &err);
        CHECK(rc == 0 && x.s.ntris == 1, "case %d loads", c);
        CHECK((x.s.nvnormals == 1) == cases[c].expect && (x.s.tris[0].vn != 0) == cases[c].expect,
              "case %d: %s", c, cases[c].expect ? "smooth" : "flat");
        double worst = 0;
        for (int v = 0; v < 3 && cases[c].expect && x.s.nvnormals == 1; v++) {
            const float *w = &cases[c].want[3 * v], *n = &x.s.vnormals[0][3 * v];
            double lw = sqrt((double)w[0] * w[0] + (double)w[1] * w[1] + (double)w[2] * w[2]);
            for (int i = 0; i < 3; i++)
                worst = fmax(worst, fabs(n[i] - w[i] / lw));
        }
        /* float normals of double arithmetic: a few ulps */
        CHECK(worst < 1e-6, "case %d: normals off by %.3g", c, worst);
        bs_close(&x);
    }
    /* normals against the winding: turned to the front face */
    spm_mesh_normals back[1] = {{{{-1, 0, 0}, {-1, 0, 0}, {-1, 0, 0}}}};
    spm_mesh_data db = {0, 1, 1, mats, tris, back, NULL, NULL, "", NULL, 0, 0, NULL, NULL};
    bscene x;
    bs_open(&x);
    spm_mesh_opts o;
    identity(&o);
    o.material = x.grey;
    o.shading = SPM_MESH_SHADE_SMOOTH;
    int rc = spm_mesh_add(&x.b, &x.cache, &db, &o, "m", "t", &err);
    CHECK(rc == 0 && x.s.nvnormals == 1 && x.s.vnormals[0][0] == 1.0f && x.s.vnormals[0][3] == 1.0f &&
              x.s.vnormals[0][6] == 1.0f,
          "normals against the winding are turned to the front face");
    bs_close(&x);
    /* a zero normal: that triangle is flat */
    spm_mesh_normals zero[1] = {{{{1, 0, 0}, {0, 0, 0}, {1, 0, 0}}}};
    spm_mesh_data dz = {0, 1, 1, mats, tris, zero, NULL, NULL, "", NULL, 0, 0, NULL, NULL};
    bs_open(&x);
    identity(&o);
    o.material = x.grey;
    o.shading = SPM_MESH_SHADE_SMOOTH;
    rc = spm_mesh_add(&x.b, &x.cache, &dz, &o, "m", "t", &err);
    CHECK(rc == 0 && x.s.nvnormals == 0 && x.s.tris[0].vn == 0, "a zero vertex normal: flat");
    bs_close(&x);
}

static void check_build(void)
{
    spm_mesh_material mats[3] = {{.name = "a", .diffuse = {0.8f, 0.2f, 0.1f}, .emission = {0, 0, 0}},
                                 {.name = "b", .diffuse = {0.8f, 0.2f, 0.1f}, .emission = {0, 0, 0}},
                                 {.name = "c", .diffuse = {0, 0, 0}, .emission = {2, 2, 2}}};
    spm_mesh_tri tris[4] = {{{{1, 0, 0}, {1, 1, 0}, {1, 0, 1}}, 0},
                            {{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, 1}, /* collinear */
                            {{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}}, 1}, /* coincident */
                            {{{0, 0, 3}, {1, 0, 3}, {0, 1, 3}}, 1}};
    spm_mesh_data d = {0, 3, 4, mats, tris, NULL, NULL, NULL, "", NULL, 0, 0, NULL, NULL};
    spm_error err;
    spm_quiet_warnings = 1;

    /* lifted: a and b share one colour and one material; degenerate ones skipped */
    bscene x;
    bs_open(&x);
    spm_mesh_opts o;
    identity(&o);
    int rc = spm_mesh_add(&x.b, &x.cache, &d, &o, "m", "t", &err);
    CHECK(rc == 0, "a mesh with degenerate triangles loads: %s", rc ? err.msg : "");
    CHECK(x.s.ntris == 2, "2 of 4 triangles kept (%d)", x.s.ntris);
    CHECK(x.s.ntris == 2 && x.s.tris[0].material == x.s.tris[1].material &&
              x.s.tris[0].material != x.grey && x.s.tris[0].material != x.lamp,
          "two file materials of one RGB lift to one material");
    CHECK(x.s.ncolours == 3, "one lifted colour (%d colours)", x.s.ncolours);
    bs_close(&x);

    /* bind and material */
    spm_mesh_bind binds[1] = {{"b", 0}};
    bs_open(&x);
    identity(&o);
    binds[0].material = x.lamp;
    o.binds = binds;
    o.nbinds = 1;
    o.material = x.grey;
    rc = spm_mesh_add(&x.b, &x.cache, &d, &o, "m", "t", &err);
    CHECK(rc == 0 && x.s.ntris == 2 && x.s.tris[0].material == x.grey &&
              x.s.tris[1].material == x.lamp,
          "bind wins over material for its file material");
    CHECK(x.s.ncolours == 2, "nothing lifted when all is bound (%d colours)", x.s.ncolours);
    bs_close(&x);

    bs_open(&x);
    identity(&o);
    snprintf(binds[0].file_mat, sizeof binds[0].file_mat, "nosuch");
    o.binds = binds;
    o.nbinds = 1;
    rc = spm_mesh_add(&x.b, &x.cache, &d, &o, "m", "t", &err);
    CHECK(rc != 0 && strstr(err.msg, "nosuch") && strstr(err.msg, "'a'"),
          "binding a material the file lacks is an error listing its materials: %s", err.msg);
    bs_close(&x);

    /* scale, then rotate, then translate: (1 0 0) -> (2 0 0) -> (0 2 0) -> (0 2 5) */
    double scale[3] = {2, 2, 2}, axis[3] = {0, 0, 1}, tr[3] = {0, 0, 5};
    bs_open(&x);
    identity(&o);
    spm_mesh_transform(scale, axis, 90, tr, o.m);
    o.material = x.grey;
    spm_mesh_data one = {0, 3, 1, mats, tris, NULL, NULL, NULL, "", NULL, 0, 0, NULL, NULL};
    rc = spm_mesh_add(&x.b, &x.cache, &one, &o, "m", "t", &err);
    /* 1e-6: cos 90 degrees in double is 6e-17, times coordinates of 2 */
    CHECK(rc == 0 && fabsf(x.s.tris[0].p[0][0]) < 1e-6f && x.s.tris[0].p[0][1] == 2.0f &&
              x.s.tris[0].p[0][2] == 5.0f,
          "transform order: (1 0 0) went to (%g %g %g), not (0 2 5)", x.s.tris[0].p[0][0],
          x.s.tris[0].p[0][1], x.s.tris[0].p[0][2]);
    bs_close(&x);

    /* transforms compose in the order applied: (0 1 0) rotated -90 degrees about x
     * is (0 0 -1), then 180 about y (0 0 1); the other order gives (0 0 -1) */
    {
        double ax[3] = {1, 0, 0}, ay[3] = {0, 1, 0}, m1[3][4], m2[3][4];
        spm_mesh_identity(m1);
        spm_mesh_rotate(m1, ax, -90);
        spm_mesh_rotate(m1, ay, 180);
        spm_mesh_identity(m2);
        spm_mesh_rotate(m2, ay, 180);
        spm_mesh_rotate(m2, ax, -90);
        /* 1e-12: the sines and cosines of right angles in double are off by ~1e-16 */
        CHECK(fabs(m1[0][1]) < 1e-12 && fabs(m1[1][1]) < 1e-12 && fabs(m1[2][1] - 1) < 1e-12,
              "rotate x then y: (0 1 0) went to (%g %g %g), not (0 0 1)", m1[0][1], m1[1][1],
              m1[2][1]);
        CHECK(fabs(m2[0][1]) < 1e-12 && fabs(m2[1][1]) < 1e-12 && fabs(m2[2][1] + 1) < 1e-12,
              "rotate y then x: (0 1 0) went to (%g %g %g), not (0 0 -1)", m2[0][1], m2[1][1],
              m2[2][1]);
        double s2[3] = {2, 2, 2}, t1[3] = {1, 0, 0};
        spm_mesh_identity(m1);
        spm_mesh_translate(m1, t1);
        spm_mesh_scale(m1, s2);
        CHECK(m1[0][0] == 2 && m1[0][3] == 2, "translate then scale: x' = %g x + %g, not 2 x + 2",
              m1[0][0], m1[0][3]);
    }

    /* a mirror keeps the front face: the normal of the mirrored triangle is the mirror
     * image of the original's (+x at x = 1 becomes -x at x = -1) */
    double mirror[3] = {-1, 1, 1}, zero[3] = {0, 0, 0};
    bs_open(&x);
    identity(&o);
    spm_mesh_transform(mirror, axis, 0, zero, o.m);
    o.material = x.grey;
    rc = spm_mesh_add(&x.b, &x.cache, &one, &o, "m", "t", &err);
    if (rc == 0) {
        const float(*p)[3] = x.s.tris[0].p;
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = p[1][k] - p[0][k];
            e2[k] = p[2][k] - p[0][k];
        }
        double nx = e1[1] * e2[2] - e1[2] * e2[1]; /* the original's is +1 */
        CHECK(nx < 0 && p[0][0] == -1.0f, "a mirrored triangle faces -x (normal x %g)", nx);
    } else {
        CHECK(0, "mirror: %s", err.msg);
    }
    bs_close(&x);

    /* all degenerate: an error, not an empty mesh */
    spm_mesh_data degen = {0, 3, 2, mats, tris + 1, NULL, NULL, NULL, "", NULL, 0, 0, NULL, NULL};
    bs_open(&x);
    identity(&o);
    rc = spm_mesh_add(&x.b, &x.cache, &degen, &o, "m", "t", &err);
    CHECK(rc != 0 && strstr(err.msg, "degenerate"), "a mesh of degenerate triangles is refused");
    bs_close(&x);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/spm_test_mesh.%d", (int)getpid());
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "python3 %s/tools/gen_meshes.py %s", SPM_SOURCE_DIR, dir);
    if (system(cmd) != 0) {
        CHECK(0, "%s", cmd);
        TEST_END();
    }
    const char *cubes[] = {"cube.obj", "cube_ascii.ply", "cube_binary.ply", "cube.gltf",
                           "cube.glb", "cube_ascii.stl", "cube_binary.stl"};
    for (int i = 0; i < 7; i++)
        check_same(cubes[i], "cube.tris", 0);
    /* 1e-5: Assimp turns glTF's quaternion into a float matrix; its rounding
     * (a few ulps of 1) times coordinates up to 12 */
    check_same("hier.gltf", "hier.tris", 1e-5);
    check_materials("cube.obj");
    check_materials("cube.gltf");
    check_materials("cube.glb");

    check_textured("tex_cube.obj", 1, "tex.png");
    check_textured("tex_cube.gltf", 1, "tex.png");
    check_textured("tex_cube.glb", 1, "embedded image 0");
    /* a texture that is not there: the factor alone, and the reason kept */
    char cmd2[2048];
    snprintf(cmd2, sizeof cmd2, "sed 's/tex.png/nosuch.png/' %s/tex_cube.mtl > %s/notex.mtl && "
             "sed 's/tex_cube.mtl/notex.mtl/' %s/tex_cube.obj > %s/notex.obj", dir, dir, dir, dir);
    CHECK(system(cmd2) == 0, "%s", cmd2);
    check_textured("notex.obj", 0, "nosuch.png");

    check_strips();
    check_ply_polygons();
    check_normals("sphere_n.obj", 1);
    check_normals("sphere_n.ply", 1);
    check_normals("sphere_n_strips.ply", 1);
    check_normals("sphere_n.gltf", 2);
    {
        spm_mesh_data d;
        spm_error err;
        CHECK(import("cube.obj", &d, &err) == 0 && d.normals == NULL,
              "a file without vertex normals has none");
        spm_mesh_free(&d);
        CHECK(import("cube_ascii.stl", &d, &err) == 0 && d.normals == NULL,
              "STL's facet normals are no vertex normals");
        spm_mesh_free(&d);
    }
    static const char glb[] = "glTF\x02\0\0\0\xff\xff\xff\xff not json";
    write_file("garbage.glb", glb, sizeof glb - 1);
    check_fails("garbage.glb", "truncated: its header says 4294967295 bytes");
    static const char ply[] = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
                              "property float x\nproperty float y\nproperty float z\n"
                              "element face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n\0\0\0\0";
    write_file("truncated.ply", ply, sizeof ply);
    /* Assimp 5.2 died of SIGSEGV on this file (in its triangulation); the
     * project's reader names where it ends */
    check_fails("truncated.ply", "truncated.ply: element vertex item 1 (byte ");
    write_file("empty.stl", "", 0);
    check_fails("empty.stl", NULL);
    static const char badidx[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    write_file("badindex.obj", badidx, sizeof badidx - 1);
    check_fails("badindex.obj", NULL);
    setenv("SPECMIP_TEST_MESH_CHILD", "crash", 1);
    check_fails("cube.obj", "crashed");
#if !defined(__SANITIZE_ADDRESS__) /* no address-space limit under ASan (mesh_import.c) */
    setenv("SPECMIP_TEST_MESH_CHILD", "as=1", 1); /* 1 MiB: less than the process already maps */
    check_fails("cube.obj", NULL);
#endif
    unsetenv("SPECMIP_TEST_MESH_CHILD");

    check_decode();
    check_build();
    check_build_normals();
    check_pbr();
    check_pbr_rows();
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    TEST_END();
}
