/* The material contract (host/cpu/refcpu_bsdf.h): every type of
 * include/spm_types.h's list through its dispatch (the test names no type:
 * a new entry is checked here without an edit), each made as a scene makes
 * it (its descriptor's fill, its numbers at 0.3 of their range, grey
 * colours), checked against itself in ways a kernel/reference comparison
 * cannot see:
 *  - eval and pdf against sample: for each sampled direction of a lobe that
 *    is not a delta, the weight sample gives (f |cos_i| / pdf, the Russian
 *    roulette's share included) equals eval's f |cos_i| over the density
 *    (sample's own, and the type's pdf where it has the lobe's alone);
 *  - reciprocity in radiance mode, f(wo, wi) = f(wi, wo), for every type
 *    whose vertex value is a function of the two directions alone (its
 *    instance makes no random choice: the Lambertian, the conductor, the
 *    dielectric's reflection); a type whose vertex picks one of its terms
 *    (the coated lobes, the rough diffuse terms) checks its model's sum in
 *    its own test;
 *  - each pdf integrates over the sphere (a midpoint rule in (cos theta,
 *    phi)) to the share of sample's directions that are kept (1, less what
 *    a GGX lobe sends below the horizon).
 * A type that shares another's define (the measured fluorescent type, the
 * fluorescent one's code) is that type's, checked there. */
#include <math.h>
#include <string.h>
#include "materials.h"
#include "bsdf_testlib.h"
#include "scene.h"
#include "spectrum.h"
#include "geometry_vec3.h"
#include "testutil.h"

/* the device material of type tag as the tables fill it: its numbers at 0.3
 * of their range, its colours grey (0.5, 0.4, 0.6) */
static spm_material material(spm_u32 tag)
{
    spm_colour cols[3];
    memset(cols, 0, sizeof cols);
    for (int i = 0; i < 3; i++)
        spm_spectrum_constant(0.5 + 0.1 * (i == 2) - 0.1 * (i == 1), SPM_KIND_REFLECTANCE,
                              &cols[i].s);
    spm_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.colours = cols;
    sc.ncolours = 3;
    spm_scene_material s;
    memset(&s, 0, sizeof s);
    s.type = (int)tag;
    s.refl = 0, s.col2 = 1, s.col3 = 2, s.emit = -1, s.diag = -1;
    const spm_mtype_desc *t = &spm_material_types[tag];
    for (int i = 0; i < t->nparams; i++)
        if (t->params[i].kind == SPM_MP_NUMBER || t->params[i].kind == SPM_MP_INDEX)
            s.p[t->params[i].slot] = t->params[i].lo + 0.3 * (t->params[i].hi - t->params[i].lo);
    spm_material m;
    spm_material_fill(&sc, &s, &m);
    return m;
}

static const char *name(spm_u32 tag)
{
    return spm_material_types[tag].keyword ? spm_material_types[tag].keyword : "lambert";
}

/* whether type tag is another's code (a type before it has its define) */
static int shares_code(spm_u32 tag)
{
    for (spm_u32 t = 0; t < tag; t++)
        if (!strcmp(spm_material_types[t].define, spm_material_types[tag].define))
            return 1;
    return 0;
}

#define NSAMPLES 16384
static const float WO[3] = {0.48f, -0.36f, 0.8f};

/* returns the share of the samples kept (not ending the path) */
static double eval_vs_sample(spm_u32 tag)
{
    spm_material m = material(tag);
    const float *wo = WO;
    spm_ref_hit h = bt_hit_from(wo);
    spm_ref_walk w = {NULL, 0, SPM_NONE};
    int n = 0, bad = 0, badpdf = 0, kept = 0;
    double worst = 0.0;
    for (spm_u32 s = 0; s < NSAMPLES; s++) {
        spm_ref_key k = {7u, 11u, s};
        spm_ref_bsdf b;
        spm_ref_begin(&m, &h, &k, 0, &w, &b);
        spm_ref_bsample bs;
        if (!spm_ref_sample(&m, &b, &h, &k, 0, SPM_REF_RADIANCE, &bs) || bs.wi[2] == 0.0f)
            continue;
        kept++;
        if (!(bs.wi[2] > 0.0f)) /* a refraction: eval is the reflection's */
            continue;
        float mean, inv;
        spm_ref_lobe(&m, &b, &mean, &inv);
        float total = bs.w * bs.wt * mean * inv;
        spm_ref_eval e = spm_ref_eval_bsdf(&m, &b, &h, bs.wi, SPM_REF_RADIANCE);
        float pdf = bs.pdf; /* the lobe's own density, where sample gives one */
        /* the coated vertex's diffuse lobe is the cosine bounce; its pdf is the
         * mixture's (for MIS at a light sample) */
        int coated_diffuse = tag == SPM_MAT_COATED && !b.lobe;
        if (pdf < 0.0f) /* a lobe without MIS: its density from the contract's pdf */
            pdf = coated_diffuse ? bs.wi[2] / SPM_PI_F : spm_ref_pdf(&m, &b, wo, bs.wi, 0);
        if (pdf == 0.0f) /* a delta lobe */
            continue;
        n++;
        double r = bt_value(e) / pdf / total;
        worst = fmax(worst, fabs(r - 1.0));
        bad += !(fabs(r - 1.0) < 1e-4);
        if (tag != SPM_MAT_COATED && bs.pdf > 0.0f) /* the type's pdf, one lobe */
            badpdf += !(fabs(spm_ref_pdf(&m, &b, wo, bs.wi, 0) / bs.pdf - 1.0) < 1e-4);
    }
    /* measured: the rough glass keeps 500 to check (it refracts the rest),
     * every other type over 10000 */
    CHECK(n > 300, "%s: %d sampled directions to check", name(tag), n);
    CHECK(bad == 0, "%s: %d of %d samples whose weight is not eval / pdf (worst %.3g)", name(tag),
          bad, n, worst);
    CHECK(badpdf == 0, "%s: %d of %d samples whose density is not pdf's", name(tag), badpdf, n);
    return (double)kept / NSAMPLES;
}

/* f(wo, wi) cos_i, made from a vertex seen from wo, its choices by key */
static float f_cos(spm_u32 tag, spm_u32 key, const float wo[3], const float wi[3])
{
    spm_material m = material(tag);
    spm_ref_hit h = bt_hit_from(wo);
    spm_ref_walk w = {NULL, 0, SPM_NONE};
    spm_ref_key k = {1, 2, key};
    spm_ref_bsdf b;
    spm_ref_begin(&m, &h, &k, 0, &w, &b);
    return bt_value(spm_ref_eval_bsdf(&m, &b, &h, wi, SPM_REF_RADIANCE));
}

/* direction pair i of the 200 (wo, wi), spread over the hemisphere */
static void pair(int i, float wo[3], float wi[3])
{
    float a = 0.05f + 0.9f * (float)((i * 37) % 200) / 200.0f, pa = 0.7f * (float)i;
    float c = 0.05f + 0.9f * (float)((i * 91) % 200) / 200.0f, pc = 1.3f * (float)i + 0.4f;
    float o[3] = {sqrtf(1 - a * a) * cosf(pa), sqrtf(1 - a * a) * sinf(pa), a};
    float n[3] = {sqrtf(1 - c * c) * cosf(pc), sqrtf(1 - c * c) * sinf(pc), c};
    memcpy(wo, o, sizeof o);
    memcpy(wi, n, sizeof n);
}

/* whether the vertex's value depends on its own random numbers (a term or
 * lobe picked at begin): then it is not the model's f alone. 1024 draws per
 * pair find a choice of probability 1 % (the rough diffuse type's second
 * term at rho 0.5, roughness 0.3, is picked with 2 %). */
static int picks(spm_u32 tag)
{
    for (int i = 0; i < 200; i += 20) {
        float wo[3], wi[3];
        pair(i, wo, wi);
        for (spm_u32 key = 1; key < 1024; key++)
            if (f_cos(tag, key, wo, wi) != f_cos(tag, 0, wo, wi))
                return 1;
    }
    return 0;
}

/* returns 1 when checked */
static int reciprocity(spm_u32 tag)
{
    if (picks(tag)) {
        printf("%s: its vertex picks a term: not checked here\n",
               name(tag));
        return 0;
    }
    int bad = 0, n = 0;
    for (int i = 0; i < 200; i++) {
        float wo[3], wi[3];
        pair(i, wo, wi);
        float f1 = f_cos(tag, 0, wo, wi) / wi[2], f2 = f_cos(tag, 0, wi, wo) / wo[2];
        if (!(f1 > 0.0f))
            continue;
        n++;
        bad += !(fabsf(f1 / f2 - 1.0f) < 1e-4f);
    }
    CHECK(n > 150 && bad == 0, "%s: %d of %d direction pairs not reciprocal", name(tag), bad, n);
    return 1;
}

/* the integral of pdf(wo, .) over the sphere */
static double pdf_integral(spm_u32 tag)
{
    spm_material m = material(tag);
    const float *wo = WO;
    spm_ref_hit h = bt_hit_from(wo);
    spm_ref_walk w = {NULL, 0, SPM_NONE};
    spm_ref_key k = {1, 2, 3};
    spm_ref_bsdf b;
    spm_ref_begin(&m, &h, &k, 0, &w, &b);
    const int nz = 2000, np = 400;
    double sum = 0.0;
    for (int i = 0; i < nz; i++)
        for (int j = 0; j < np; j++) {
            double z = -1.0 + 2.0 * (i + 0.5) / nz, ph = 2.0 * M_PI * (j + 0.5) / np;
            double r = sqrt(1.0 - z * z);
            float wi[3] = {(float)(r * cos(ph)), (float)(r * sin(ph)), (float)z};
            sum += spm_ref_pdf(&m, &b, wo, wi, 0);
        }
    return sum * (2.0 / nz) * (2.0 * M_PI / np);
}

int main(void)
{
    int checked = 0, reciprocal = 0;
    for (spm_u32 tag = 0; tag < (spm_u32)spm_nmaterial_types; tag++) {
        if (shares_code(tag))
            continue;
        double kept = eval_vs_sample(tag);
        reciprocal += reciprocity(tag);
        /* the share kept is a binomial count of NSAMPLES: its standard error
         * is at most 0.5 / sqrt(16384) = 0.004; 0.02 is 5 of them (measured
         * differences: at most 0.003); the grid's own error is below 1e-4 */
        double s = pdf_integral(tag);
        printf("%s: integral of pdf %.6f, share of samples kept %.6f\n", name(tag), s, kept);
        CHECK(fabs(s - kept) < 0.02, "%s: pdf integrates to %.6f, %.6f of the samples kept",
              name(tag), s, kept);
        checked++;
    }
    /* the list's types, less the one that shares the fluorescent code */
    CHECK(checked == spm_nmaterial_types - 1, "%d types checked of %d", checked,
          spm_nmaterial_types);
    CHECK(reciprocal >= 3, "reciprocity checked on %d types (the Lambertian, the conductor, "
          "the dielectric at least)", reciprocal);
    TEST_END();
}
