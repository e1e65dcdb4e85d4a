/* The spectral film: pass images of XYZ then bins, summed per pixel and
 * divided by the samples; a pixel's pass with a non-finite bin is left out
 * whole; channel names of the spectral layout; the render loop's pass
 * images carry the bins (a backend that fills them, through spm_render_run). */
#include <stdlib.h>
#include <string.h>
#include "film_spectral.h"
#include "render_run.h"
#include "spectral_exr.h"
#include "testutil.h"

enum { W = 3, H = 2, N = W * H, NB = 4, CH = 3 + NB };

static void passes(void)
{
    spm_film f;
    spm_error err;
    CHECK(spm_film_init(&f, W, H, &err) == 0 && spm_film_spectral_init(&f, NB, &err) == 0, "%s",
          err.msg);
    float pass[N * CH];
    /* pass k of spp k+1: pixel i, channel c holds (k+1) * (i + 1) * (c + 1) */
    for (int k = 0; k < 3; k++) {
        for (int i = 0; i < N; i++)
            for (int c = 0; c < CH; c++)
                pass[i * CH + c] = (float)((k + 1) * (i + 1) * (c + 1));
        if (k == 2)
            pass[4 * CH + 3 + 2] = NAN; /* pixel 4's last pass is dropped whole */
        spm_film_add_pass(&f, pass, k + 1);
    }
    float xyz[N * 3], spec[N * NB];
    spm_film_resolve(&f, xyz);
    spm_film_resolve_spectrum(&f, spec);
    CHECK(f.nonfinite == 1, "%lld non-finite pixel passes", f.nonfinite);
    for (int i = 0; i < N; i++) {
        /* sums over passes: (1 + 2 + 3) * (i+1) * (c+1) over 6 samples; pixel 4 without the third */
        double scale = i == 4 ? 3.0 / 6.0 : 6.0 / 6.0;
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(xyz[i * 3 + c], scale * (i + 1) * (c + 1), 1e-5, "XYZ");
        for (int b = 0; b < NB; b++)
            CHECK_NEAR(spec[i * NB + b], scale * (i + 1) * (b + 4), 1e-5, "bin");
    }
    spm_film_free(&f);
}

static void names(void)
{
    char buf[32];
    spm_spectral_channel_name(0, 80, buf, sizeof buf);
    CHECK(!strcmp(buf, "S0.382,5nm"), "%s", buf);
    spm_spectral_channel_name(79, 80, buf, sizeof buf);
    CHECK(!strcmp(buf, "S0.777,5nm"), "%s", buf);
    spm_spectral_channel_name(0, 400, buf, sizeof buf);
    CHECK(!strcmp(buf, "S0.380,5nm"), "%s", buf);
    spm_spectral_channel_name(10, 40, buf, sizeof buf);
    CHECK(!strcmp(buf, "S0.485nm"), "%s", buf);
    CHECK(spm_spectral_path("a/b.SPECTRAL.exr") && !spm_spectral_path("b.exr") &&
              !spm_spectral_path(".spectral.exr"),
          "spectral file names");
}

/* A backend whose pass pixel is XYZ = spp, bins = spp * (b + 1). */
static int fake_pass(spm_backend *b, spm_u32 first, spm_u32 spp, float *img, spm_pass_stats *st,
                     spm_error *err)
{
    (void)b, (void)first, (void)err;
    for (int i = 0; i < N; i++)
        for (int c = 0; c < CH; c++)
            img[i * CH + c] = (float)spp * (c < 3 ? 1.0f : (float)(c - 2));
    st->paths += (uint64_t)N * spp;
    return 0;
}

static void render_loop(void)
{
    spm_film f;
    spm_error err;
    spm_film_init(&f, W, H, &err);
    spm_film_spectral_init(&f, NB, &err);
    spm_backend be;
    memset(&be, 0, sizeof be);
    be.pass = fake_pass;
    spm_backend *b = &be;
    spm_run_opts o = {.spp = 10, .spp_per_pass = 3, .stop = NULL, .progress = 0};
    spm_run_result r;
    CHECK(spm_render_run(&b, 1, N, &o, &f, &r, &err) == 0, "%s", err.msg);
    float spec[N * NB];
    spm_film_resolve_spectrum(&f, spec);
    for (int i = 0; i < N * NB; i++)
        CHECK_NEAR(spec[i], (float)(i % NB + 1), 1e-6, "bin through the render loop");
    spm_film_free(&f);
}

int main(void)
{
    passes();
    names();
    render_loop();
    TEST_END();
}
