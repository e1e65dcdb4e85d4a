/* glTF's KHR_materials_dispersion onto the dielectric's dispersion: a glTF
 * written here (a closed cube of transmissive glass with `dispersion` 0.8,
 * V_d = 20 / 0.8 = 25, and one without) imported and mapped; the glass's
 * index table checked against the Abbe number's own definition,
 * V_d = (n_d - 1) / (n_F - n_C) at 587.6, 486.1 and 656.3 nm, and n_d
 * against the file's ior: a closed form, not the Cauchy coefficients the
 * mapping computes. */
#include "mesh.h"
#include "dispersion.h"
#include "materials.h"
#include "testutil.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void base64(const unsigned char *in, size_t n, FILE *f)
{
    static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)in[i] << 16 | (i + 1 < n ? (unsigned)in[i + 1] << 8 : 0) |
                     (i + 2 < n ? in[i + 2] : 0);
        fputc(t[v >> 18 & 63], f);
        fputc(t[v >> 12 & 63], f);
        fputc(i + 1 < n ? t[v >> 6 & 63] : '=', f);
        fputc(i + 2 < n ? t[v & 63] : '=', f);
    }
}

/* A unit cube (8 vertices, 12 triangles wound outwards) as two primitives,
 * material 0 (dispersive glass) and 1 (the same glass without the extension). */
static void write_gltf(const char *path, const char *disp_ext)
{
    float pos[24];
    for (int c = 0; c < 8; c++)
        for (int i = 0; i < 3; i++)
            pos[3 * c + i] = (float)((c >> (2 - i)) & 1);
    static const uint32_t idx[36] = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                                     2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
    unsigned char buf[sizeof pos + sizeof idx];
    memcpy(buf, pos, sizeof pos);
    memcpy(buf + sizeof pos, idx, sizeof idx);
    FILE *f = fopen(path, "w");
    fprintf(f, "{\"asset\": {\"version\": \"2.0\"}, \"extensionsUsed\": [\"KHR_materials_transmission\", "
               "\"KHR_materials_volume\", \"KHR_materials_ior\", \"KHR_materials_dispersion\"],\n"
               "\"scene\": 0, \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{\"mesh\": 0}],\n"
               "\"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1, "
               "\"material\": 0}, {\"attributes\": {\"POSITION\": 0}, \"indices\": 2, "
               "\"material\": 1}]}],\n");
    const char *glass = "\"pbrMetallicRoughness\": {\"metallicFactor\": 0, \"roughnessFactor\": 0}, "
                        "\"extensions\": {\"KHR_materials_transmission\": {\"transmissionFactor\": 1}, "
                        "\"KHR_materials_volume\": {\"thicknessFactor\": 1}, "
                        "\"KHR_materials_ior\": {\"ior\": 1.6}";
    fprintf(f, "\"materials\": [{\"name\": \"flint\", %s%s}}, {\"name\": \"plain\", %s}}],\n", glass,
            disp_ext, glass);
    fprintf(f, "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 8, "
               "\"type\": \"VEC3\", \"min\": [0, 0, 0], \"max\": [1, 1, 1]}, {\"bufferView\": 1, "
               "\"componentType\": 5125, \"count\": 18, \"type\": \"SCALAR\"}, {\"bufferView\": 1, "
               "\"byteOffset\": 72, \"componentType\": 5125, \"count\": 18, \"type\": \"SCALAR\"}],\n"
               "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": %zu}, {\"buffer\": 0, "
               "\"byteOffset\": %zu, \"byteLength\": %zu}],\n"
               "\"buffers\": [{\"byteLength\": %zu, \"uri\": \"data:application/octet-stream;base64,",
            sizeof pos, sizeof pos, sizeof idx, sizeof buf);
    base64(buf, sizeof buf, f);
    fprintf(f, "\"}]}\n");
    fclose(f);
}

/* n at lambda nm from the table of n at bin centres, linearly between them */
static double n_at(const double *table, double lambda)
{
    double x = lambda - SPM_LAMBDA_MIN - 0.5;
    int b = (int)floor(x);
    double f = x - b;
    return (1 - f) * table[b] + f * table[b + 1];
}

/* The scene of the file at `path`; its materials named flint and plain. */
static int load(const char *path, spm_scene *s)
{
    spm_mesh_data d;
    spm_error err;
    spm_file file;
    if (spm_paths_set_root(path, &file, &err) || spm_mesh_import(&file, &d, &err)) {
        CHECK(0, "%s: %s", path, err.msg);
        return 1;
    }
    spm_scene_builder b;
    spm_mesh_cache cache;
    spm_sb_init(&b, s, "<test>");
    spm_mesh_cache_init(&cache);
    spm_mesh_opts o;
    memset(&o, 0, sizeof o);
    o.material = -1;
    spm_mesh_identity(o.m);
    int rc = spm_mesh_add(&b, &cache, &d, &o, path, "t", &err);
    CHECK(rc == 0, "the cube maps: %s", rc ? err.msg : "");
    spm_mesh_cache_free(&cache);
    spm_sb_done(&b, rc == 0);
    spm_mesh_free(&d);
    return rc;
}

static const spm_scene_material *find(const spm_scene *s, const char *name)
{
    for (int i = 0; i < s->nmaterials; i++)
        if (!strcmp(s->materials[i].name, name))
            return &s->materials[i];
    return NULL;
}

int main(void)
{
    char dir[] = "/tmp/spm_disp_XXXXXX", path[64];
    CHECK(mkdtemp(dir) != NULL, "a temporary folder");
    snprintf(path, sizeof path, "%s/disp.gltf", dir);
    write_gltf(path, ", \"KHR_materials_dispersion\": {\"dispersion\": 0.8}");
    spm_scene s;
    memset(&s, 0, sizeof s);
    if (load(path, &s) == 0) {
        const spm_scene_material *flint = find(&s, "flint"), *plain = find(&s, "plain");
        CHECK(flint && flint->type == SPM_MAT_DIELECTRIC, "flint is a dielectric");
        CHECK(plain && plain->type == SPM_MAT_DIELECTRIC, "plain is a dielectric");
        int row = flint ? (int)flint->p[SPM_DIEL_P_DISP] - 1 : -1;
        CHECK(row >= 0 && row < s.ndisp, "flint has an index table (row %d of %d)", row, s.ndisp);
        CHECK(plain && plain->p[SPM_DIEL_P_DISP] == 0, "plain has none");
        CHECK(plain && fabs(plain->p[SPM_DIEL_P_IOR] - 1.6) < 1e-6, "plain's ior 1.6");
        if (row >= 0 && row < s.ndisp) {
            const double *t = s.disp + (size_t)row * SPM_TRUTH_BINS;
            double nd = n_at(t, 587.6), nf = n_at(t, 486.1), nc = n_at(t, 656.3);
            double vd = (nd - 1) / (nf - nc);
            printf("n_F %.6f n_d %.6f n_C %.6f: V_d %.4f\n", nf, nd, nc, vd);
            /* Measured: n_d 1.599996 and V_d 24.990 against 25: the
             * extension's constants 523655 and 1.5168 are rounded (its n at
             * 587.6 nm lies 3.8e-6 below the ior, its n_F - n_C is 1.0004
             * (n_d - 1) / V_d); the table's interpolation adds ~2e-8. Bounds:
             * n_d 1e-5, V_d 0.1 %. Shown failing: without the extension read
             * there is no table; with `dispersion` taken as V_d, V_d is 0.80. */
            CHECK(fabs(nd - 1.6) < 1e-5, "n_d %.7f is the file's ior 1.6", nd);
            CHECK(fabs(vd / 25.0 - 1) < 1e-3, "V_d %.5f is 20 / 0.8 = 25", vd);
            CHECK(fabs(flint->p[SPM_DIEL_P_IOR] - 1.6) < 1e-5, "the d-line index %.7f",
                  flint->p[SPM_DIEL_P_IOR]);
            CHECK(t[0] > t[SPM_TRUTH_BINS - 1], "n falls with the wavelength");
        }
    }
    spm_scene_free(&s);
    unlink(path);
    rmdir(dir);
    TEST_END();
}
