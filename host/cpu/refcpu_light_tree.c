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

/* A node's importance to the shading point x of geometric normal n (pbrt-v4's
 * LightBounds::Importance): phi cos(theta') / d^2, theta' the least angle
 * between the point's direction from the box and the box's emitting cone
 * (theta_w - theta_o - theta_b, theta_b the box's angular radius from x), 0
 * beyond theta_e; times the bound cos(theta_i - theta_b) of the cosine at
 * the point (either face). d^2 is clamped to the box's squared half
 * diagonal, a length of the scene's own (pbrt-v4 clamps to half the
 * diagonal's length, which depends on the unit). */
static float importance(const float *nd, const float x[3], const float n[3])
{
    float pc[3], d[3], h[3];
    for (int k = 0; k < 3; k++) {
        pc[k] = 0.5f * (nd[SPM_LTN_LO + k] + nd[SPM_LTN_HI + k]);
        d[k] = x[k] - pc[k];
        h[k] = nd[SPM_LTN_HI + k] - pc[k];
    }
    float d2 = v3_dot(d, d), r2 = v3_dot(h, h), d2c = d2 > r2 ? d2 : r2, phi = nd[SPM_LTN_PHI];
    if (!(d2c > 0.0f))
        return phi;
    if (d2 <= r2) /* inside the box's sphere: every direction */
        return phi / d2c;
    float inv = 1.0f / sqrtf(d2), wi[3] = {d[0] * inv, d[1] * inv, d[2] * inv};
    float cos_w = v3_dot(&nd[SPM_LTN_W], wi);
    if (word(&nd[SPM_LTN_FLAGS]) & SPM_LTF_TWOSIDED)
        cos_w = fabsf(cos_w);
    float cos_b = sqrtf(1.0f - r2 / d2), sin_b = sin_of(cos_b);
    float cos_o = nd[SPM_LTN_COS_O], sin_o = sin_of(cos_o), sin_w = sin_of(cos_w);
    float cos_x = cos_w > cos_o ? 1.0f : cos_w * cos_o + sin_w * sin_o;
    float sin_x = cos_w > cos_o ? 0.0f : sin_w * cos_o - cos_w * sin_o;
    float cos_p = cos_sub(sin_x, cos_x, sin_b, cos_b);
    if (cos_p <= nd[SPM_LTN_COS_E])
        return 0.0f;
    float cos_i = fabsf(v3_dot(wi, n));
    float imp = phi * cos_p / d2c * cos_sub(sin_of(cos_i), cos_i, sin_b, cos_b);
    return imp > 0.0f ? imp : 0.0f;
}

/* The weights of inner node i's children (the first at i + 1, the second at
 * next) at x: their importance, or where both bound it 0 (their cones turn
 * away from x though the parent's looser one does not), their power, so the
 * pmfs still sum to 1 (the light then drawn gives nothing). */
static void child_weights(const float *lt, spm_u32 i, spm_u32 next, const float x[3],
                          const float n[3], float *c0, float *c1)
{
    const float *a = node_at(lt, i + 1u), *b = node_at(lt, next);
    *c0 = importance(a, x, n);
    *c1 = importance(b, x, n);
    if (!(*c0 + *c1 > 0.0f)) {
        *c0 = a[SPM_LTN_PHI];
        *c1 = b[SPM_LTN_PHI];
    }
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
            return i > 0u || importance(nd, x, n) > 0.0f ? (int)word(&nd[SPM_LTN_NEXT]) : -1;
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
            return i > 0u || importance(nd, x, n) > 0.0f ? p : 0.0f;
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
