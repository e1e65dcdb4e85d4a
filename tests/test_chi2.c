/* Chi-squared goodness of fit for the CPU reference's samplers against their
 * densities (tests/chi2_testlib.h), the densities written here in double from
 * the papers, not from the reference:
 *  - the GGX conductor lobe (Heitz 2018's visible normals): pdf(wi) =
 *    D_wo(m) / (4 wo.m), D_wo(m) = G1(wo) (wo.m) D(m) / wo_z, m the half
 *    vector; eval D G2 / (4 wo_z) (Fresnel aside, in the shade stage);
 *  - the rough dielectric (Walter et al. 2007): reflection with F(wo.m),
 *    F D_wo(m) / (4 wo.m), and refraction with 1 - F,
 *    (1 - F) D_wo(m) e^2 |wi.m| / (wo.m + e wi.m)^2, from outside and inside;
 *  - the coated material's specular lobe, chosen with ps = Fo s / (Fo s +
 *    (1 - Fo)(1 - s)) (its diffuse choice gives no direction here: the
 *    cosine bounce is the trace loop's);
 *  - light sampling by power (the pick table of emitter triangles) and the
 *    committed wavelength of dispersive glass (uniform over the 1 nm bins):
 *    counts per choice against their probabilities;
 *  - the trace loop's own draws at a Lambertian floor, read from the rays it
 *    casts (refcpu.h's ray sink): the bounce, cos / pi about the normal, and
 *    the light sample's direction towards two unequal quad lights, pdf(wi) =
 *    P(triangle) d^2 / (A cos_e) with P the triangle's share of the power.
 * Each with fixed seeds; the level is corrected for the number of tests
 * (Sidak, ALPHA overall). The samplers are reached through small adapters
 * (sample, pdf, eval), so a material's sample/pdf of its own plugs in the
 * same way; a newer type's own sampler is checked in its own test
 * (tests/test_cl_<type>.c). */
#include <string.h>
#include "chi2_testlib.h"
#include "geomtest_scene.h"
#include "geometry.h"
#include "refcpu_bsdf.h"
#include "refcpu_coated.h"
#include "refcpu_conductor.h"
#include "refcpu_dielectric.h"
#include "spm_rng.h"

#define ALPHA 0.01
#define N_DIR 400000L
#define N_PICK 1000000L
#define NTESTS 14 /* chi-squared tests run below */

/* --- GGX in double (Trowbridge-Reitz, Smith's height-correlated G2) */
static double d_ggx(double a, double mz)
{
    double a2 = a * a, t = mz * mz * (a2 - 1.0) + 1.0;
    return mz > 0.0 ? a2 / (M_PI * t * t) : 0.0;
}
static double lambda(double a, double z)
{
    double z2 = z * z;
    return 0.5 * (-1.0 + sqrt(1.0 + a * a * (1.0 - z2) / z2));
}
static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static void unit3(double v[3])
{
    double l = sqrt(dot3(v, v));
    v[0] /= l, v[1] /= l, v[2] /= l;
}
/* the visible-normal density of m seen from wo */
static double d_visible(double a, const double wo[3], const double m[3])
{
    double c = dot3(wo, m);
    return c > 0.0 ? d_ggx(a, m[2]) * c / (wo[2] * (1.0 + lambda(a, wo[2]))) : 0.0;
}
static double fresnel(double ci, double e)
{
    double s2 = (1.0 - ci * ci) / (e * e);
    if (s2 >= 1.0)
        return 1.0;
    double ct = sqrt(1.0 - s2), rs = (ci - e * ct) / (ci + e * ct), rp = (e * ci - ct) / (e * ci + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* A frame with normal +z, tangent +x, for the reference's lobes */
static spm_ref_cond frame(const double wo[3], float alpha)
{
    spm_tri t;
    memset(&t, 0, sizeof t);
    t.n[2] = 1.0f;
    t.t[0] = 1.0f;
    float d[3] = {(float)-wo[0], (float)-wo[1], (float)-wo[2]};
    spm_ref_cond c;
    spm_ref_cond_make(&t, d, alpha, &c);
    return c;
}

typedef struct {
    double alpha, eta; /* eta: the dielectric's relative index e, the coating's index */
    double spec;       /* the coating's specular sampling weight s */
} lobe_ctx;

/* --- the conductor */
static int cond_sample(void *ctx, const double wo[3], const double u[3], double wi[3], double *pdf,
                       double *w)
{
    const lobe_ctx *l = ctx;
    spm_ref_cond c = frame(wo, (float)l->alpha);
    float out[3], cm, fw, fp;
    if (!spm_ref_cond_lobe(&c, (float)u[0], (float)u[1], out, &cm, &fw, &fp))
        return 0;
    for (int i = 0; i < 3; i++)
        wi[i] = out[i];
    unit3(wi);
    *pdf = fp, *w = fw;
    return 1;
}
static double cond_pdf(void *ctx, const double wo[3], const double wi[3])
{
    const lobe_ctx *l = ctx;
    if (!(wi[2] > 0.0))
        return 0.0;
    double m[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    unit3(m);
    return d_visible(l->alpha, wo, m) / (4.0 * dot3(wo, m));
}
static double cond_eval(void *ctx, const double wo[3], const double wi[3])
{
    const lobe_ctx *l = ctx;
    double m[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    unit3(m);
    double g2 = 1.0 / (1.0 + lambda(l->alpha, wo[2]) + lambda(l->alpha, wi[2]));
    return d_ggx(l->alpha, m[2]) * g2 / (4.0 * wo[2]);
}

/* --- the rough dielectric (e = eta_t / eta_i on wo's side) */
static int diel_sample(void *ctx, const double wo[3], const double u[3], double wi[3], double *pdf,
                       double *w)
{
    const lobe_ctx *l = ctx;
    spm_ref_cond c = frame(wo, (float)l->alpha);
    float out[3], wt, wg, fp;
    int r = spm_ref_diel_lobe(&c, (float)l->eta, (float)u[0], (float)u[1], (float)u[2], out, &wt,
                              &wg, &fp);
    if (!r)
        return 0;
    for (int i = 0; i < 3; i++)
        wi[i] = out[i];
    unit3(wi);
    *pdf = r == 1 ? fp : 0.0; /* the reference keeps the reflection's density only (for MIS) */
    *w = wt * wg;
    return 1;
}
/* the half vector of wo and wi (refraction's generalised one), on +z; its
 * Jacobian dm / dwi into *jac; 0 when wi cannot come from a facet */
static int diel_half(const lobe_ctx *l, const double wo[3], const double wi[3], double m[3],
                     double *jac)
{
    if (wi[2] > 0.0) {
        for (int i = 0; i < 3; i++)
            m[i] = wo[i] + wi[i];
        unit3(m);
        *jac = 1.0 / (4.0 * dot3(wo, m));
        return dot3(wo, m) > 0.0;
    }
    for (int i = 0; i < 3; i++)
        m[i] = -(wo[i] + l->eta * wi[i]);
    unit3(m);
    if (m[2] < 0.0)
        m[0] = -m[0], m[1] = -m[1], m[2] = -m[2];
    double co = dot3(wo, m), ci = dot3(wi, m), den = co + l->eta * ci;
    *jac = l->eta * l->eta * fabs(ci) / (den * den);
    return co > 0.0 && ci < 0.0;
}
static double diel_pdf(void *ctx, const double wo[3], const double wi[3])
{
    const lobe_ctx *l = ctx;
    double m[3], jac;
    if (wi[2] == 0.0 || !diel_half(l, wo, wi, m, &jac))
        return 0.0;
    double f = fresnel(dot3(wo, m), l->eta);
    return d_visible(l->alpha, wo, m) * (wi[2] > 0.0 ? f : 1.0 - f) * jac;
}
/* f |cos wi| in radiance mode (refraction scaled by 1 / e^2) */
static double diel_eval(void *ctx, const double wo[3], const double wi[3])
{
    const lobe_ctx *l = ctx;
    double m[3], jac;
    if (!diel_half(l, wo, wi, m, &jac))
        return 0.0;
    double f = fresnel(dot3(wo, m), l->eta);
    double g2 = 1.0 / (1.0 + lambda(l->alpha, wo[2]) + lambda(l->alpha, fabs(wi[2])));
    double dm = d_ggx(l->alpha, m[2]) * g2;
    if (wi[2] > 0.0)
        return f * dm / (4.0 * wo[2]);
    return (1.0 - f) * dm * dot3(wo, m) * jac / (wo[2] * l->eta * l->eta);
}

/* --- the coating's specular lobe (its diffuse choice: no direction here) */
static double coat_ps(const lobe_ctx *l, const double wo[3])
{
    double fo = fresnel(wo[2], l->eta), a = fo * l->spec, b = (1.0 - fo) * (1.0 - l->spec);
    return a / (a + b);
}
static int coat_sample(void *ctx, const double wo[3], const double u[3], double wi[3], double *pdf,
                       double *w)
{
    const lobe_ctx *l = ctx;
    spm_ref_cond f = frame(wo, (float)l->alpha);
    spm_material m;
    memset(&m, 0, sizeof m);
    m.p[SPM_COAT_P_ETA] = (float)l->eta;
    m.p[SPM_COAT_P_SPEC] = (float)l->spec;
    m.p[SPM_COAT_P_KD] = 1.0f;
    spm_ref_coat co;
    spm_ref_coat_make(&f, &m, (float)u[2], (float)u[0], (float)u[1], &co);
    if (!co.spec || !co.up)
        return 0;
    for (int i = 0; i < 3; i++)
        wi[i] = co.dir[i];
    unit3(wi);
    *pdf = co.pdf * co.ps; /* the lobe's density times its choice */
    *w = co.w;
    return 1;
}
static double coat_pdf(void *ctx, const double wo[3], const double wi[3])
{
    return coat_ps(ctx, wo) * cond_pdf(ctx, wo, wi);
}
static double coat_eval(void *ctx, const double wo[3], const double wi[3])
{
    const lobe_ctx *l = ctx;
    double m[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    unit3(m);
    return fresnel(dot3(wo, m), l->eta) * cond_eval(ctx, wo, wi);
}

static void wo_at(double theta_deg, double wo[3])
{
    double t = theta_deg * M_PI / 180.0, p = 0.7; /* off the tangent: no symmetry to hide behind */
    wo[0] = sin(t) * cos(p), wo[1] = sin(t) * sin(p), wo[2] = cos(t);
}

static int ntests;

static void directions(double alpha_test)
{
    const struct {
        const char *name;
        double theta, alpha, eta, spec;
        int kind; /* 0 conductor, 1 dielectric, 2 coated */
    } cases[] = {
        {"conductor GGX a 0.05", 30.0, 0.05, 0.0, 0.0, 0},
        {"conductor GGX a 0.3", 10.0, 0.3, 0.0, 0.0, 0},
        {"conductor GGX a 0.3", 70.0, 0.3, 0.0, 0.0, 0},
        {"conductor GGX a 0.8", 45.0, 0.8, 0.0, 0.0, 0},
        {"dielectric a 0.2 outside e 1.5", 35.0, 0.2, 1.5, 0.0, 1},
        {"dielectric a 0.5 outside e 1.5", 75.0, 0.5, 1.5, 0.0, 1},
        {"dielectric a 0.3 inside e 1/1.5", 20.0, 0.3, 1.0 / 1.5, 0.0, 1},
        {"dielectric a 0.3 inside e 1/1.5", 50.0, 0.3, 1.0 / 1.5, 0.0, 1},
        {"coated a 0.2 ior 1.5 s 0.6", 40.0, 0.2, 1.5, 0.6, 2},
        {"coated a 0.4 ior 1.5 s 0.3", 70.0, 0.4, 1.5, 0.3, 2},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        lobe_ctx l = {cases[i].alpha, cases[i].eta, cases[i].spec};
        chi2_sampler s = {cases[i].name, &l, cond_sample, cond_pdf, cond_eval};
        if (cases[i].kind == 1)
            s.sample = diel_sample, s.pdf = diel_pdf, s.eval = diel_eval;
        else if (cases[i].kind == 2)
            s.sample = coat_sample, s.pdf = coat_pdf, s.eval = coat_eval;
        double wo[3];
        wo_at(cases[i].theta, wo);
        chi2_run(&s, wo, N_DIR, 0x5eed0000u + i, alpha_test);
        ntests++;
    }
}

/* Counts of k choices against their probabilities: Pearson's statistic, k - 1 dof. */
static void discrete(const char *name, const double *count, const double *prob, int k, long n,
                     double alpha_test)
{
    double stat = 0.0;
    for (int i = 0; i < k; i++) {
        double e = prob[i] * (double)n;
        stat += (count[i] - e) * (count[i] - e) / e;
    }
    double p = st_chi2_sf(stat, k - 1);
    printf("%-34s chi2 %.1f over %d choices, p %.3g (reject below %.2g)\n", name, stat, k, p,
           alpha_test);
    CHECK(p >= alpha_test, "%s: chi2 %.1f over %d choices, p %.3g", name, stat, k, p);
    ntests++;
}

/* Light sampling by power: the pick table of emitters of unequal power. */
static void light_pick(double alpha_test)
{
    enum { K = 6 };
    const double w[K] = {1.0, 3.5, 0.2, 7.0, 2.3, 0.01};
    spm_emitter em[K];
    memset(em, 0, sizeof em);
    spm_emitter_table_build(em, w, K);
    double total = 0.0, count[K] = {0}, prob[K];
    for (int i = 0; i < K; i++)
        total += w[i];
    for (int i = 0; i < K; i++) {
        prob[i] = w[i] / total;
        /* the probability the estimator divides by is the pick's own: counts of 2^-24 */
        CHECK(fabs(em[i].pdf - prob[i]) <= 1e-6, "emitter %d: pdf %.9g, power share %.9g", i,
              em[i].pdf, prob[i]);
        CHECK(fabs(em[i].inv_pdf * em[i].pdf - 1.0) <= 1e-6, "emitter %d: inv_pdf %.9g pdf %.9g",
              i, em[i].inv_pdf, em[i].pdf);
    }
    /* each emitter owns its first count and the one before belongs to the one
     * before: a boundary off by one is 2^-24 of the draws, too rare to count */
    for (int i = 1; i < K; i++)
        CHECK(spm_emitter_search(em, K, em[i].cdf) == (spm_u32)i &&
                  spm_emitter_search(em, K, em[i].cdf - 1u) == (spm_u32)(i - 1),
              "the draw %u (emitter %d's first count) picks %u", em[i].cdf, i,
              spm_emitter_search(em, K, em[i].cdf));
    for (long k = 0; k < N_PICK; k++) {
        spm_u32 u24 = spm_rng_u32(7u, (spm_u32)k, 0u, SPM_DIM_VERTEX(0) + SPM_DIM_EMITTER) >> 8;
        count[spm_emitter_search(em, K, u24)] += 1.0;
    }
    discrete("light pick by power (6 emitters)", count, prob, K, N_PICK, alpha_test);
}

/* The committed wavelength: uniform over the 1 nm bins (the record's 1 / pdf
 * is SPM_TRUTH_BINS), drawn as the trace loop draws it. */
static void committed_wavelength(double alpha_test)
{
    static double count[SPM_TRUTH_BINS], prob[SPM_TRUTH_BINS];
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        prob[b] = 1.0 / SPM_TRUTH_BINS, count[b] = 0.0;
    long n = 0;
    for (spm_u32 px = 0; px < 2000; px++)
        for (spm_u32 s = 0; s < 200; s++, n++)
            count[spm_ref_disp_bin(spm_rng_stratified_u32(3u, px, s, SPM_DIM_TYPE(0u, SPM_DIM_DIEL_LAMBDA)))] += 1.0;
    discrete("committed wavelength (400 bins)", count, prob, SPM_TRUTH_BINS, n, alpha_test);
}

/* --- the trace loop's draws at vertex 0 on a Lambertian floor (y = 0),
 * seen by a camera 0.002 above it looking down (all paths hit within 2e-4
 * of the same point x, 0.6 and more from the lights) */
#define N_TRACE 400000L
#define TRACE_BATCH 4096
typedef struct {
    float *bounce, *shadow; /* directions, 3 floats each, in the floor's frame (z = +y) */
    long nb, ns;
    int state;              /* 0: camera ray next, 1: vertex 0's rays, 2: done */
    int got_b, got_s;
    double x[3];
} ray_log;

static void to_local(const float d[3], float *out)
{
    out[0] = d[0], out[1] = d[2], out[2] = d[1]; /* a frame of the floor: z along its normal +y */
}

static void log_ray(void *ctx, const spm_ray *r)
{
    ray_log *l = ctx;
    if (r->skip == 0xFFFFFFFFu) { /* a camera ray: a new path */
        l->state = 1, l->got_b = l->got_s = 0;
        return;
    }
    if (l->state != 1)
        return;
    if (r->emitter != SPM_RAY_CLOSEST && !l->got_s) {
        to_local(r->d, &l->shadow[3 * l->ns++]);
        l->got_s = 1;
        for (int i = 0; i < 3; i++)
            l->x[i] = r->o[i];
    } else if (r->emitter == SPM_RAY_CLOSEST && !l->got_b) {
        to_local(r->d, &l->bounce[3 * l->nb++]);
        l->got_b = 1;
    }
    if (l->got_b && l->got_s)
        l->state = 2;
}

/* the lights: quads at height h over [x0, x1] x [z0, z1], facing down, radiance e */
static const struct {
    double h, x0, x1, z0, z1, e;
} lights[2] = {{1.0, -0.8, -0.2, -0.3, 0.3, 1.0}, {0.6, 0.3, 0.7, -0.2, 0.4, 4.0}};

static void trace_floor(ray_log *l)
{
    spm_scene s;
    ts_init(&s);
    s.width = s.height = 1;
    s.fov_deg = 10.0f; /* the narrowest field there is: the camera is close instead */
    memcpy(s.eye, (float[]){0.0f, 0.002f, 0.0f}, sizeof s.eye);
    memcpy(s.dir, (float[]){0.0f, -1.0f, 0.0f}, sizeof s.dir);
    int floor_m = ts_material(&s, ts_colour(&s, SPM_KIND_REFLECTANCE, 1.0), -1);
    ts_quad(&s, floor_m, (float[]){-50, 0, -50}, (float[]){-50, 0, 50}, (float[]){50, 0, 50},
            (float[]){50, 0, -50});
    for (int k = 0; k < 2; k++) {
        int m = ts_material(&s, -1, ts_colour(&s, SPM_KIND_EMISSION, lights[k].e));
        float h = (float)lights[k].h, x0 = (float)lights[k].x0, x1 = (float)lights[k].x1;
        float z0 = (float)lights[k].z0, z1 = (float)lights[k].z1;
        ts_quad(&s, m, (float[]){x0, h, z0}, (float[]){x1, h, z0}, (float[]){x1, h, z1},
                (float[]){x0, h, z1});
    }
    spm_geometry g;
    spm_error err;
    if (spm_geometry_build(&s, &g, &err)) {
        CHECK(0, "build: %s", err.msg);
        ts_free(&s);
        return;
    }
    spm_tables t;
    ts_tables(&s, &t);
    spm_trace_params p = ts_params(&s, &g, (spm_u32)N_TRACE, 21u);
    spm_path *paths = calloc(TRACE_BATCH, sizeof *paths);
    uint8_t levels[TRACE_BATCH];
    spm_ref_rays = (spm_ref_ray_sink){log_ray, l};
    for (long b = 0; b < N_TRACE; b += TRACE_BATCH) {
        long e = b + TRACE_BATCH < N_TRACE ? b + TRACE_BATCH : N_TRACE;
        spm_ref_trace_range(&g, t.materials, NULL, 0, &p, (size_t)b, (size_t)e, paths, levels);
    }
    spm_ref_rays = (spm_ref_ray_sink){NULL, NULL};
    free(paths);
    spm_tables_free(&t);
    spm_geometry_free(&g);
    ts_free(&s);
}

typedef struct {
    const float *dirs;
    long n, next;
    const double *x;
} replay_ctx;

/* the logged directions one by one (u unused: the trace loop drew them) */
static int replay_sample(void *ctx, const double wo[3], const double u[3], double wi[3],
                         double *pdf, double *w)
{
    (void)wo, (void)u;
    replay_ctx *r = ctx;
    if (r->next >= r->n)
        return 0;
    for (int i = 0; i < 3; i++)
        wi[i] = r->dirs[3 * r->next + i];
    r->next++;
    unit3(wi);
    *pdf = 0.0, *w = 0.0; /* neither is logged */
    return 1;
}
static double lambert_pdf(void *ctx, const double wo[3], const double wi[3])
{
    (void)ctx, (void)wo;
    return wi[2] > 0.0 ? wi[2] / M_PI : 0.0;
}
/* a direction (the floor's frame) towards the lights from x: the density of
 * picking by power, then a uniform point on the triangle */
static double light_pdf(void *ctx, const double wo[3], const double wl[3])
{
    (void)wo;
    const replay_ctx *r = ctx;
    double d[3] = {wl[0], wl[2], wl[1]}, total = 0.0, pdf = 0.0; /* back to the scene's axes */
    for (int k = 0; k < 2; k++)
        total += lights[k].e * (lights[k].x1 - lights[k].x0) * (lights[k].z1 - lights[k].z0);
    for (int k = 0; k < 2; k++) {
        if (!(d[1] > 0.0))
            break;
        double t = (lights[k].h - r->x[1]) / d[1];
        double px = r->x[0] + t * d[0], pz = r->x[2] + t * d[2];
        if (px < lights[k].x0 || px > lights[k].x1 || pz < lights[k].z0 || pz > lights[k].z1)
            continue;
        /* the quad's power share, spread uniformly over its area: P / A = e / total */
        double dist2 = t * t, cos_e = d[1];
        pdf += lights[k].e / total * dist2 / cos_e;
    }
    return pdf;
}

static void trace_draws(double alpha_test)
{
    ray_log l;
    memset(&l, 0, sizeof l);
    l.bounce = malloc(3 * sizeof(float) * N_TRACE);
    l.shadow = malloc(3 * sizeof(float) * N_TRACE);
    trace_floor(&l);
    CHECK(l.nb > N_TRACE / 2 && l.ns > N_TRACE / 2, "logged %ld bounces, %ld light samples of %ld paths",
          l.nb, l.ns, N_TRACE);
    double wo[3] = {0.0, 0.0, 1.0};
    replay_ctx rb = {l.bounce, l.nb, 0, l.x}, rs = {l.shadow, l.ns, 0, l.x};
    chi2_sampler b = {"lambertian bounce (trace loop)", &rb, replay_sample, lambert_pdf, NULL};
    chi2_sampler s = {"light sample by power (trace loop)", &rs, replay_sample, light_pdf, NULL};
    chi2_run(&b, wo, l.nb, 0, alpha_test);
    chi2_run(&s, wo, l.ns, 0, alpha_test);
    ntests += 2;
    free(l.bounce);
    free(l.shadow);
}

int main(void)
{
    double alpha_test = st_sidak(ALPHA, NTESTS);
    directions(alpha_test);
    light_pick(alpha_test);
    committed_wavelength(alpha_test);
    trace_draws(alpha_test);
    CHECK(ntests == NTESTS, "%d tests run, the correction assumed %d", ntests, NTESTS);
    TEST_END();
}
