/* The bench's in-memory comparison: a film's image is the film's mean XYZ in
 * linear sRGB, and spm_bench_delta_e leaves both images as they were (the
 * compare API blurs its inputs in place, and the bench compares one image
 * many times). */
#include <stdlib.h>
#include <string.h>
#include "bench_image.h"
#include "colour.h"
#include "testutil.h"

#define W 5
#define H 4

int main(void)
{
    spm_error err;
    spm_film film;
    CHECK(spm_film_init(&film, W, H, &err) == 0, "%s", err.msg);
    float pass[3 * W * H];
    for (int i = 0; i < W * H; i++) /* a gradient, so a blur would change it */
        for (int c = 0; c < 3; c++)
            pass[3 * i + c] = 2.0f * (0.05f + 0.04f * (float)i) * (0.9f + 0.1f * (float)c);
    spm_film_add_pass(&film, pass, 2);

    spm_image a;
    spm_bench_film_image(&film, &a);
    CHECK(a.width == W && a.height == H, "size %dx%d", a.width, a.height);
    /* the film holds sums of 2 samples: the image is M * (sum / 2); float
     * storage of values below 2 rounds at 1.2e-7 relative, so 1e-6 is ample */
    for (int i = 0; i < W * H; i++) {
        double xyz[3] = {pass[3 * i] / 2.0, pass[3 * i + 1] / 2.0, pass[3 * i + 2] / 2.0}, rgb[3];
        spm_xyz_to_linear_srgb(xyz, rgb);
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(a.rgb[3 * i + c], rgb[c], 1e-6, "pixel channel");
    }

    size_t bytes = sizeof(float) * 3 * W * H;
    float *keep = malloc(bytes);
    memcpy(keep, a.rgb, bytes);
    spm_de_stats st;
    CHECK(spm_bench_delta_e(&a, &a, 3, &st, &err) == 0, "%s", err.msg);
    CHECK(st.mean == 0.0 && st.max == 0.0, "identical images: mean %g max %g", st.mean, st.max);
    CHECK(memcmp(keep, a.rgb, bytes) == 0, "the reference image was changed");

    spm_image b = {W, H, malloc(bytes), 0};
    for (int i = 0; i < 3 * W * H; i++)
        b.rgb[i] = 0.5f * a.rgb[i];
    CHECK(spm_bench_delta_e(&a, &b, 3, &st, &err) == 0, "%s", err.msg);
    CHECK(st.mean > 1.0, "half the light must be a visible difference, got %g", st.mean);
    CHECK(memcmp(keep, a.rgb, bytes) == 0, "the reference image was changed");

    spm_image small = {W - 1, H, b.rgb, 0};
    CHECK(spm_bench_delta_e(&a, &small, 3, &st, &err) != 0, "different sizes accepted");

    free(keep);
    spm_image_free(&b);
    spm_image_free(&a);
    spm_film_free(&film);
    TEST_END();
}
