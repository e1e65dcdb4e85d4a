// Image files through OpenImageIO 2.4 behind a C interface (image_io.h).
#include "image_io.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <strings.h>
#include <unistd.h>
#include <vector>

extern "C" {
#include "colour.h"
#include "interrupt.h"
}
#include <climits>
#include <sys/stat.h>

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

// Bounds the allocation a hostile header could ask for (3 floats per pixel).
static const long long MAX_PIXELS = 1LL << 28;

extern "C" int spm_image_read(const char *path, spm_image *img, spm_error *err)
{
    img->width = img->height = 0;
    img->rgb = nullptr;
    auto in = ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
        spm_errorf(err, "%s: cannot read image: %s", path, why.empty() ? "unknown format" : why.c_str());
        return 1;
    }
    const ImageSpec &spec = in->spec();
    long long npix = (long long)spec.width * spec.height;
    if (spec.deep || spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || npix > MAX_PIXELS ||
        spec.nchannels < 1) {
        spm_errorf(err, "%s: unsupported image (%dx%d, %d channels%s)", path, spec.width,
                   spec.height, spec.nchannels, spec.deep ? ", deep" : "");
        return 1;
    }
    int nch = spec.nchannels >= 3 ? 3 : 1;
    std::vector<float> buf((size_t)npix * nch);
    if (!in->read_image(0, 0, 0, nch, TypeDesc::FLOAT, buf.data())) {
        spm_errorf(err, "%s: cannot read pixels: %s", path, in->geterror().c_str());
        return 1;
    }
    // Integer pixels are display-encoded by convention unless the file says linear.
    bool encoded = !spec.format.is_floating_point() &&
                   strcasecmp(spec.get_string_attribute("oiio:ColorSpace").c_str(), "linear") != 0;
    float *rgb = (float *)spm_xmalloc((size_t)npix * 3 * sizeof(float));
    for (long long i = 0; i < npix; i++)
        for (int c = 0; c < 3; c++) {
            float v = buf[(size_t)i * nch + (nch == 3 ? c : 0)];
            rgb[i * 3 + c] = encoded ? (float)spm_srgb_decode(v) : v;
        }
    img->width = spec.width;
    img->height = spec.height;
    img->rgb = rgb;
    img->encoded = encoded;
    return 0;
}

extern "C" void spm_image_free(spm_image *img)
{
    free(img->rgb);
    img->rgb = nullptr;
    img->width = img->height = 0;
}

extern "C" int spm_image_can_write(const char *path)
{
    auto out = ImageOutput::create(path);
    OIIO::geterror(); // clear the message a failed lookup leaves behind
    return out != nullptr;
}

static std::string dir_of(const std::string &p)
{
    size_t slash = p.rfind('/');
    return slash == std::string::npos ? "." : slash == 0 ? "/" : p.substr(0, slash);
}

static std::string base_of(const std::string &p)
{
    size_t slash = p.rfind('/');
    return slash == std::string::npos ? p : p.substr(slash + 1);
}

extern "C" char *spm_image_target(const char *path, spm_error *err)
{
    std::string t = path;
    for (int hops = 0;; hops++) {
        struct stat st;
        if (lstat(t.c_str(), &st) != 0 || !S_ISLNK(st.st_mode))
            break;
        if (hops == 40) {
            spm_errorf(err, "%s: too many levels of symbolic links", path);
            return nullptr;
        }
        std::vector<char> buf((size_t)st.st_size + PATH_MAX + 1);
        ssize_t n = readlink(t.c_str(), buf.data(), buf.size() - 1);
        if (n < 0) {
            spm_errorf(err, "%s: cannot read the symbolic link: %s", path, strerror(errno));
            return nullptr;
        }
        std::string link(buf.data(), (size_t)n);
        t = link[0] == '/' ? link : dir_of(t) + "/" + link;
    }
    std::string dir = dir_of(t), base = base_of(t);
    char *real = realpath(dir.c_str(), nullptr);
    if (!real) {
        if (t == path)
            spm_errorf(err, "%s: output directory '%s' does not exist", path, dir.c_str());
        else
            spm_errorf(err, "%s: symbolic link to '%s', whose directory does not exist", path,
                       t.c_str());
        return nullptr;
    }
    std::string out = std::string(real) + (real[1] ? "/" : "") + base;
    free(real);
    return spm_xstrdup(out.c_str());
}

// A fresh, exclusively created file next to `target`, with the extension `ext`
// (some writers look at it): dir/.base.spmtmp-PID-N.ext. Registered as a
// temporary file (interrupt.h) in *slot from before it exists.
static std::string make_temp(const std::string &target, const std::string &ext, int *slot,
                             int *errnum)
{
    std::string dir = dir_of(target), base = base_of(target);
    size_t dot = base.rfind('.');
    std::string stem = dot == std::string::npos || dot == 0 ? base : base.substr(0, dot);
    for (int n = 0; n < 100; n++) {
        std::string tmp = dir + "/." + stem + ".spmtmp-" + std::to_string((long)getpid()) + "-" +
                          std::to_string(n) + ext;
        *slot = spm_temp_register(tmp.c_str());
        int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd >= 0) {
            close(fd);
            return tmp;
        }
        int e = errno;
        spm_temp_unregister(*slot);
        if (e != EEXIST) {
            *errnum = e;
            return "";
        }
    }
    *errnum = EEXIST;
    return "";
}

extern "C" char *spm_temp_create(const char *target, const char *ext, int *slot, int *errnum)
{
    std::string t = make_temp(target, ext, slot, errnum);
    return t.empty() ? nullptr : spm_xstrdup(t.c_str());
}

extern "C" int spm_image_read_string_attr(const char *path, const char *name, char *buf,
                                          size_t size, spm_error *err)
{
    auto in = ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
        spm_errorf(err, "%s: cannot read image: %s", path,
                   why.empty() ? "unknown format" : why.c_str());
        return -1;
    }
    const OIIO::ParamValue *p = in->spec().find_attribute(name, TypeDesc::STRING);
    if (!p)
        return 0;
    snprintf(buf, size, "%s", p->get_string().c_str());
    return 1;
}

// Typed where the format keeps types (EXR), else as text.
static void put_attrs(ImageSpec &spec, const char *format, const spm_image_attr *a, int n)
{
    bool typed = !strcmp(format, "openexr");
    for (int k = 0; k < n; k++) {
        std::string text;
        switch (a[k].type) {
        case SPM_ATTR_INT:
            if (typed)
                spec.attribute(a[k].name, a[k].i);
            text = std::to_string(a[k].i);
            break;
        case SPM_ATTR_FLOAT: {
            if (typed)
                spec.attribute(a[k].name, a[k].f);
            char buf[32];
            snprintf(buf, sizeof buf, "%.9g", (double)a[k].f);
            text = buf;
            break;
        }
        case SPM_ATTR_STRING:
            text = a[k].s ? a[k].s : "";
            break;
        }
        if (!typed || a[k].type == SPM_ATTR_STRING)
            spec.attribute(a[k].name, text);
    }
}

// Writes the image to a temporary file next to path's target and renames it
// over the target once complete (image_io.h spm_image_write).
static int write_replacing(const char *path, ImageOutput *out, const ImageSpec &spec, TypeDesc td,
                           const void *pixels, spm_error *err)
{
    char *target = spm_image_target(path, err);
    if (!target)
        return 1;
    std::string base = base_of(path);
    size_t dot = base.rfind('.');
    int errnum = 0, slot = -1;
    std::string tmp = make_temp(target, dot == std::string::npos ? "" : base.substr(dot), &slot,
                                &errnum);
    if (tmp.empty()) {
        spm_errorf(err, "%s: cannot create a temporary file next to %s: %s", path, target,
                   strerror(errnum));
        free(target);
        return 1;
    }
    bool ok = out->open(tmp, spec);
    spm_test_pause("write");
    ok = ok && out->write_image(td, pixels);
    ok = out->close() && ok;
    std::string why = out->geterror();
    if (ok && rename(tmp.c_str(), target) != 0) {
        why = std::string("rename: ") + strerror(errno);
        ok = false;
    }
    if (!ok)
        unlink(tmp.c_str());
    spm_temp_unregister(slot);
    free(target);
    if (!ok) {
        spm_errorf(err, "%s: cannot write image: %s", path, why.empty() ? "write failed" : why.c_str());
        return 1;
    }
    return 0;
}

extern "C" int spm_image_write(const char *path, int width, int height, const void *pixels,
                               spm_pixel_type type, spm_error *err)
{
    return spm_image_write_attrs(path, width, height, pixels, type, nullptr, 0, err);
}

extern "C" int spm_image_write_attrs(const char *path, int width, int height, const void *pixels,
                                     spm_pixel_type type, const spm_image_attr *attrs, int nattrs,
                                     spm_error *err)
{
    auto out = ImageOutput::create(path);
    if (!out) {
        OIIO::geterror();
        spm_errorf(err, "%s: no image writer for this file extension", path);
        return 1;
    }
    bool is_float = type == SPM_PIXEL_FLOAT;
    TypeDesc td = is_float ? TypeDesc::FLOAT : TypeDesc::UINT8;
    ImageSpec spec(width, height, 3, td);
    spec.attribute("oiio:ColorSpace", is_float ? "Linear" : "sRGB");
    if (is_float) {
        // IEC 61966-2-1 primaries and D65 white, so EXR readers know what the numbers mean.
        static const float srgb_chroma[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
        spec.attribute("chromaticities", TypeDesc(TypeDesc::FLOAT, 8), srgb_chroma);
    }
    put_attrs(spec, out->format_name(), attrs, nattrs);
    return write_replacing(path, out.get(), spec, td, pixels, err);
}

extern "C" int spm_image_write_channels(const char *path, int width, int height, int nch,
                                        const char *const *names, const float *pixels,
                                        const spm_image_attr *attrs, int nattrs, spm_error *err)
{
    auto out = ImageOutput::create(path);
    if (!out) {
        OIIO::geterror();
        spm_errorf(err, "%s: no image writer for this file extension", path);
        return 1;
    }
    ImageSpec spec(width, height, nch, TypeDesc::FLOAT);
    spec.channelnames.assign(names, names + nch);
    spec.alpha_channel = -1;
    put_attrs(spec, out->format_name(), attrs, nattrs);
    return write_replacing(path, out.get(), spec, TypeDesc::FLOAT, pixels, err);
}
