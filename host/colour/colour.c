/* Colour science: spectrum -> XYZ with the bin-integrated CIE 1931 weights,
 * CIELAB, sRGB (IEC 61966-2-1) and the colour differences ΔE*ab and CIEDE2000. */
#include "colour.h"
#include "csv.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const double PI = 3.14159265358979323846;

void spm_xyz_emission(const spm_spectrum *s, double xyz[3])
{
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    for (int k = 0; k < 3; k++) {
        double sum = 0.0;
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            sum += s->nm1[i] * w[k][i];
        xyz[k] = sum;
    }
}

void spm_xyz_reflectance(const spm_spectrum *r, const spm_spectrum *illum, double xyz[3])
{
    spm_spectrum lit = *illum;
    spm_spectrum_multiply(&lit, r);
    double white[3];
    spm_xyz_emission(illum, white);
    spm_xyz_emission(&lit, xyz);
    double f = white[1] > 0 ? 100.0 / white[1] : 0.0;
    for (int k = 0; k < 3; k++)
        xyz[k] *= f;
}

void spm_xyz_bins(const double *bins, int level, double xyz[3])
{
    double w[3][SPM_TRUTH_BINS];
    spm_cmf_level(level, w);
    for (int k = 0; k < 3; k++) {
        double sum = 0.0;
        for (int b = 0; b < SPM_LEVEL_BINS(level); b++)
            sum += bins[b] * w[k][b];
        xyz[k] = sum;
    }
}

/* CIE 15 constants: epsilon = (6/29)^3, kappa = (29/3)^3. */
#define LAB_EPS (216.0 / 24389.0)
#define LAB_KAPPA (24389.0 / 27.0)

static double lab_f(double t)
{
    return t > LAB_EPS ? cbrt(t) : (LAB_KAPPA * t + 16.0) / 116.0;
}

static double lab_finv(double f)
{
    double t = f * f * f;
    return t > LAB_EPS ? t : (116.0 * f - 16.0) / LAB_KAPPA;
}

void spm_xyz_to_lab(const double xyz[3], const double white[3], double lab[3])
{
    double fx = lab_f(xyz[0] / white[0]), fy = lab_f(xyz[1] / white[1]),
           fz = lab_f(xyz[2] / white[2]);
    lab[0] = 116.0 * fy - 16.0;
    lab[1] = 500.0 * (fx - fy);
    lab[2] = 200.0 * (fy - fz);
}

void spm_lab_to_xyz(const double lab[3], const double white[3], double xyz[3])
{
    double fy = (lab[0] + 16.0) / 116.0;
    double fx = fy + lab[1] / 500.0, fz = fy - lab[2] / 200.0;
    xyz[0] = white[0] * lab_finv(fx);
    xyz[1] = white[1] * lab_finv(fy);
    xyz[2] = white[2] * lab_finv(fz);
}

static void mat3(const double m[3][3], const double in[3], double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = m[r][0] * in[0] + m[r][1] * in[1] + m[r][2] * in[2];
}

/* The matrices as IEC 61966-2-1 publishes them (4 decimals; each is the
 * standard's own, so they are inverse to each other only to about 1e-4). */
void spm_xyz_to_linear_srgb(const double xyz[3], double rgb[3])
{
    /* the inverse of the matrix below to 7 digits, so round trips agree to ~1e-7
     * (the standard's 4-digit pair is off by ~1e-4) */
    static const double m[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                   {-0.9692660, 1.8760108, 0.0415560},
                                   {0.0556434, -0.2040259, 1.0572252}};
    mat3(m, xyz, rgb);
}

void spm_linear_srgb_to_xyz(const double rgb[3], double xyz[3])
{
    /* sRGB primaries and D65 white (IEC 61966-2-1) to 7 digits, as the thesis uses */
    static const double m[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                   {0.2126729, 0.7151522, 0.0721750},
                                   {0.0193339, 0.1191920, 0.9503041}};
    mat3(m, rgb, xyz);
}

void spm_cat_bradford(const double src[3], const double dst[3], double m[3][3])
{
    static const double b[3][3] = {{0.8951, 0.2664, -0.1614},
                                   {-0.7502, 1.7135, 0.0367},
                                   {0.0389, -0.0685, 1.0296}};
    static const double binv[3][3] = {{0.9869929, -0.1470543, 0.1599627},
                                      {0.4323053, 0.5183603, 0.0492912},
                                      {-0.0085287, 0.0400428, 0.9684867}};
    double s[3], d[3], ys = src[1] > 0 ? src[1] : 1.0, yd = dst[1] > 0 ? dst[1] : 1.0;
    double sn[3] = {src[0] / ys, 1.0, src[2] / ys}, dn[3] = {dst[0] / yd, 1.0, dst[2] / yd};
    mat3(b, sn, s);
    mat3(b, dn, d);
    /* m = binv * diag(d / s) * b */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double v = 0.0;
            for (int k = 0; k < 3; k++)
                v += binv[i][k] * (s[k] != 0.0 ? d[k] / s[k] : 1.0) * b[k][j];
            m[i][j] = v;
        }
}

double spm_srgb_encode(double v)
{
    v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

double spm_srgb_decode(double e)
{
    return e <= 0.04045 ? e / 12.92 : pow((e + 0.055) / 1.055, 2.4);
}

double spm_delta_e_ab(const double a[3], const double b[3])
{
    double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
    return sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

static double deg(double rad) { return rad * 180.0 / PI; }
static double rad(double deg) { return deg * PI / 180.0; }

/* Hue angle in degrees [0, 360); 0 for a neutral colour (Sharma 2005, eq. 4). */
static double hue_deg(double b, double a)
{
    if (a == 0.0 && b == 0.0)
        return 0.0;
    double h = deg(atan2(b, a));
    return h < 0.0 ? h + 360.0 : h;
}

/* CIEDE2000 with kL = kC = kH = 1, as formulated by Sharma, Wu & Dalal (2005). */
double spm_delta_e_2000(const double lab1[3], const double lab2[3])
{
    double C1 = hypot(lab1[1], lab1[2]), C2 = hypot(lab2[1], lab2[2]);
    double Cm = 0.5 * (C1 + C2), Cm7 = pow(Cm, 7.0);
    double G = 0.5 * (1.0 - sqrt(Cm7 / (Cm7 + pow(25.0, 7.0))));
    double a1 = (1.0 + G) * lab1[1], a2 = (1.0 + G) * lab2[1];
    double c1 = hypot(a1, lab1[2]), c2 = hypot(a2, lab2[2]);
    double h1 = hue_deg(lab1[2], a1), h2 = hue_deg(lab2[2], a2);

    double dL = lab2[0] - lab1[0], dC = c2 - c1, dh = 0.0;
    if (c1 * c2 != 0.0) {
        dh = h2 - h1;
        if (dh > 180.0)
            dh -= 360.0;
        else if (dh < -180.0)
            dh += 360.0;
    }
    double dH = 2.0 * sqrt(c1 * c2) * sin(rad(0.5 * dh));

    double Lm = 0.5 * (lab1[0] + lab2[0]), cm = 0.5 * (c1 + c2), hm = h1 + h2;
    if (c1 * c2 != 0.0) {
        if (fabs(h1 - h2) <= 180.0)
            hm *= 0.5;
        else
            hm = hm < 360.0 ? 0.5 * (hm + 360.0) : 0.5 * (hm - 360.0);
    }
    double T = 1.0 - 0.17 * cos(rad(hm - 30.0)) + 0.24 * cos(rad(2.0 * hm)) +
               0.32 * cos(rad(3.0 * hm + 6.0)) - 0.20 * cos(rad(4.0 * hm - 63.0));
    double dtheta = 30.0 * exp(-pow((hm - 275.0) / 25.0, 2.0));
    double cm7 = pow(cm, 7.0);
    double RC = 2.0 * sqrt(cm7 / (cm7 + pow(25.0, 7.0)));
    double Lm50 = (Lm - 50.0) * (Lm - 50.0);
    double SL = 1.0 + 0.015 * Lm50 / sqrt(20.0 + Lm50);
    double SC = 1.0 + 0.045 * cm, SH = 1.0 + 0.015 * cm * T;
    double RT = -sin(rad(2.0 * dtheta)) * RC;
    double tL = dL / SL, tC = dC / SC, tH = dH / SH;
    return sqrt(tL * tL + tC * tC + tH * tH + RT * tC * tH);
}

const spm_spectrum *spm_d65(spm_error *err)
{
    static int ready;
    static spm_spectrum d65;
    if (!ready) {
        char path[4096];
        spm_data_path("spectra/illuminant_D65_1nm.csv", path, sizeof path);
        if (spm_spectrum_load(path, NULL, SPM_KIND_EMISSION, &d65, err))
            return NULL;
        ready = 1;
    }
    return &d65;
}

void spm_white_d65(double xyz[3])
{
    static int ready;
    static double white[3];
    if (!ready) {
        spm_error err;
        const spm_spectrum *d65 = spm_d65(&err);
        if (!d65) {
            /* bundled data: missing means a broken installation */
            fprintf(stderr, "specmip: %s\n", err.msg);
            exit(SPM_EXIT_RUNTIME);
        }
        spm_xyz_emission(d65, white);
        double y = white[1];
        for (int k = 0; k < 3; k++)
            white[k] /= y;
        ready = 1;
    }
    for (int k = 0; k < 3; k++)
        xyz[k] = white[k];
}
