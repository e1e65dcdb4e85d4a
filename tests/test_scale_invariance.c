/* The CPU reference renders a scene the same in any unit (scale_testlib.h):
 * bit for bit when every coordinate is multiplied by 2^-10 or 2^10, within
 * Monte Carlo noise by 10^-3 or 10^3. */
#include "scale_testlib.h"

static int render(double scale, int spp, sc_render *r, sc_world *w1)
{
    sc_world w;
    if (sc_world_build(&w, scale))
        return 1;
    sc_render_alloc(r, spp);
    spm_trace_params p = ts_params(&w.s, &w.g, (spm_u32)spp, SC_SEED);
    const uint8_t *lvlk = spm_mode_lvlk(spm_mode(SPM_MODE_REF), &w.t);
    spm_ref_trace(&w.g, w.t.materials, lvlk, &p, r->paths, r->levels);
    spm_ref_shade(&w.t, SPM_MODE_REF, &p, 0, r->paths, r->levels, r->n, r->xyz);
    for (size_t i = 0; i < r->n; i++)
        for (int c = 0; c < 3; c++)
            r->image[3 * (i / (size_t)spp) + c] += r->xyz[3 * i + c]; /* in sample order */
    if (w1)
        *w1 = w;
    else
        sc_world_free(&w);
    return 0;
}

static void run(const double scales[3], int spp, int exact)
{
    sc_render r[3];
    sc_world w1;
    for (int k = 0; k < 3; k++)
        if (render(scales[k], spp, &r[k], k == 1 ? &w1 : NULL)) {
            CHECK(0, "scale %g renders", scales[k]);
            return;
        }
    if (exact)
        sc_check_exact("reference", r, &w1);
    else
        sc_check_noise("reference", r, spp, &w1);
    for (int k = 0; k < 3; k++)
        sc_render_free(&r[k]);
    sc_world_free(&w1);
}

int main(void)
{
    run((const double[]){1.0 / 1024.0, 1.0, 1024.0}, 64, 1);
    run((const double[]){1e-3, 1.0, 1e3}, 256, 0);
    TEST_END();
}
