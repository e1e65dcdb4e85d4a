// Reads a spectral OpenEXR file back with OpenImageIO and checks it against
// independent computations (the shell test cli_render_spectral.sh runs it):
//   the layout: spectralLayoutVersion "1.0", emissiveUnits "W.m^-2.sr^-1",
//     R, G, B and S0.<wavelength>nm channels with a comma as decimal
//     separator, at evenly spaced bin centres covering 380-780 nm;
//   --xyz REF.exr TOL: every pixel integrated with the CIE 1931 CMFs (read
//     here from the CSV, 683 lm/W) gives REF's XYZ (REF: the same render's
//     linear-sRGB .exr) within TOL times the pixel's |X|+|Y|+|Z|;
//   --xyz-mean REF.exr TOL: the same for the image's mean XYZ;
//   --lamp CSV LUM X Y TOL: pixel (X, Y) holds the lamp's spectrum (CSV of
//     wavelength,value, at luminance LUM cd/m^2) bin by bin within TOL times
//     its largest bin;
//   --energy CSV LUM X Y TOL: pixel (X, Y) holds the lamp's total radiance
//     (sum over the bins) within TOL of it.
// Prints what it finds; exits 0 if every check holds, 1 if one fails, 2 on
// bad input.
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using OIIO::ImageInput;
using OIIO::TypeDesc;

static int failures = 0;
#define FAIL(...) (std::fprintf(stderr, "spectral_check: FAIL: " __VA_ARGS__), std::fputc('\n', stderr), failures++)

// A tabulated function, linear between its points, zero outside them.
struct table {
    std::vector<double> x;
    std::vector<std::vector<double>> y; // per column
    double at(int col, double w) const
    {
        if (x.empty() || w < x.front() || w > x.back())
            return 0.0;
        size_t k = 1;
        while (k < x.size() - 1 && x[k] < w)
            k++;
        double f = (w - x[k - 1]) / (x[k] - x[k - 1]);
        return y[col][k - 1] + f * (y[col][k] - y[col][k - 1]);
    }
    // Mean over [a, a + 1]: the function is linear there when its points are
    // at whole nanometres (both CSVs used are), so the trapezoid is exact.
    double mean1(int col, double a) const { return 0.5 * (at(col, a) + at(col, a + 1.0)); }
};

static table read_csv(const char *path, int ncols)
{
    std::ifstream f(path);
    if (!f) {
        std::fprintf(stderr, "spectral_check: cannot read %s\n", path);
        std::exit(2);
    }
    table t;
    t.y.resize(ncols);
    std::string line;
    while (std::getline(f, line)) {
        if (line.empty() || line[0] == '#' || !(std::isdigit((unsigned char)line[0])))
            continue;
        std::stringstream ss(line);
        std::string cell;
        std::vector<double> v;
        while (std::getline(ss, cell, ','))
            v.push_back(std::atof(cell.c_str()));
        if ((int)v.size() < ncols + 1)
            continue;
        t.x.push_back(v[0]);
        for (int c = 0; c < ncols; c++)
            t.y[c].push_back(v[1 + c]);
    }
    return t;
}

struct image {
    int w = 0, h = 0, nch = 0;
    std::vector<float> px;
    std::vector<std::string> names;
    OIIO::ImageSpec spec;
};

static image read_image(const char *path)
{
    image im;
    auto in = ImageInput::open(path);
    if (!in) {
        std::fprintf(stderr, "spectral_check: cannot open %s: %s\n", path, OIIO::geterror().c_str());
        std::exit(2);
    }
    im.spec = in->spec();
    im.w = im.spec.width, im.h = im.spec.height, im.nch = im.spec.nchannels;
    im.names = im.spec.channelnames;
    im.px.resize((size_t)im.w * im.h * im.nch);
    if (!in->read_image(0, 0, 0, im.nch, TypeDesc::FLOAT, im.px.data())) {
        std::fprintf(stderr, "spectral_check: cannot read %s: %s\n", path, in->geterror().c_str());
        std::exit(2);
    }
    return im;
}

static int channel(const image &im, const std::string &name)
{
    for (int c = 0; c < im.nch; c++)
        if (im.names[c] == name)
            return c;
    return -1;
}

// sRGB (D65) to XYZ, IEC 61966-2-1.
static void rgb_to_xyz(const float *rgb, double xyz[3])
{
    static const double m[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                   {0.2126729, 0.7151522, 0.0721750},
                                   {0.0193339, 0.1191920, 0.9503041}};
    for (int r = 0; r < 3; r++)
        xyz[r] = m[r][0] * rgb[0] + m[r][1] * rgb[1] + m[r][2] * rgb[2];
}

int main(int argc, char **argv)
{
    if (argc < 4 || std::string(argv[2]) != "--cmf") {
        std::fprintf(stderr, "usage: spectral_check FILE --cmf CMF.csv [checks]\n");
        return 2;
    }
    image im = read_image(argv[1]);
    table cmf = read_csv(argv[3], 3);

    // the layout
    std::string ver = im.spec.get_string_attribute("spectralLayoutVersion");
    std::string units = im.spec.get_string_attribute("emissiveUnits");
    if (ver != "1.0")
        FAIL("spectralLayoutVersion is '%s', not '1.0'", ver.c_str());
    if (units != "W.m^-2.sr^-1")
        FAIL("emissiveUnits is '%s'", units.c_str());
    int cr = channel(im, "R"), cg = channel(im, "G"), cb = channel(im, "B");
    if (cr < 0 || cg < 0 || cb < 0)
        FAIL("no R, G, B preview channels");
    std::vector<int> sch;
    std::vector<double> centre;
    for (int c = 0; c < im.nch; c++) {
        const std::string &n = im.names[c];
        if (n.rfind("S0.", 0) != 0)
            continue;
        if (n.size() < 6 || n.substr(n.size() - 2) != "nm" || n.find('.', 3) != std::string::npos) {
            FAIL("channel '%s' is not S0.<number>nm with a comma", n.c_str());
            continue;
        }
        std::string num = n.substr(3, n.size() - 5);
        size_t comma = num.find(',');
        if (comma != std::string::npos)
            num[comma] = '.';
        sch.push_back(c);
        centre.push_back(std::atof(num.c_str()));
    }
    size_t nb = sch.size();
    if (nb < 2) {
        FAIL("%zu spectral channels", nb);
        return 1;
    }
    // order by wavelength (EXR keeps channels sorted by name)
    for (size_t i = 0; i < nb; i++)
        for (size_t j = i + 1; j < nb; j++)
            if (centre[j] < centre[i]) {
                std::swap(centre[i], centre[j]);
                std::swap(sch[i], sch[j]);
            }
    double width = (centre.back() - centre.front()) / (double)(nb - 1);
    for (size_t i = 0; i < nb; i++)
        if (std::fabs(centre[i] - (380.0 + width * (i + 0.5))) > 1e-6)
            FAIL("bin %zu centre %g is not 380 + %g * (%zu + 1/2)", i, centre[i], width, i);
    if (std::fabs(width * nb - 400.0) > 1e-6)
        FAIL("%zu bins of %g nm do not cover 380-780 nm", nb, width);
    int w1 = (int)std::lround(width);
    std::printf("%s: %dx%d, %zu bins of %g nm\n", argv[1], im.w, im.h, nb, width);

    // the CMFs integrated over each bin, from the 1 nm means
    std::vector<double> cbin[3];
    for (int k = 0; k < 3; k++) {
        cbin[k].assign(nb, 0.0);
        for (size_t b = 0; b < nb; b++)
            for (int j = 0; j < w1; j++)
                cbin[k][b] += cmf.mean1(k, 380.0 + (double)b * w1 + j);
    }
    auto spectral_xyz = [&](size_t p, double xyz[3]) {
        for (int k = 0; k < 3; k++) {
            double s = 0.0;
            for (size_t b = 0; b < nb; b++)
                s += (double)im.px[p * im.nch + sch[b]] * cbin[k][b];
            xyz[k] = 683.0 * s;
        }
    };
    size_t npix = (size_t)im.w * im.h;

    for (int i = 4; i < argc; i++) {
        std::string opt = argv[i];
        if ((opt == "--xyz" || opt == "--xyz-mean") && i + 2 < argc) {
            image ref = read_image(argv[i + 1]);
            double tol = std::atof(argv[i + 2]);
            i += 2;
            if (ref.w != im.w || ref.h != im.h || ref.nch < 3) {
                FAIL("%s is %dx%d with %d channels", argv[i - 1], ref.w, ref.h, ref.nch);
                continue;
            }
            double worst = 0.0, sum_s[3] = {0, 0, 0}, sum_r[3] = {0, 0, 0};
            size_t worst_p = 0;
            for (size_t p = 0; p < npix; p++) {
                double s[3], r[3];
                spectral_xyz(p, s);
                rgb_to_xyz(&ref.px[p * ref.nch], r);
                double norm = std::fabs(r[0]) + std::fabs(r[1]) + std::fabs(r[2]) + 1e-30;
                for (int k = 0; k < 3; k++) {
                    sum_s[k] += s[k], sum_r[k] += r[k];
                    double e = std::fabs(s[k] - r[k]) / norm;
                    if (e > worst)
                        worst = e, worst_p = p;
                }
            }
            if (opt == "--xyz") {
                std::printf("  per pixel: largest |XYZ error| / (|X|+|Y|+|Z|) %.3g at (%zu, %zu)\n",
                            worst, worst_p % im.w, worst_p / im.w);
                if (!(worst <= tol))
                    FAIL("pixel (%zu, %zu): spectral XYZ off by %.3g of the film's (tolerance %g)",
                         worst_p % im.w, worst_p / im.w, worst, tol);
            } else {
                double norm = std::fabs(sum_r[0]) + std::fabs(sum_r[1]) + std::fabs(sum_r[2]);
                double e = 0.0;
                for (int k = 0; k < 3; k++)
                    e = std::fmax(e, std::fabs(sum_s[k] - sum_r[k]) / norm);
                std::printf("  image mean: spectral XYZ %.6g %.6g %.6g, film %.6g %.6g %.6g: "
                            "off by %.3g\n", sum_s[0] / npix, sum_s[1] / npix, sum_s[2] / npix,
                            sum_r[0] / npix, sum_r[1] / npix, sum_r[2] / npix, e);
                if (!(e <= tol))
                    FAIL("image mean XYZ off by %.3g (tolerance %g)", e, tol);
            }
        } else if ((opt == "--lamp" || opt == "--energy") && i + 5 < argc) {
            table lamp = read_csv(argv[i + 1], 1);
            double lum = std::atof(argv[i + 2]);
            size_t x = (size_t)std::atol(argv[i + 3]), y = (size_t)std::atol(argv[i + 4]);
            double tol = std::atof(argv[i + 5]);
            i += 5;
            // the lamp at luminance lum: 683 * sum of (1 nm means) * y-bar = lum
            std::vector<double> nm1(400);
            double yraw = 0.0;
            for (int j = 0; j < 400; j++) {
                nm1[j] = lamp.mean1(0, 380.0 + j);
                yraw += nm1[j] * cmf.mean1(1, 380.0 + j);
            }
            std::vector<double> want(nb, 0.0);
            double peak = 0.0, total_want = 0.0, total_got = 0.0, worst = 0.0;
            size_t worst_b = 0;
            const float *px = &im.px[(y * im.w + x) * im.nch];
            for (size_t b = 0; b < nb; b++) {
                for (int j = 0; j < w1; j++)
                    want[b] += nm1[b * w1 + j] * lum / (683.0 * yraw) / w1;
                peak = std::fmax(peak, want[b]);
                total_want += want[b] * width;
                total_got += px[sch[b]] * width;
            }
            for (size_t b = 0; b < nb; b++) {
                double e = std::fabs(px[sch[b]] - want[b]) / peak;
                if (e > worst)
                    worst = e, worst_b = b;
            }
            if (opt == "--lamp") {
                std::printf("  pixel (%zu, %zu) against the lamp: largest bin error %.3g of the "
                            "peak (%g nm: %.6g, lamp %.6g)\n", x, y, worst, centre[worst_b],
                            px[sch[worst_b]], want[worst_b]);
                if (!(worst <= tol))
                    FAIL("pixel (%zu, %zu) bin %g nm is %.6g, the lamp's %.6g (tolerance %g of "
                         "the peak %.6g)", x, y, centre[worst_b], px[sch[worst_b]], want[worst_b],
                         tol, peak);
            } else {
                double e = std::fabs(total_got - total_want) / total_want;
                std::printf("  pixel (%zu, %zu): radiance %.6g W/m^2/sr, the lamp's %.6g: off "
                            "by %.3g\n", x, y, total_got, total_want, e);
                if (!(e <= tol))
                    FAIL("pixel (%zu, %zu) radiance %.6g, the lamp's %.6g (tolerance %g)", x, y,
                         total_got, total_want, tol);
            }
        } else {
            std::fprintf(stderr, "spectral_check: unknown or incomplete check '%s'\n", argv[i]);
            return 2;
        }
    }
    return failures ? 1 : 0;
}
