/* Closest-hit queries: the watertight ray-triangle test over the BVH or over
 * every triangle. */
#include "geometry.h"
#include "geometry_vec3.h"
#include <float.h>

/* The ray's frame (Woop, Benthin and Wald, "Watertight Ray/Triangle
 * Intersection", JCGT 2013): kz is the axis of d's largest |component| (the
 * first of equal ones), kx and ky the next two cyclically; the shear
 *   x' = x + sx z, y' = y + sy z, z' = sz z,  sx = -d_kx / d_kz, sy = -d_ky / d_kz, sz = 1 / d_kz
 * takes d to (0, 0, 1), so the ray is the z' axis through the origin. */
void spm_ray_frame_make(const float o[3], const float d[3], spm_ray_frame *f)
{
    float ax = fabsf(d[0]), ay = fabsf(d[1]), az = fabsf(d[2]);
    int kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    f->kz = kz;
    f->kx = (kz + 1) % 3;
    f->ky = (kz + 2) % 3;
    f->sx = -d[f->kx] / d[kz];
    f->sy = -d[f->ky] / d[kz];
    f->sz = 1.0f / d[kz];
    for (int i = 0; i < 3; i++)
        f->o[i] = o[i], f->d[i] = d[i];
}

/* One vertex relative to the origin, sheared: (x', y'), and z before its scaling. */
static void shear_vertex(const spm_ray_frame *f, const float v[3], float *x, float *y, float *z)
{
    float a = v[f->kx] - f->o[f->kx], b = v[f->ky] - f->o[f->ky], c = v[f->kz] - f->o[f->kz];
    *x = a + f->sx * c;
    *y = b + f->sy * c;
    *z = c;
}

/* In the sheared frame the ray passes through (0, 0), and the edge functions
 *   U = cx by - cy bx,  V = ax cy - ay cx,  W = bx ay - by ax
 * are twice the signed areas of the triangles (0, b, c), (0, c, a), (0, a, b).
 * It hits when none is negative or none is positive (either face: no
 * culling) and det = U + V + W is not 0 (not edge-on); then
 *   t = (U az + V bz + W cz) / det  with z scaled by sz.
 * A triangle's neighbour computes a shared edge's function from the same two
 * sheared vertices with the opposite sign, exactly (a product does not depend
 * on its operands' order, nor a difference's magnitude), and 0 counts as
 * inside for both: a ray through a shared edge or vertex cannot pass between
 * the triangles. A function that is 0 in float is computed again in double,
 * where the products of floats are exact: its sign is then that of the exact
 * value (a nonzero float difference of rounded products already has it).
 * Nothing here compares with an absolute bound, so the decisions are the same
 * for a scene in any unit; only t > 0 keeps hits behind the origin out (a
 * ray leaving a surface starts off it, spm_ray_spawn, and skips its own
 * triangle: it neither re-hits the plane it leaves nor passes a face that
 * meets it at an edge, at any scale). kernels/traverse.clh does
 * the same operations in the same order, contraction off on both sides
 * (CMakeLists.txt), so the two answer every ray alike. */
float spm_tri_intersect_frame(const spm_tri *t, const spm_ray_frame *f)
{
    float ax, ay, az, bx, by, bz, cx, cy, cz;
    shear_vertex(f, t->v0, &ax, &ay, &az);
    shear_vertex(f, t->v1, &bx, &by, &bz);
    shear_vertex(f, t->v2, &cx, &cy, &cz);
    float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        u = (float)((double)cx * by - (double)cy * bx);
        v = (float)((double)ax * cy - (double)ay * cx);
        w = (float)((double)bx * ay - (double)by * ax);
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f))
        return -1.0f;
    float det = u + v + w;
    if (det == 0.0f)
        return -1.0f;
    float tn = u * (f->sz * az) + v * (f->sz * bz) + w * (f->sz * cz);
    float dist = tn / det;
    return dist > 0.0f && dist <= FLT_MAX ? dist : -1.0f;
}

float spm_tri_intersect(const spm_tri *t, const float o[3], const float d[3])
{
    spm_ray_frame f;
    spm_ray_frame_make(o, d, &f);
    return spm_tri_intersect_frame(t, &f);
}

/* |x| + |y| + |z| of b - a: at least the edge's length */
static float edge_l1(const float a[3], const float b[3])
{
    return fabsf(b[0] - a[0]) + fabsf(b[1] - a[1]) + fabsf(b[2] - a[2]);
}

/* Where a ray leaving triangle `from` at o along d starts. A hit point
 * carries rounding of its coordinates: on an edge of a closed box it may lie
 * just outside the neighbouring face, whose hit is then at t <= 0 and does
 * not count (light left the box). So the point is rebuilt from its
 * barycentrics on the triangle, each raised so it lies at least 2 e inside
 * every edge (distance to edge k = b_k 2 area / |edge k|; the L1 length bounds
 * |edge k| from above), and moved e off the plane on d's side:
 *   e = SPM_SPAWN_ULPS FLT_EPSILON max |vertex coordinate|,
 *   b_k' = max(b_k, e |edge k|_1 / area),  p = v0 + (v1 - v0) b1' / s + (v2 - v0) b2' / s,
 *   o' = p +- e n  (s = b0' + b1' + b2').
 * Then the plane it leaves (and a coplanar neighbour's) lies behind the ray
 * and a face meeting the triangle at an edge ahead of it at t > 0, in a
 * scene of any unit. A triangle too small for the margins starts the ray
 * from its centroid. kernels/traverse.clh ray_spawn is the same operations. */
void spm_ray_spawn(const spm_geometry *g, spm_u32 from, const float o[3], const float d[3],
                   float out[3])
{
    if (from >= (spm_u32)g->ntris) {
        for (int i = 0; i < 3; i++)
            out[i] = o[i];
        return;
    }
    const spm_tri *t = &g->tris[from];
    float e0[3], e1[3], q[3], c[3], m = 0.0f;
    v3_sub(e0, t->v1, t->v0);
    v3_sub(e1, t->v2, t->v0);
    v3_sub(q, o, t->v0);
    for (int i = 0; i < 3; i++) {
        m = fmaxf(m, fabsf(t->v0[i]));
        m = fmaxf(m, fabsf(t->v1[i]));
        m = fmaxf(m, fabsf(t->v2[i]));
    }
    float e = SPM_SPAWN_ULPS * FLT_EPSILON * m, den = 2.0f * t->area;
    v3_cross(c, q, e1);
    float b1 = v3_dot(c, t->n) / den;
    v3_cross(c, e0, q);
    float b2 = v3_dot(c, t->n) / den;
    float b0 = 1.0f - b1 - b2;
    float m0 = e * edge_l1(t->v1, t->v2) / t->area, m1 = e * edge_l1(t->v0, t->v2) / t->area,
          m2 = e * edge_l1(t->v0, t->v1) / t->area;
    if (m0 + m1 + m2 < 0.5f) {
        b0 = fmaxf(b0, m0), b1 = fmaxf(b1, m1), b2 = fmaxf(b2, m2);
    } else {
        b0 = 1.0f / 3.0f, b1 = b0, b2 = b0;
    }
    float s = b0 + b1 + b2, side = v3_dot(d, t->n) < 0.0f ? -e : e;
    b1 = b1 / s, b2 = b2 / s;
    for (int i = 0; i < 3; i++)
        out[i] = t->v0[i] + e0[i] * b1 + e1[i] * b2 + t->n[i] * side;
}

/* Keeps the nearer hit; an exact tie goes to the lower index so the result
 * does not depend on the order triangles are visited in. A hit where the
 * surface's opacity says it is not there does not count (spm_alpha_there:
 * by the ray and the triangle alone, so again not by the order). */
static void consider(const spm_geometry *g, int i, const spm_ray_frame *f, spm_u32 skip,
                     int *best, float *best_t)
{
    if ((spm_u32)i == skip)
        return;
    float t = spm_tri_intersect_frame(&g->tris[i], f);
    if (t >= 0.0f && (t < *best_t || (t == *best_t && i < *best)) &&
        (!g->ntex || spm_alpha_there(g, (spm_u32)i, f->o, f->d, t)))
        *best = i, *best_t = t;
}

int spm_brute_intersect(const spm_geometry *g, const float o0[3], const float d[3], spm_u32 skip,
                        float *t_out)
{
    int best = -1;
    float best_t = INFINITY, o[3];
    spm_ray_spawn(g, skip, o0, d, o);
    spm_ray_frame f;
    spm_ray_frame_make(o, d, &f);
    for (int i = 0; i < g->ntris; i++)
        consider(g, i, &f, skip, &best, &best_t);
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

int spm_bvh_intersect(const spm_geometry *g, const float o0[3], const float d[3], spm_u32 skip,
                      float *t_out)
{
    int best = -1;
    float best_t = INFINITY, tn, o[3];
    *t_out = best_t;
    if (g->nnodes == 0)
        return -1;
    spm_ray_spawn(g, skip, o0, d, o);
    /* A zero component gets the reciprocal 1e30 (per unit of distance, as d is
     * a unit vector): its slab distances (bmin - o) * 1e30 are then beyond
     * every hit unless o lies within float rounding of the slab's face (the
     * boxes are padded by far more), at any scale, and never 0 * inf = NaN. */
    float inv[3];
    for (int i = 0; i < 3; i++)
        inv[i] = 1.0f / (d[i] != 0.0f ? d[i] : 1e-30f);
    spm_ray_frame f;
    spm_ray_frame_make(o, d, &f);
    if (!box_hit(&g->nodes[0], o, inv, best_t, &tn))
        return -1;
    spm_u32 stack[SPM_BVH_STACK];
    int top = 0;
    spm_u32 node = 0;
    for (;;) {
        const spm_bvh_node *n = &g->nodes[node];
        if (n->count > 0) {
            for (spm_u32 k = 0; k < n->count; k++)
                consider(g, (int)(n->first + k), &f, skip, &best, &best_t);
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
