/* Material and emitter types (host/scene/materials.h): a Lambertian-only scene
 * compiles exactly the Lambertian and area-light code (the kernel options the
 * OpenCL program is built with, render_plan.h type_defines) and records
 * nothing per vertex beyond spm_vertex; every scene material is tagged; the
 * descriptors are well formed (tags in place, random-number dimensions within
 * the types' range, a define each); and the material statement reads its
 * clauses from the descriptors (errors name them). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "materials.h"
#include "render_plan.h"
#include "spm_rng.h"
#include "testutil.h"

static void descriptors(void)
{
    const spm_mtype_desc *tables[2] = {spm_material_types, spm_emitter_types};
    int counts[2] = {spm_nmaterial_types, spm_nemitter_types};
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < counts[k]; i++) {
            const spm_mtype_desc *d = &tables[k][i];
            CHECK(d->tag == (unsigned)i, "descriptor %d of table %d has tag %u", i, k, d->tag);
            unsigned half = k == 0 ? SPM_TYPE_MAT_DIMS : SPM_TYPE_EMIT_DIMS;
            CHECK(d->rng_dims >= 0 && d->rng_dims <= (int)half,
                  "type %d of table %d draws %d dimensions (at most %u)", i, k, d->rng_dims, half);
            CHECK(d->define && !strncmp(d->define, "SPM_WITH_", 9), "type %d: define", i);
            CHECK(d->nparams <= SPM_MTYPE_MAX_PARAMS, "type %d: %d parameters", i, d->nparams);
            /* a number's slot indexes p[] or ep[] (the generic fill copies it there) */
            for (int q = 0; q < d->nparams && q < SPM_MTYPE_MAX_PARAMS; q++) {
                const spm_mparam *pa = &d->params[q];
                int into_p = pa->kind == SPM_MP_NUMBER || pa->kind == SPM_MP_INDEX ||
                             pa->kind == SPM_MP_FILE;
                if (into_p)
                    CHECK(pa->slot >= 0 && pa->slot < SPM_MAT_PARAMS,
                          "type %d of table %d: parameter %d's slot %d outside p[]", i, k, q, pa->slot);
                if (pa->kind == SPM_MP_EMIT_NUMBER)
                    CHECK(pa->slot >= 0 && pa->slot < SPM_EMIT_PARAMS,
                          "type %d of table %d: parameter %d's slot %d outside ep[]", i, k, q, pa->slot);
            }
        }
    CHECK(spm_material_type_default()->tag == SPM_MAT_LAMBERT, "the default type is Lambertian");
}

static void lambert_only(const char *rel)
{
    char path[1024];
    spm_scene sc;
    spm_geometry g;
    spm_tables t;
    spm_error err;
    spm_pretest_opts po;
    spm_pretest_defaults(&po);
    if (spm_scene_load(spm_data_path(rel, path, sizeof path), &sc, &err)) {
        CHECK(0, "%s", err.msg);
        return;
    }
    sc.width = 8;
    sc.height = 6;
    CHECK(spm_geometry_build(&sc, &g, &err) == 0, "%s", err.msg);
    CHECK(spm_tables_build(&sc, &po, &t, &err) == 0, "%s", err.msg);
    int tagged = 1;
    for (int m = 0; m < t.nmaterials; m++)
        tagged &= t.materials[m].type == (SPM_MAT_LAMBERT | SPM_EMIT_AREA << 16) &&
                  t.materials[m].col2 == SPM_NONE;
    CHECK(tagged, "%s: a material is not Lambertian with an area light", rel);
    for (int mode = 0; mode < SPM_MODE_COUNT; mode++) {
        spm_render_plan plan;
        CHECK(spm_render_plan_init(&plan, &g, &t, mode, 7, &err) == 0, "%s", err.msg);
        CHECK(!strcmp(plan.type_defines, "-DSPM_WITH_LAMBERT -DSPM_WITH_AREA "),
              "%s, %s: build options '%s'", rel, spm_mode_name(mode), plan.type_defines);
        CHECK(plan.vertex_bytes == sizeof(spm_vertex) && sizeof(spm_vertex) == 8,
              "%s: a vertex's record is %zu bytes", rel, plan.vertex_bytes);
        spm_render_plan_free(&plan);
    }
    spm_tables_free(&t);
    spm_geometry_free(&g);
    spm_scene_free(&sc);
}

/* A scene lit only by its background uses no emitter type's code. */
static void background_only(void)
{
    spm_material m = {0, SPM_NONE, 0.5f, 2.0f, SPM_MAT_LAMBERT | SPM_EMIT_AREA << 16, SPM_NONE,
                      {0, 0, 0, 0}, {0}};
    char defs[128];
    spm_material_defines(&m, 1, defs, sizeof defs);
    CHECK(!strcmp(defs, "-DSPM_WITH_LAMBERT "), "background-only scene: '%s'", defs);
}

static void parse_errors(void)
{
    const char *text = "spectrum flat equal\nmaterial a reflect flat 0.5 reflect flat\n";
    char path[] = "/tmp/spm_test_material_XXXXXX";
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!f) {
        CHECK(0, "temporary file");
        return;
    }
    fputs(text, f);
    fclose(f);
    spm_scene sc;
    spm_error err;
    /* the clauses listed are the descriptors': every emitter type's follow */
    CHECK(spm_scene_load(path, &sc, &err) != 0 && strstr(err.msg, "expected 'reflect'") && strstr(err.msg, "'emit'") &&
              strstr(err.msg, " (each once), found 'reflect'"),
          "a clause given twice: '%s'", err.msg);
    remove(path);
}

int main(void)
{
    descriptors();
    lambert_only("scenes/cornell.scene");
    lambert_only("scenes/cornell_spiky.scene");
    background_only();
    parse_errors();
    TEST_END();
}
