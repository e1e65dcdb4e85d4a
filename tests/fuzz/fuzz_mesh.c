/* libFuzzer harness: the project's own mesh code on small generated meshes —
 * the check of the importer's answer (spm_mesh_decode, given the raw input),
 * and binding, the transform and degenerate filtering (spm_mesh_add, on a
 * mesh made from the input's bytes). Assimp itself is not fuzzed here: it
 * runs in a child process whose failures are errors (host/mesh_import.c). */
#include "mesh.h"
#include <stdlib.h>
#include <string.h>

static const char *names[4] = {"a", "b", "", "a"}; /* "" is a file without materials */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    spm_quiet_warnings = 1;
    spm_error err;
    /* the answer's decoder: any bytes */
    void *copy = malloc(size ? size : 1);
    memcpy(copy, data, size);
    spm_mesh_data d;
    if (spm_mesh_decode(copy, size, "fuzz", &d, &err) == 0)
        spm_mesh_free(&d);
    else
        free(copy);
    if (size < 4)
        return 0;

    /* a mesh: 1..4 materials, then triangles of 10 bytes (coordinates in
     * quarter units from -32 to 32, so that coincident and collinear vertices
     * are common, and a material byte) */
    uint8_t flags = data[0], sa = data[1], sb = data[2];
    spm_mesh_material mats[4];
    uint32_t nmats = 1 + (data[3] & 3);
    memset(mats, 0, sizeof mats);
    for (uint32_t i = 0; i < nmats; i++) {
        snprintf(mats[i].name, sizeof mats[i].name, "%s", names[(data[3] >> (2 + i)) & 3]);
        mats[i].diffuse[0] = (float)((sa >> i) & 1);
        mats[i].diffuse[1] = 0.25f * (float)(i + 1);
        mats[i].emission[2] = (float)((sb >> i) & 1) * 3.0f;
    }
    size_t ntris = (size - 4) / 10;
    spm_mesh_tri *tris = calloc(ntris + 1, sizeof *tris);
    for (size_t t = 0; t < ntris; t++) {
        const uint8_t *b = data + 4 + 10 * t;
        for (int k = 0; k < 9; k++)
            tris[t].p[k / 3][k % 3] = (float)(int8_t)b[k] * 0.25f;
        tris[t].mat = b[9] % nmats;
    }
    d = (spm_mesh_data){0, nmats, ntris, mats, tris, NULL, NULL, ""};

    spm_scene s;
    spm_scene_builder bld;
    spm_mesh_cache cache;
    spm_sb_init(&bld, &s, "fuzz");
    spm_mesh_cache_init(&cache);
    spm_spectrum sp;
    spm_spectrum_constant(0.5, SPM_KIND_REFLECTANCE, &sp);
    int grey = spm_sb_material(&bld, "grey", spm_sb_colour(&bld, "grey", &sp, "f", &err), -1,
                               "f", &err);
    spm_mesh_bind binds[2] = {{"a", grey}, {"nosuch", grey}};
    double scale[3] = {1, 1, 1}, axis[3] = {(sa & 7) - 3.5, (sb & 7) - 3.5, 1},
           tr[3] = {sa * 1e3, 0, -(double)sb};
    if (flags & 8)
        scale[0] = -2; /* a mirror */
    if (flags & 16)
        scale[1] = 1e-30; /* flattening: everything degenerate */
    if (flags & 32)
        scale[2] = 1e11; /* beyond the coordinate bound */
    spm_mesh_opts o;
    memset(&o, 0, sizeof o);
    o.material = flags & 1 ? grey : -1;
    o.binds = binds;
    o.nbinds = (flags >> 1) & 3 ? 1 + ((flags >> 2) & 1) : 0;
    spm_mesh_transform(scale, axis, (double)sa * 3.0, tr, o.m);
    if (spm_mesh_add(&bld, &cache, &d, &o, "fuzz.obj", "f", &err) == 0 && s.ntris == 0)
        abort(); /* success means triangles */
    spm_mesh_cache_free(&cache);
    spm_sb_done(&bld, 0);
    free(tris);
    return 0;
}
