/* The spectral tables' arrays are listed once (tables.h SPM_TABLES_ARRAYS).
 * This test is a test build: it compiles tables.c and prepared.c itself with
 * SPM_TABLES_TEST_ARRAY, which appends one array to the list and touches no
 * other code, and checks that the array is made, counted in the footprint,
 * packed for the other MPI ranks, arrives there byte for byte (with every other
 * listed array) and is freed: nothing but the list names it. */
#include <stdlib.h>
#include <string.h>
#include "prepared.h"
#include "scene.h"
#include "tables.h"
#include "testutil.h"

#ifndef SPM_TABLES_TEST_ARRAY
#error "test_tables_list is built with SPM_TABLES_TEST_ARRAY (tests/CMakeLists.txt)"
#endif

static int same(const void *a, const void *b, size_t n)
{
    return (a == NULL) == (b == NULL) && (!a || memcmp(a, b, n) == 0);
}

int main(void)
{
    char path[1024];
    spm_scene sc;
    spm_geometry g, g2;
    spm_tables t, t2;
    spm_error err;
    spm_pretest_opts po;
    spm_pretest_defaults(&po);
    if (spm_scene_load(spm_data_path("scenes/cornell_spiky.scene", path, sizeof path), &sc, &err)) {
        CHECK(0, "%s", err.msg);
        TEST_END();
    }
    CHECK(spm_geometry_build(&sc, &g, &err) == 0, "%s", err.msg);
    CHECK(spm_tables_build(&sc, &po, &t, &err) == 0, "%s", err.msg);

    /* made by spm_tables_build from the list alone, zeroed */
    size_t n_extra = (size_t)t.ncolours * 3 + 1;
    CHECK(t.test_extra != NULL, "the listed test array was not made");
    int zero = 1;
    for (size_t i = 0; t.test_extra && i < n_extra; i++)
        zero &= t.test_extra[i] == 0.0;
    CHECK(zero, "the test array is not zeroed");
    /* its builder: what a mode's or material's builder would put there */
    for (size_t i = 0; t.test_extra && i < n_extra; i++)
        t.test_extra[i] = 0.25 * (double)i + 1.0 / 3.0;

    /* the footprint counts it */
    size_t bytes = spm_tables_bytes(&t);
    double *keep = t.test_extra;
    t.test_extra = NULL;
    CHECK(bytes - spm_tables_bytes(&t) == n_extra * sizeof(double),
          "footprint: %zu bytes with the test array, %zu without", bytes, spm_tables_bytes(&t));
    t.test_extra = keep;

    /* it arrives on another rank, as does every other array of the list */
    spm_prepared_info in = {sc.width, sc.height, 4, 0, 5, 0}, out;
    size_t n;
    unsigned char *buf = spm_prepared_pack(&g, &t, &in, &n);
    CHECK(spm_prepared_unpack(buf, n, &g2, &t2, &out, &err) == 0, "%s", err.msg);
    CHECK(t2.test_extra != NULL && t2.test_extra != t.test_extra &&
              same(t.test_extra, t2.test_extra, n_extra * sizeof(double)),
          "the test array did not arrive");
    int arrays = 0, arrived = 0;
#define SAME_A(name, type, count) \
    arrays++;                     \
    arrived += same(tp->name, t2.name, (count) * sizeof(type)) && tp->name != t2.name;
#define SAME_L(name, type, count)                                                        \
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {                                           \
        arrays++;                                                                        \
        arrived += same(tp->name[l], t2.name[l], (count) * sizeof(type)) &&      \
                   tp->name[l] != t2.name[l];                                     \
    }
    {
        const spm_tables *tp = &t;
#define t tp /* the list's counts read t as a pointer */
        SPM_TABLES_ARRAYS(SAME_A, SAME_L)
#undef t
    }
    CHECK(arrays == arrived, "%d of %d listed arrays arrived", arrived, arrays);
    CHECK(spm_tables_bytes(&t2) == bytes, "footprint after the trip: %zu, before %zu",
          spm_tables_bytes(&t2), bytes);
    free(buf);
    spm_tables_free(&t2);
    CHECK(t2.test_extra == NULL, "freed and cleared");
    spm_geometry_free(&g2);
    spm_tables_free(&t);
    spm_geometry_free(&g);
    spm_scene_free(&sc);
    TEST_END();
}
