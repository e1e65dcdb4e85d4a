/* The coated material (material type SPM_MAT_COATED): a Lambertian base of
 * reflectance R under a dielectric coating of index eta, smooth or GGX-rough,
 * the light bouncing between base and coating accounted for as Mitsuba 3's
 * plastic / roughplastic with nonlinear true (docs/METHODS.md "Coatings").
 * The host's part: the coating's Fresnel in double, its internal diffuse
 * reflectance Fdr_i and the colour the vertex records for the diffuse lobe. */
#ifndef SPM_COATED_H
#define SPM_COATED_H
#include "scene.h"

/* the index a coated material takes without an 'ior' clause (Mitsuba 3's
 * plastic: 1.49, polypropylene; rounded) */
#define SPM_COAT_DEFAULT_ETA 1.5

/* The exact unpolarised Fresnel reflectance of a smooth boundary for light
 * arriving at incidence cosine c in [0, 1] from the side of index 1 towards
 * relative index eta (eta < 1: from inside a denser medium; total internal
 * reflection gives 1): sin^2 t = (1 - c^2) / eta^2, ct = sqrt(1 - sin^2 t),
 * rs = (c - eta ct) / (c + eta ct), rp = (eta c - ct) / (eta c + ct),
 * F = (rs^2 + rp^2) / 2. kernels/coated.clh and host/cpu/refcpu_coated.c
 * evaluate the same formula in float. */
double spm_dielectric_fresnel(double eta, double c);

/* The internal diffuse reflectance of a coating of index eta: the
 * cosine-weighted hemispherical mean of the Fresnel reflectance seen from
 * inside, Fdr_i = integral over mu in [0, 1] of F(1 / eta, mu) 2 mu dmu,
 * integrated numerically (mu_c^2 exactly for the totally reflected cone
 * mu < mu_c = sqrt(1 - 1 / eta^2), a quadrature above it). It is the average
 * of the Fresnel the kernels use, so that (1 - Fdr_e) / eta^2 = 1 - Fdr_i
 * holds for it (a white base under a smooth coating then reflects all light;
 * Mitsuba's polynomial fit of Fdr does not satisfy it). */
double spm_coat_fdr_internal(double eta);
/* The external one, integral of F(eta, mu) 2 mu dmu (the same quadrature). */
double spm_coat_fdr_external(double eta);

/* The colour a coated vertex records for its diffuse lobe, per 1 nm bin:
 * D = R (1 - Fdr_i) / (1 - Fdr_i R), the base's effective reflectance
 * R / (1 - Fdr_i R) (Mitsuba's nonlinear internal reflections) times the
 * constant 1 - Fdr_i, so that D is a reflectance in [0, 1] (the chance that
 * light entering the coating diffusely leaves it again) and white stays
 * white; the constant 1 / (eta^2 (1 - Fdr_i)) goes into the scalar weights. */
void spm_coat_effective(const spm_spectrum *R, double fdr_i, spm_spectrum *out);
#endif
