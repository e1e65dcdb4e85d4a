/* The CPU reference's triangle test (watertight_testlib.h): a grazing ray
 * hits a 1e-8 m^2 triangle, and no ray through a shared edge or vertex of a
 * closed mesh passes between its triangles; through the BVH and, on every
 * seventh ray, by testing every triangle. */
#include "watertight_testlib.h"

static void run(const wt_case *c)
{
    int *hits = malloc(c->n * sizeof *hits), *brute = malloc(c->n * sizeof *brute);
    for (size_t i = 0; i < c->n; i++) {
        const spm_ray *r = &c->rays[i];
        float t;
        hits[i] = spm_bvh_intersect(&c->g, r->o, r->d, r->skip, &t);
        brute[i] = i % 7 ? hits[i] : spm_brute_intersect(&c->g, r->o, r->d, r->skip, &t);
    }
    wt_check("reference BVH", c, hits);
    size_t differ = 0;
    for (size_t i = 0; i < c->n; i++)
        differ += brute[i] != hits[i];
    CHECK(differ == 0, "%s: %zu rays where the BVH and every triangle disagree", c->name, differ);
    free(hits);
    free(brute);
}

int main(void)
{
    wt_all(run);
    TEST_END();
}
