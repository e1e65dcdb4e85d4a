/* spm_divisor (spm_shared.h), the multiply-and-shift division the hero shade
 * kernel uses for path index / spp, against C's division: every divisor up to
 * 4096 and the powers of two and their neighbours up to 2^32 - 1, each with
 * dividends at and around its multiples, the ends of the range and a seeded
 * spread. */
#include <stdint.h>
#include "spm_rng.h"
#include "testutil.h"

static int check_divisor(spm_u32 d)
{
    spm_divisor dv = spm_divisor_make(d);
    int bad = 0;
    spm_u32 n[64];
    int k = 0;
    n[k++] = 0;
    n[k++] = 1;
    n[k++] = 0xFFFFFFFFu;
    n[k++] = 0xFFFFFFFEu;
    n[k++] = 0x7FFFFFFFu;
    n[k++] = 0x80000000u;
    for (spm_u32 m = 1; m <= 8; m++) {
        uint64_t x = (uint64_t)d * m;
        uint64_t top = (uint64_t)d * (0xFFFFFFFFu / d - m + 1);
        if (x <= 0xFFFFFFFFu) {
            n[k++] = (spm_u32)x;
            n[k++] = (spm_u32)(x - 1);
        }
        n[k++] = (spm_u32)top;
        n[k++] = (spm_u32)(top - 1);
    }
    for (spm_u32 j = 0; k < 64; j++)
        n[k++] = spm_rng_u32(d, j, 0, 0);
    for (int i = 0; i < 64; i++) {
        spm_u32 q = spm_divisor_div(n[i], dv);
        if (q != n[i] / d) {
            if (!bad)
                fprintf(stderr, "d %u: %u / d gave %u, not %u\n", d, n[i], q, n[i] / d);
            bad++;
        }
    }
    return bad;
}

int main(void)
{
    long bad = 0, tried = 0;
    for (spm_u32 d = 1; d <= 4096; d++, tried++)
        bad += check_divisor(d) != 0;
    for (int b = 1; b < 32; b++)
        for (int o = -1; o <= 1; o++, tried++)
            bad += check_divisor((spm_u32)(((uint64_t)1 << b) + o)) != 0;
    bad += check_divisor(0xFFFFFFFFu) != 0;
    tried++;
    CHECK(bad == 0, "%ld of %ld divisors divide wrongly", bad, tried);
    TEST_END();
}
