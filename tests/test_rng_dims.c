/* The random-number dimensions (include/spm_rng.h): the existing ones are
 * where they have always been (the constants, and the numbers drawn at them,
 * recorded before the types' range existed), and the types' range
 * (SPM_DIM_TYPE) overlaps none of them, at any depth, nor hero's. */
#include "spm_rng.h"
#include "testutil.h"

int main(void)
{
    /* MiniLight's dimensions, unchanged */
    CHECK(SPM_DIM_CAM_X == 0u && SPM_DIM_CAM_Y == 1u, "camera dimensions moved");
    CHECK(SPM_DIMS_PER_VERTEX == 6u, "a vertex draws %u dimensions, not 6", SPM_DIMS_PER_VERTEX);
    for (spm_u32 j = 0; j < SPM_MAX_DEPTH; j++)
        CHECK(SPM_DIM_VERTEX(j) == 2u + 6u * j, "vertex %u starts at %u", j, SPM_DIM_VERTEX(j));
    CHECK(SPM_DIM_EMITTER == 0u && SPM_DIM_EPOINT_A == 1u && SPM_DIM_EPOINT_B == 2u &&
              SPM_DIM_RR == 3u && SPM_DIM_DIR_A == 4u && SPM_DIM_DIR_B == 5u,
          "a vertex's offsets moved");
    CHECK(SPM_DIM_HERO == 0x7fffff00u, "hero's dimension moved");

    /* the numbers drawn there, recorded from the generator before this range
     * was added (seed 7, pixel 123, sample 4) */
    static const struct {
        spm_u32 dim, bits;
    } gold[] = {
        {SPM_DIM_CAM_X, 0x937cffb7u},
        {SPM_DIM_CAM_Y, 0x03fcef2au},
        {SPM_DIM_VERTEX(0) + SPM_DIM_EMITTER, 0x22781c7du},
        {SPM_DIM_VERTEX(0) + SPM_DIM_DIR_B, 0x976254a2u},
        {SPM_DIM_VERTEX(5) + SPM_DIM_RR, 0x8379ff62u},
        {SPM_DIM_VERTEX(63) + SPM_DIM_DIR_B, 0x7ed4a8b7u},
        {SPM_DIM_HERO, 0x8519d5e8u},
    };
    for (unsigned i = 0; i < sizeof gold / sizeof gold[0]; i++)
        CHECK(spm_rng_u32(7, 123, 4, gold[i].dim) == gold[i].bits, "dimension %u draws %08x",
              gold[i].dim, spm_rng_u32(7, 123, 4, gold[i].dim));

    /* the types' range: above every vertex's, below hero's, one slot per
     * depth and offset */
    spm_u32 last_vertex = SPM_DIM_VERTEX(SPM_MAX_DEPTH - 1) + SPM_DIMS_PER_VERTEX - 1;
    CHECK(SPM_DIM_TYPE(0, 0) > last_vertex, "the types' range starts at %u, inside the vertices'",
          SPM_DIM_TYPE(0, 0));
    CHECK(SPM_DIM_TYPE(SPM_MAX_DEPTH - 1, SPM_TYPE_DIMS_PER_VERTEX - 1) < SPM_DIM_HERO,
          "the types' range reaches hero's dimension");
    CHECK(SPM_DIM_TYPE(1, 0) == SPM_DIM_TYPE(0, SPM_TYPE_DIMS_PER_VERTEX - 1) + 1,
          "vertex j's type dimensions are not next to vertex j-1's");
    /* and the draws there are not those of the vertex dimensions */
    int distinct = 1;
    for (spm_u32 j = 0; j < 4; j++)
        for (spm_u32 k = 0; k < SPM_TYPE_DIMS_PER_VERTEX; k++)
            for (spm_u32 d = 0; d < SPM_DIMS_PER_VERTEX; d++)
                distinct &= spm_rng_u32(7, 123, 4, SPM_DIM_TYPE(j, k)) !=
                            spm_rng_u32(7, 123, 4, SPM_DIM_VERTEX(j) + d);
    CHECK(distinct, "a type dimension draws a vertex dimension's number");
    /* a vertex's material type and the emitter type sampled for it never share one */
    CHECK(SPM_DIM_TYPE(0, SPM_TYPE_MAT_DIMS - 1) < SPM_DIM_EMIT_TYPE(0, 0) &&
              SPM_DIM_EMIT_TYPE(0, SPM_TYPE_EMIT_DIMS - 1) < SPM_DIM_TYPE(1, 0),
          "the emitter types' half overlaps the material types' or the next vertex's");
    /* each type's offsets are its own: two of them at one dimension draw one
     * number twice (a visible normal from u1 = u2 lies on a curve) */
    static const struct {
        const char *type;
        spm_u32 dims[4];
        int n;
    } types[] = {
        {"conductor", {SPM_DIM_COND_M_A, SPM_DIM_COND_M_B}, 2},
        {"coated", {SPM_DIM_COAT_LOBE, SPM_DIM_COAT_M_A, SPM_DIM_COAT_M_B}, 3},
        {"dielectric", {SPM_DIM_DIEL_M_A, SPM_DIM_DIEL_M_B, SPM_DIM_DIEL_CHOICE, SPM_DIM_DIEL_LAMBDA}, 4},
    };
    for (unsigned t = 0; t < sizeof types / sizeof types[0]; t++)
        for (int a = 0; a < types[t].n; a++) {
            CHECK(types[t].dims[a] < SPM_TYPE_MAT_DIMS, "%s: offset %u past the types' %u",
                  types[t].type, types[t].dims[a], SPM_TYPE_MAT_DIMS);
            for (int b = a + 1; b < types[t].n; b++)
                CHECK(types[t].dims[a] != types[t].dims[b], "%s: offsets %d and %d share dimension %u",
                      types[t].type, a, b, types[t].dims[a]);
        }
    /* a thin lens's two dimensions: past the types' range at any depth, below
     * hero's, distinct (a pinhole's paths never draw them) */
    CHECK(SPM_DIM_LENS_A > SPM_DIM_TYPE(SPM_MAX_DEPTH - 1, SPM_TYPE_DIMS_PER_VERTEX - 1) &&
              SPM_DIM_LENS_B > SPM_DIM_LENS_A && SPM_DIM_LENS_B < SPM_DIM_HERO,
          "the lens dimensions %#x, %#x overlap another range", SPM_DIM_LENS_A, SPM_DIM_LENS_B);
    TEST_END();
}
