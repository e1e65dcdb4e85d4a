/* Closest-hit queries: MiniLight's ray-triangle test over the BVH or over
 * every triangle. */
#include "geometry.h"
#include "geometry_vec3.h"

/* Moller-Trumbore exactly as MiniLight writes it, in float: a determinant
 * within SPM_RAY_EPSILON of zero (ray in the triangle's plane) misses. */
float spm_tri_intersect(const spm_tri *t, const float o[3], const float d[3])
{
    float pvec[3], tvec[3], qvec[3];
    v3_cross(pvec, d, t->e2);
    float det = v3_dot(t->e1, pvec);
    if (det > -SPM_RAY_EPSILON && det < SPM_RAY_EPSILON)
        return -1.0f;
    float inv_det = 1.0f / det;
    v3_sub(tvec, o, t->v0);
    float u = v3_dot(tvec, pvec) * inv_det;
    if (!(u >= 0.0f && u <= 1.0f))
        return -1.0f;
    v3_cross(qvec, tvec, t->e1);
    float v = v3_dot(d, qvec) * inv_det;
    if (!(v >= 0.0f && u + v <= 1.0f))
        return -1.0f;
    float dist = v3_dot(t->e2, qvec) * inv_det;
    return dist >= 0.0f ? dist : -1.0f;
}

/* Keeps the nearer hit; an exact tie goes to the lower index so the result
 * does not depend on the order triangles are visited in. */
static void consider(const spm_geometry *g, int i, const float o[3], const float d[3],
                     spm_u32 skip, int *best, float *best_t)
{
    if ((spm_u32)i == skip)
        return;
    float t = spm_tri_intersect(&g->tris[i], o, d);
    if (t >= 0.0f && (t < *best_t || (t == *best_t && i < *best)))
        *best = i, *best_t = t;
}

int spm_brute_intersect(const spm_geometry *g, const float o[3], const float d[3], spm_u32 skip,
                        float *t_out)
{
    int best = -1;
    float best_t = INFINITY;
    for (int i = 0; i < g->ntris; i++)
        consider(g, i, o, d, skip, &best, &best_t);
    *t_out = best_t;
    return best;
}

_Thread_local unsigned long long spm_bvh_nodes_tested;

/* Slab test over [0, tmax]; the entry distance in *tnear. Zero direction
 * components get a huge reciprocal instead of infinity (no 0 * inf NaN). */
static int box_hit(const spm_bvh_node *n, const float o[3], const float inv[3], float tmax,
                   float *tnear)
{
    spm_bvh_nodes_tested++;
    float t0 = 0.0f, t1 = tmax;
    for (int i = 0; i < 3; i++) {
        float a = (n->bmin[i] - o[i]) * inv[i], b = (n->bmax[i] - o[i]) * inv[i];
        if (a > b) {
            float s = a;
            a = b, b = s;
        }
        t0 = a > t0 ? a : t0;
        t1 = b < t1 ? b : t1;
    }
    *tnear = t0;
    return t0 <= t1;
}

int spm_bvh_intersect(const spm_geometry *g, const float o[3], const float d[3], spm_u32 skip,
                      float *t_out)
{
    int best = -1;
    float best_t = INFINITY, tn;
    *t_out = best_t;
    if (g->nnodes == 0)
        return -1;
    float inv[3];
    for (int i = 0; i < 3; i++)
        inv[i] = 1.0f / (d[i] != 0.0f ? d[i] : 1e-30f);
    if (!box_hit(&g->nodes[0], o, inv, best_t, &tn))
        return -1;
    spm_u32 stack[SPM_BVH_STACK];
    int top = 0;
    spm_u32 node = 0;
    for (;;) {
        const spm_bvh_node *n = &g->nodes[node];
        if (n->count > 0) {
            for (spm_u32 k = 0; k < n->count; k++)
                consider(g, (int)(n->first + k), o, d, skip, &best, &best_t);
        } else {
            /* descend into the nearer child, keep the other for later */
            float ta, tb;
            int ha = box_hit(&g->nodes[n->first], o, inv, best_t, &ta);
            int hb = box_hit(&g->nodes[n->first + 1], o, inv, best_t, &tb);
            if (ha && hb) {
                int a_first = ta <= tb;
                node = a_first ? n->first : n->first + 1;
                stack[top++] = a_first ? n->first + 1 : n->first;
                continue;
            }
            if (ha || hb) {
                node = ha ? n->first : n->first + 1;
                continue;
            }
        }
        /* pop, skipping nodes that now start beyond the best hit */
        for (;;) {
            if (top == 0) {
                *t_out = best_t;
                return best;
            }
            node = stack[--top];
            if (box_hit(&g->nodes[node], o, inv, best_t, &tn))
                break;
        }
    }
}

static double node_area(const spm_bvh_node *n)
{
    double d[3];
    for (int i = 0; i < 3; i++)
        d[i] = n->bmax[i] > n->bmin[i] ? (double)n->bmax[i] - (double)n->bmin[i] : 0.0;
    return 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

double spm_bvh_sah_cost(const spm_bvh_node *nodes, int nnodes, int *leaves)
{
    int nl = 0;
    double sum = 0.0;
    for (int k = 0; k < nnodes; k++) {
        double a = node_area(&nodes[k]);
        if (nodes[k].count) {
            nl++;
            sum += a * (double)nodes[k].count;
        } else {
            sum += a;
        }
    }
    if (leaves)
        *leaves = nl;
    double root = nnodes ? node_area(&nodes[0]) : 0.0;
    /* a flat root (all triangles in one plane) has area 0: cost as one box test per node */
    return root > 0.0 ? sum / root : (double)nnodes;
}
