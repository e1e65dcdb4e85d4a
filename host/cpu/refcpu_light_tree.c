/* The CPU reference's walk of the light tree (include/spm_light_tree.h;
 * kernels/light_tree.clh is the kernels'): the pick and the pmf of a given
 * light at a shading point, both through one importance and one choice per
 * node, so the pmf is the pick's. Plain scalar float C. */
#include "refcpu_lights.h"
#include "geometry_vec3.h"
#include "spm_light_tree.h"
#include <math.h>
#include <string.h>

static spm_u32 word(const float *f)
{
    spm_u32 u;
    memcpy(&u, f, sizeof u);
    return u;
}

static const float *tree_of(const spm_geometry *g)
{
    return g->light_pdf + g->ntris;
}

static const float *node_at(const float *lt, spm_u32 i)
{
    return lt + SPM_LTREE_HEAD + word(&lt[SPM_LTREE_H_INF]) + (size_t)i * SPM_LTREE_NODE;
}

/* cos(max(0, a - b)) of angles a, b given by their cosines and sines */
static float cos_sub(float sa, float ca, float sb, float cb)
{
    return ca > cb ? 1.0f : ca * cb + sa * sb;
}

static float sin_of(float c)
{
    float s2 = 1.0f - c * c;
    return s2 > 0.0f ? sqrtf(s2) : 0.0f;
}

/* A node's weight for the shading point x of geometric normal n: pbrt-v4's
 * LightBounds::Importance, phi / d^2 cos(theta') cos(theta_i'), made
 * continuous in x, so that the float differences between devices move the
 * pmf by as little and never flip a choice:
 *  - theta' = max(0, theta_w - theta_o - theta_b), theta_w the angle from
 *    the cone's axis to the direction from the box's centre to x, theta_b
 *    the box's angular radius from x (sin theta_b = r / d); inside the box's
 *    sphere theta_b goes on growing (sin theta_b = d / r, cos theta_b < 0)
 *    to pi at the centre, where every direction counts, instead of jumping
 *    there to "every direction" as pbrt-v4 does;
 *  - the cosine falls to 0 at theta_e instead of jumping there: the factor
 *    is (cos theta' - c) / (1 - c), c = max(0, cos theta_e), which is
 *    pbrt-v4's clamped cos theta' wherever theta_e >= pi/2 (triangles);
 *  - theta_i' = max(0, theta_i - theta_b), theta_i the angle to the
 *    point's normal on either face;
 *  - d^2 is clamped to the box's squared half diagonal, a length of the
 *    scene's own (pbrt-v4 clamps to half the diagonal's length, which
 *    depends on the unit);
 *  - a floor of SPM_LTREE_FLOOR times the power over distance (the
 *    unit-free phi / d^2): where both children's cones turn away from x
 *    they still weigh by it, so every light with power keeps a pmf above 0
 *    (no bias, the pmfs sum to 1) and no choice switches between
 *    importance and power at a threshold. */
static float importance(const float *nd, const float x[3], const float n[3])
{
    float pc[3], d[3], h[3];
    for (int k = 0; k < 3; k++) {
        pc[k] = 0.5f * (nd[SPM_LTN_LO + k] + nd[SPM_LTN_HI + k]);
        d[k] = x[k] - pc[k];
        h[k] = nd[SPM_LTN_HI + k] - pc[k];
    }
    float d2 = v3_dot(d, d), r2 = v3_dot(h, h), d2c = fmaxf(d2, r2), phi = nd[SPM_LTN_PHI];
    if (!(d2c > 0.0f))
        return phi;
    float inv = d2 > 0.0f ? 1.0f / sqrtf(d2) : 0.0f, wi[3] = {d[0] * inv, d[1] * inv, d[2] * inv};
    float cos_w = v3_dot(&nd[SPM_LTN_W], wi);
    if (word(&nd[SPM_LTN_FLAGS]) & SPM_LTF_TWOSIDED)
        cos_w = fabsf(cos_w);
    float sin_b = sqrtf(fminf(d2, r2) / d2c), cos_b = copysignf(sin_of(sin_b), d2 - r2);
    float cos_o = nd[SPM_LTN_COS_O], sin_o = sin_of(cos_o), sin_w = sin_of(cos_w);
    float cos_x = cos_w > cos_o ? 1.0f : cos_w * cos_o + sin_w * sin_o;
    float sin_x = cos_w > cos_o ? 0.0f : sin_w * cos_o - cos_w * sin_o;
    float cos_p = cos_sub(sin_x, cos_x, sin_b, cos_b), cos_i = fabsf(v3_dot(wi, n));
    float cos_ib = cos_sub(sin_of(cos_i), cos_i, sin_b, cos_b);
    float ce = fmaxf(nd[SPM_LTN_COS_E], 0.0f);
    float f = fmaxf(cos_p - ce, 0.0f) / (1.0f - ce) * fmaxf(cos_ib, 0.0f);
    return phi / d2c * (SPM_LTREE_FLOOR + (1.0f - SPM_LTREE_FLOOR) * f);
}

/* The weights of inner node i's children (the first at i + 1, the second at
 * next) at x */
static void child_weights(const float *lt, spm_u32 i, spm_u32 next, const float x[3],
                          const float n[3], float *c0, float *c1)
{
    *c0 = importance(node_at(lt, i + 1u), x, n);
    *c1 = importance(node_at(lt, next), x, n);
}

/* the probability of child `bit` of a node whose children weigh c0, c1 */
static float child_p(float c0, float c1, spm_u32 bit)
{
    return (bit ? c1 : c0) / (c0 + c1);
}

/* the share of the lights beside the tree: each as likely as the tree */
static float p_beside(const float *lt)
{
    spm_u32 ninf = word(&lt[SPM_LTREE_H_INF]), nodes = word(&lt[SPM_LTREE_H_NODES]);
    return (float)ninf / (float)(ninf + (nodes > 0u));
}

#define ONE_MINUS_EPS 0x1.fffffep-1f

int spm_ref_ltree_pick(const spm_geometry *g, const float x[3], const float n[3], float u,
                       float *pmf)
{
    const float *lt = tree_of(g);
    spm_u32 ninf = word(&lt[SPM_LTREE_H_INF]);
    float pi = p_beside(lt);
    if (u < pi) {
        u = fminf(u / pi, ONE_MINUS_EPS);
        spm_u32 i = (spm_u32)(u * (float)ninf);
        *pmf = pi / (float)ninf;
        return (int)word(&lt[SPM_LTREE_HEAD + (i < ninf ? i : ninf - 1u)]);
    }
    if (!word(&lt[SPM_LTREE_H_NODES]))
        return -1;
    u = fminf((u - pi) / (1.0f - pi), ONE_MINUS_EPS);
    float p = 1.0f - pi;
    for (spm_u32 i = 0;;) {
        const float *nd = node_at(lt, i);
        if (word(&nd[SPM_LTN_FLAGS]) & SPM_LTF_LEAF) {
            *pmf = p;
            return (int)word(&nd[SPM_LTN_NEXT]);
        }
        spm_u32 next = word(&nd[SPM_LTN_NEXT]);
        float c0, c1;
        child_weights(lt, i, next, x, n, &c0, &c1);
        if (!(c0 + c1 > 0.0f))
            return -1;
        float p0 = child_p(c0, c1, 0u);
        spm_u32 bit = !(u < p0);
        u = fminf(bit ? (u - p0) / (1.0f - p0) : u / p0, ONE_MINUS_EPS);
        p *= child_p(c0, c1, bit);
        i = bit ? next : i + 1u;
    }
}

float spm_ref_ltree_pmf(const spm_geometry *g, const float x[3], const float n[3], spm_u32 em)
{
    const float *lt = tree_of(g);
    float pi = p_beside(lt);
    spm_u32 kind = g->emitters[em].kind;
    if (kind != SPM_LIGHT_AREA && kind != SPM_LIGHT_POINT && kind != SPM_LIGHT_SPOT)
        return pi / (float)word(&lt[SPM_LTREE_H_INF]);
    const float *tr = node_at(lt, word(&lt[SPM_LTREE_H_NODES])) + 2u * em;
    unsigned long long trail = word(&tr[0]) | (unsigned long long)word(&tr[1]) << 32;
    float p = 1.0f - pi;
    for (spm_u32 i = 0;; trail >>= 1) {
        const float *nd = node_at(lt, i);
        if (word(&nd[SPM_LTN_FLAGS]) & SPM_LTF_LEAF)
            return p;
        spm_u32 next = word(&nd[SPM_LTN_NEXT]), bit = (spm_u32)(trail & 1u);
        float c0, c1;
        child_weights(lt, i, next, x, n, &c0, &c1);
        if (!(c0 + c1 > 0.0f))
            return 0.0f;
        p *= child_p(c0, c1, bit);
        i = bit ? next : i + 1u;
    }
}

spm_u32 spm_ref_ltree_area_index(const spm_geometry *g, spm_u32 tri)
{
    spm_u32 lo = 0, hi = word(&tree_of(g)[SPM_LTREE_H_AREA]);
    while (hi - lo > 1u) { /* the area emitters are in triangle order */
        spm_u32 mid = lo + (hi - lo) / 2u;
        if (g->emitters[mid].tri <= tri)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}
