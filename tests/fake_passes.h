/* Pass images of stand-in devices for the render loop's tests (no OpenCL):
 * a sample's XYZ is a function of (pixel, sample) only, with all 24 mantissa
 * bits in use so that any change of summation order shows in the film.
 * Include after defining NPIX, the image's pixels. */
#ifndef SPM_FAKE_PASSES_H
#define SPM_FAKE_PASSES_H
#include <stddef.h>
#include "render_run.h"

static inline float fake_sample_value(size_t pix, spm_u32 sample, int c)
{
    spm_u32 h = (spm_u32)pix * 2654435761u ^ (sample + 1u) * 2246822519u ^ (spm_u32)c * 3266489917u;
    h ^= h >> 15;
    h *= 2246822519u;
    h ^= h >> 13;
    return (float)(h >> 8) * (1.0f / 16777216.0f) * 97.0f;
}

/* A pass image: per pixel the float sum of its samples [first, first + spp) in order. */
static inline void fake_pass_image(spm_u32 first, spm_u32 spp, float *img)
{
    for (size_t i = 0; i < NPIX; i++)
        for (int c = 0; c < 3; c++) {
            float sum = 0.0f;
            for (spm_u32 s = first; s < first + spp; s++)
                sum += fake_sample_value(i, s, c);
            img[3 * i + c] = sum;
        }
}
#endif
