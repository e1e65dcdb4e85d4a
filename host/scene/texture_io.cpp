// Image textures read through OpenImageIO 2.4 behind a C interface
// (texture.h): linear RGB texels, rows top to bottom. The mesh importer's
// child reads with it too (mesh_texture_io.cpp), under its resource limits.
#include "texture.h"
#include "mesh_texture.h" // SPM_TEXTURE_MAX_PIXELS

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
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

static int read_linear(std::unique_ptr<ImageInput> in, float **rgb, int *w, int *h, char *why,
                       size_t whylen, bool data = false)
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
    // reads images); float and half are linear already
    bool encoded = !data && !spec.format.is_floating_point() &&
                   strcasecmp(spec.get_string_attribute("oiio:ColorSpace").c_str(), "linear") != 0;
    float *out = (float *)malloc(sizeof(float) * 3 * (size_t)npix);
    if (!out)
        return fail(why, whylen, "out of memory");
    for (long long i = 0; i < npix; i++)
        for (int c = 0; c < 3; c++) {
            double v = buf[(size_t)i * nch + (nch == 3 ? c : 0)];
            v = encoded ? spm_srgb_decode(v) : v;
            if (!std::isfinite(v)) {
                free(out);
                return fail(why, whylen, "pixels that are not finite numbers");
            }
            out[3 * i + c] = (float)v;
        }
    *rgb = out;
    *w = spec.width;
    *h = spec.height;
    return 0;
}

// One channel as stored, no sRGB decoding (opacity is data, not colour): the
// alpha channel when the file has one (RGBA, grey and alpha), else the first;
// alpha_only -1 - c: channel c (the first when the image has fewer).
static int read_alpha(std::unique_ptr<ImageInput> in, int alpha_only, float **a, int *w, int *h,
                      char *why, size_t whylen)
{
    const ImageSpec &spec = in->spec();
    long long npix = (long long)spec.width * spec.height;
    if (spec.deep || spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.nchannels < 1 ||
        npix > SPM_TEXTURE_MAX_PIXELS)
        return fail(why, whylen, "unsupported image");
    int ch = alpha_only < 0 ? (-alpha_only - 1 < spec.nchannels ? -alpha_only - 1 : 0)
             : spec.alpha_channel >= 0 ? spec.alpha_channel
             : spec.nchannels == 2 || spec.nchannels == 4 ? spec.nchannels - 1 : -1;
    *a = nullptr;
    if (ch < 0 && alpha_only)
        return 0;
    ch = ch < 0 ? 0 : ch;
    float *out = (float *)malloc(sizeof(float) * (size_t)npix);
    if (!out)
        return fail(why, whylen, "out of memory");
    if (!in->read_image(0, 0, ch, ch + 1, TypeDesc::FLOAT, out)) {
        free(out);
        return fail(why, whylen, in->geterror());
    }
    for (long long i = 0; i < npix; i++)
        if (!std::isfinite(out[i])) {
            free(out);
            return fail(why, whylen, "pixels that are not finite numbers");
        }
    *a = out;
    *w = spec.width;
    *h = spec.height;
    return 0;
}

// An image's reader: a file by its path, bytes through an in-memory proxy
// (OpenImageIO's IOMemReader, named in the configuration, where a proxy
// passed beside a configuration is lost). unassoc: colours as the file
// stores them (a PNG's (or TIFF's) colour beside an alpha channel is not
// premultiplied by it: OpenImageIO's default would darken a cut-out's texels
// towards its transparent ones; glTF's base colour is not premultiplied).
static std::unique_ptr<ImageInput> open_src(const spm_image_src *src, bool unassoc,
                                            OIIO::Filesystem::IOMemReader *mem)
{
    OIIO::attribute("threads", 1); // a forked child: no pool threads of the parent's
    ImageSpec config;
    if (unassoc)
        config.attribute("oiio:UnassociatedAlpha", 1);
    if (src->file)
        return ImageInput::open(src->file->path, unassoc ? &config : nullptr);
    void *proxy = mem;
    config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
    return ImageInput::open(std::string("embedded.") + (src->hint ? src->hint : "png"), &config,
                            mem);
}

extern "C" int spm_texture_read(const spm_image_src *src, int as, float **rgb, int *w, int *h,
                                char *why, size_t whylen)
{
    OIIO::Filesystem::IOMemReader mem(src->data, src->file ? 0 : src->size);
    auto in = open_src(src, true, &mem);
    if (!in)
        return fail(why, whylen, OIIO::geterror());
    return read_linear(std::move(in), rgb, w, h, why, whylen, as == SPM_IMAGE_DATA);
}

extern "C" int spm_texture_read_one(const spm_image_src *src, int which, float **a, int *w,
                                    int *h, char *why, size_t whylen)
{
    OIIO::Filesystem::IOMemReader mem(src->data, src->file ? 0 : src->size);
    auto in = open_src(src, false, &mem);
    if (!in)
        return fail(why, whylen, OIIO::geterror());
    return read_alpha(std::move(in), which, a, w, h, why, whylen);
}

extern "C" int spm_texture_read_alpha_file(const spm_file *file, int alpha_only, float **a,
                                           int *w, int *h, char *why, size_t whylen)
{
    spm_image_src src = {file, nullptr, 0, nullptr};
    return spm_texture_read_one(&src, alpha_only, a, w, h, why, whylen);
}

extern "C" int spm_texture_read_channel_file(const spm_file *file, int channel, float **a,
                                             int *w, int *h, char *why, size_t whylen)
{
    spm_image_src src = {file, nullptr, 0, nullptr};
    return spm_texture_read_one(&src, -1 - channel, a, w, h, why, whylen);
}

extern "C" int spm_texture_read_file(const spm_file *file, float **rgb, int *w, int *h,
                                     char *why, size_t whylen)
{
    spm_image_src src = {file, nullptr, 0, nullptr};
    return spm_texture_read(&src, SPM_IMAGE_COLOUR, rgb, w, h, why, whylen);
}

extern "C" int spm_texture_read_data_file(const spm_file *file, float **rgb, int *w, int *h,
                                          char *why, size_t whylen)
{
    spm_image_src src = {file, nullptr, 0, nullptr};
    return spm_texture_read(&src, SPM_IMAGE_DATA, rgb, w, h, why, whylen);
}

extern "C" int spm_texture_read_data(const char *hint, const void *data, size_t size,
                                     float **rgb, int *w, int *h, char *why, size_t whylen)
{
    spm_image_src src = {nullptr, data, size, hint};
    return spm_texture_read(&src, SPM_IMAGE_COLOUR, rgb, w, h, why, whylen);
}
