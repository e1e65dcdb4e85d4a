/* 4x4 transforms as pbrt-v4 composes them: each directive multiplies the
 * current transform on the right (CTM <- CTM T), points are columns. */
#include "pbrt.h"
#include <math.h>
#include <string.h>

void pbrt_mat_identity(double m[4][4])
{
    memset(m, 0, 16 * sizeof m[0][0]);
    for (int i = 0; i < 4; i++)
        m[i][i] = 1.0;
}

void pbrt_mat_mul(const double a[4][4], const double b[4][4], double out[4][4])
{
    double r[4][4];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] + a[i][3] * b[3][j];
    memcpy(out, r, sizeof r);
}

/* Gauss-Jordan with partial pivoting. */
int pbrt_mat_inverse(const double m[4][4], double out[4][4])
{
    double a[4][8];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 8; j++)
            a[i][j] = j < 4 ? m[i][j] : (j - 4 == i);
    for (int c = 0; c < 4; c++) {
        int piv = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(a[r][c]) > fabs(a[piv][c]))
                piv = r;
        if (!(fabs(a[piv][c]) > 0.0) || !isfinite(a[piv][c]))
            return 1;
        for (int j = 0; j < 8; j++) {
            double t = a[c][j];
            a[c][j] = a[piv][j];
            a[piv][j] = t;
        }
        double inv = 1.0 / a[c][c];
        for (int j = 0; j < 8; j++)
            a[c][j] *= inv;
        for (int r = 0; r < 4; r++)
            if (r != c) {
                double f = a[r][c];
                for (int j = 0; j < 8; j++)
                    a[r][j] -= f * a[c][j];
            }
    }
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            out[i][j] = a[i][j + 4];
    return 0;
}

void pbrt_mat_translate(const double t[3], double out[4][4])
{
    pbrt_mat_identity(out);
    for (int i = 0; i < 3; i++)
        out[i][3] = t[i];
}

void pbrt_mat_scale(const double s[3], double out[4][4])
{
    pbrt_mat_identity(out);
    for (int i = 0; i < 3; i++)
        out[i][i] = s[i];
}

/* Rodrigues: R = cos I + sin [a]x + (1 - cos) a a^T, a the unit axis. */
int pbrt_mat_rotate(double deg, const double axis[3], double out[4][4])
{
    double l = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    if (!(l > 0.0) || !isfinite(l))
        return 1;
    double a[3] = {axis[0] / l, axis[1] / l, axis[2] / l};
    double th = deg * (3.14159265358979323846 / 180.0), c = cos(th), s = sin(th);
    double k[3][3] = {{0, -a[2], a[1]}, {a[2], 0, -a[0]}, {-a[1], a[0], 0}};
    pbrt_mat_identity(out);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[i][j] = (i == j ? c : 0.0) + s * k[i][j] + (1.0 - c) * a[i] * a[j];
    return 0;
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static int unit(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(l > 0.0) || !isfinite(l))
        return 1;
    for (int i = 0; i < 3; i++)
        v[i] /= l;
    return 0;
}

/* world-from-camera has the columns right = up x dir, up' = dir x right,
 * dir, eye; LookAt gives its inverse. */
int pbrt_mat_lookat(const double eye[3], const double look[3], const double up[3],
                    double out[4][4])
{
    double d[3] = {look[0] - eye[0], look[1] - eye[1], look[2] - eye[2]}, u[3], r[3], nu[3];
    memcpy(u, up, sizeof u);
    if (unit(d) || unit(u))
        return 1;
    cross(u, d, r);
    if (unit(r))
        return 1;
    cross(d, r, nu);
    double w[4][4];
    pbrt_mat_identity(w);
    for (int i = 0; i < 3; i++) {
        w[i][0] = r[i];
        w[i][1] = nu[i];
        w[i][2] = d[i];
        w[i][3] = eye[i];
    }
    return pbrt_mat_inverse(w, out);
}

void pbrt_mat_apply(const double m[4][4], const double v[3], double w, double out[3])
{
    double r[3];
    for (int i = 0; i < 3; i++)
        r[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] + m[i][3] * w;
    memcpy(out, r, sizeof r);
}
