// A texture's mean colour (mesh_texture.h): the image read as linear RGB by
// texture_io.cpp, averaged. Runs in the mesh importer's child process.
#include "mesh_texture.h"
#include "texture.h"

#include <cmath>
#include <cstdlib>

static int mean_of(float *rgb, int w, int h, float mean[3], char *why, size_t whylen)
{
    // mean_c = sum_i v_ic / n, summed in double
    double sum[3] = {0, 0, 0};
    long long npix = (long long)w * h;
    for (long long i = 0; i < npix; i++)
        for (int c = 0; c < 3; c++)
            sum[c] += rgb[3 * i + c];
    free(rgb);
    for (int c = 0; c < 3; c++) {
        mean[c] = (float)(sum[c] / (double)npix);
        if (!std::isfinite(mean[c])) {
            snprintf(why, whylen, "pixels whose mean is not a finite number");
            return 1;
        }
    }
    return 0;
}

extern "C" int spm_texture_mean_file(const spm_file *file, float mean[3], char *why,
                                     size_t whylen)
{
    float *rgb;
    int w, h;
    if (spm_texture_read_file(file, &rgb, &w, &h, why, whylen))
        return 1;
    return mean_of(rgb, w, h, mean, why, whylen);
}

extern "C" int spm_texture_mean_data(const char *hint, const void *data, size_t size,
                                     float mean[3], char *why, size_t whylen)
{
    float *rgb;
    int w, h;
    if (spm_texture_read_data(hint, data, size, &rgb, &w, &h, why, whylen))
        return 1;
    return mean_of(rgb, w, h, mean, why, whylen);
}
