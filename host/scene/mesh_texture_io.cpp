// A texture's mean colour through OpenImageIO 2.4 behind a C interface
// (mesh_texture.h). Runs in the mesh importer's child process, under its
// resource limits, as Assimp does.
#include "mesh_texture.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <strings.h>
#include <vector>

extern "C" {
#include "colour.h"
}

using OIIO::ImageInput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

static int fail(char *why, size_t n, const std::string &msg)
{
    snprintf(why, n, "%s", msg.empty() ? "unknown format" : msg.c_str());
    return 1;
}

static int mean_of(std::unique_ptr<ImageInput> in, float mean[3], char *why, size_t whylen);

extern "C" int spm_texture_mean_file(const spm_file *file, float mean[3], char *why,
                                     size_t whylen)
{
    OIIO::attribute("threads", 1); // a forked child: no pool threads of the parent's
    auto in = ImageInput::open(file->path);
    if (!in)
        return fail(why, whylen, OIIO::geterror());
    return mean_of(std::move(in), mean, why, whylen);
}

extern "C" int spm_texture_mean_data(const char *hint, const void *data, size_t size,
                                     float mean[3], char *why, size_t whylen)
{
    OIIO::attribute("threads", 1);
    OIIO::Filesystem::IOMemReader mem(data, size);
    auto in = ImageInput::open(hint, nullptr, &mem);
    if (!in)
        return fail(why, whylen, OIIO::geterror());
    return mean_of(std::move(in), mean, why, whylen);
}

static int mean_of(std::unique_ptr<ImageInput> in, float mean[3], char *why, size_t whylen)
{
    const ImageSpec &spec = in->spec();
    long long npix = (long long)spec.width * spec.height;
    if (spec.deep || spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.nchannels < 1 ||
        npix > SPM_TEXTURE_MAX_PIXELS) {
        char msg[128];
        snprintf(msg, sizeof msg, "unsupported image (%dx%d, %d channels%s)", spec.width,
                 spec.height, spec.nchannels, spec.deep ? ", deep" : "");
        return fail(why, whylen, msg);
    }
    int nch = spec.nchannels >= 3 ? 3 : 1; // one or two channels: grey (and alpha)
    std::vector<float> buf((size_t)npix * nch);
    if (!in->read_image(0, 0, 0, nch, TypeDesc::FLOAT, buf.data()))
        return fail(why, whylen, in->geterror());
    // integer codes are sRGB-encoded unless the file says linear (as image_io.cpp
    // reads images); the mean is of linear values: mean_c = sum_i decode(v_ic) / n
    bool encoded = !spec.format.is_floating_point() &&
                   strcasecmp(spec.get_string_attribute("oiio:ColorSpace").c_str(), "linear") != 0;
    double sum[3] = {0, 0, 0};
    for (long long i = 0; i < npix; i++)
        for (int c = 0; c < 3; c++) {
            double v = buf[(size_t)i * nch + (nch == 3 ? c : 0)];
            sum[c] += encoded ? spm_srgb_decode(v) : v;
        }
    for (int c = 0; c < 3; c++) {
        mean[c] = (float)(sum[c] / (double)npix);
        if (!std::isfinite(mean[c]))
            return fail(why, whylen, "pixels that are not finite numbers");
    }
    return 0;
}
