/* The wavefront's coherent order (bench_wavefront.h spm_wavefront_order),
 * against keys made here bit by bit: the order is a permutation, its keys
 * (octant, then the Morton code of the origin's cell) never decrease, equal
 * keys keep their given order, and rays that differ only in the octant or in
 * one axis's cell land where the key says. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench_wavefront.h"
#include "testutil.h"

static unsigned long long rng_state = 12345;
static float rnd(void)
{
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (float)((rng_state >> 40) * (1.0 / 16777216.0));
}

/* the key written out: octant bits (x, y, z negative) above 27 bits that
 * take bit b of cell coordinate k to bit 3b + k */
static spm_u32 naive_key(const spm_ray *r, const float lo[3], const float hi[3])
{
    spm_u32 key = 0;
    for (int k = 0; k < 3; k++) {
        float u = hi[k] > lo[k] ? (r->o[k] - lo[k]) * (512.0f / (hi[k] - lo[k])) : 0.0f;
        spm_u32 c = u >= 511.0f ? 511u : (spm_u32)u;
        for (int b = 0; b < 9; b++)
            key |= ((c >> b) & 1u) << (3 * b + k);
        if (r->d[k] < 0.0f)
            key |= 1u << (27 + k);
    }
    return key;
}

static void bounds(const spm_ray *r, size_t n, float lo[3], float hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], r[i].o[k]);
            hi[k] = fmaxf(hi[k], r[i].o[k]);
        }
}

static void check_order(const spm_ray *r, size_t n, const char *what)
{
    spm_u32 *perm = malloc(n * sizeof *perm);
    unsigned char *seen = calloc(n, 1);
    double ks, ss;
    spm_wavefront_order(r, n, perm, &ks, &ss);
    float lo[3], hi[3];
    bounds(r, n, lo, hi);
    size_t dup = 0, down = 0, unstable = 0, moved = 0;
    for (size_t i = 0; i < n; i++) {
        dup += perm[i] >= n || seen[perm[i]];
        if (perm[i] < n)
            seen[perm[i]] = 1;
        moved += perm[i] != i;
        if (i > 0 && perm[i] < n && perm[i - 1] < n) {
            spm_u32 a = naive_key(&r[perm[i - 1]], lo, hi), b = naive_key(&r[perm[i]], lo, hi);
            down += b < a;
            unstable += b == a && perm[i] < perm[i - 1];
        }
    }
    CHECK(dup == 0, "%s: a permutation (%zu repeated or out of range)", what, dup);
    CHECK(down == 0, "%s: keys never decrease (%zu steps down)", what, down);
    CHECK(unstable == 0, "%s: equal keys in the given order (%zu not)", what, unstable);
    CHECK(moved > n / 2, "%s: the order moves rays (%zu of %zu)", what, moved, n);
    free(perm);
    free(seen);
}

int main(void)
{
    size_t n = 20000;
    spm_ray *r = calloc(n, sizeof *r);
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            r[i].o[k] = 10.0f * rnd() - 3.0f;
            r[i].d[k] = rnd() - 0.5f;
        }
        if (i % 7 == 3) /* ties: a copy of an earlier ray, index later */
            r[i] = r[i / 2];
    }
    check_order(r, n, "random rays");

    /* two rays, one axis apart: the one in the lower cell first; then the same
     * two with the first heading -x: octant outranks origin */
    spm_ray two[3] = {{{1, 0, 0}, 0, {1, 1, 1}, 0}, {{0, 0, 0}, 0, {1, 1, 1}, 0},
                      {{0.5f, 1, 1}, 0, {1, 1, 1}, 0}};
    spm_u32 perm[3];
    double ks, ss;
    spm_wavefront_order(two, 3, perm, &ks, &ss);
    CHECK(perm[0] == 1 && perm[1] == 0 && perm[2] == 2,
          "origins in Morton order (got %u %u %u, want 1 0 2)", perm[0], perm[1], perm[2]);
    two[1].d[0] = -1;
    spm_wavefront_order(two, 3, perm, &ks, &ss);
    CHECK(perm[2] == 1, "a -x ray after every +x ray (got %u %u %u)", perm[0], perm[1], perm[2]);
    free(r);
    TEST_END();
}
