/* Minimal test harness: CHECK records a failure and goes on; TEST_END prints
 * the closing "N passed, N failed" line and returns the exit status. */
#ifndef SPM_TESTUTIL_H
#define SPM_TESTUTIL_H
#include <stdio.h>
#include <math.h>

static int spm_t_pass, spm_t_fail;

#define CHECK(cond, ...)                                                        \
    do {                                                                        \
        if (cond) {                                                             \
            spm_t_pass++;                                                       \
        } else {                                                                \
            spm_t_fail++;                                                       \
            fprintf(stderr, "%s:%d: FAIL: %s: ", __FILE__, __LINE__, #cond);   \
            fprintf(stderr, __VA_ARGS__);                                       \
            fputc('\n', stderr);                                                \
        }                                                                       \
    } while (0)

#define CHECK_NEAR(a, b, tol, what)                                             \
    CHECK(fabs((double)(a) - (double)(b)) <= (tol), "%s: %.9g vs %.9g (tol %.3g)", \
          what, (double)(a), (double)(b), (double)(tol))

#define TEST_END()                                                              \
    do {                                                                        \
        printf("%d passed, %d failed\n", spm_t_pass, spm_t_fail);              \
        return spm_t_fail ? 1 : (spm_t_pass ? 0 : 1);                           \
    } while (0)
#endif
