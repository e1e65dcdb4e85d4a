/* Dispersive indices (dispersion.h). */
#include "dispersion.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

double spm_disp_sellmeier(const double b[3], const double c[3], double lambda_nm)
{
    double l2 = lambda_nm * 1e-3 * lambda_nm * 1e-3, n2 = 1.0;
    for (int i = 0; i < 3; i++) {
        if (l2 == c[i])
            return NAN;
        n2 += b[i] * l2 / (l2 - c[i]);
    }
    return n2 > 0.0 ? sqrt(n2) : NAN;
}

double spm_disp_cauchy(double a, double b, double lambda_nm)
{
    double l = lambda_nm * 1e-3;
    return a + b / (l * l);
}

/* Schott optical glass catalogue (SCHOTT AG, "Optical Glass – Data Sheets",
 * the Sellmeier dispersion formula's B1, B2, B3, C1, C2, C3 [um^2]): n_d
 * 1.51680 (N-BK7) and 1.78472 (N-SF11) at 587.5618 nm. */
static const spm_glass glasses[] = {
    {"N-BK7", {1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653}},
    {"N-SF11", {1.73759695, 0.313747346, 1.89878101}, {0.013188707, 0.0623068142, 155.23629}},
};
#define NGLASSES ((int)(sizeof glasses / sizeof glasses[0]))

const spm_glass *spm_glass_find(const char *name)
{
    for (int i = 0; i < NGLASSES; i++)
        if (!strcmp(glasses[i].name, name))
            return &glasses[i];
    return NULL;
}

const char *spm_glass_list(char *buf, size_t size)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; i < NGLASSES && n < size; i++)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", i ? ", " : "", glasses[i].name);
    return buf;
}
