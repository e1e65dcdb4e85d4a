/* The kernels' 4-wide BVH (spm_bvh4_node), collapsed from the binned-SAH
 * BVH2. First the leaves: a BVH2 subtree of at most four triangles (they are
 * contiguous in the reordered array) becomes one leaf when the surface-area
 * cost of testing them together is no more than that of keeping its leaves
 * apart (leaf_costs below). Then the nodes: a wide node takes a BVH2 node's
 * two children and, while it has fewer than four, opens the interior child
 * of largest surface area into its two children (the child a ray is likeliest
 * to enter gains most from being opened). Boxes and triangles stay as the
 * BVH2 has them, so every wide leaf's box is a BVH2 node's box and both trees
 * bound the same triangles: they answer every ray alike. The CPU reference
 * keeps traversing the BVH2.
 *
 * The layout (slots of sizeof(spm_bvh4_node) bytes, one device buffer): slot
 * 0 is the root node; then, from slot 1 on, the triangle planes the
 * four-lane test reads (SPM_LEAF_PLANES); then the other nodes. */
#include "geometry.h"
#include <stdlib.h>
#include <string.h>

static double half_area(const spm_bvh_node *n)
{
    double d[3];
    for (int i = 0; i < 3; i++)
        d[i] = n->bmax[i] > n->bmin[i] ? (double)n->bmax[i] - (double)n->bmin[i] : 0.0;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* Surface-area costs, in units of one scalar triangle test: a leaf of up to
 * SPM_LEAF_SCALAR triangles is tested one triangle at a time (n tests), a
 * larger one by the four-lane test (LANE_COST, its vector arithmetic and
 * the lane-by-lane bookkeeping after it); a subtree kept apart costs its
 * children's area-weighted costs plus SLOT_COST for the wide-node slot it
 * takes. Trace-stage instructions on cornell (callgrind, 16x16 at 16 spp, ml,
 * the scalar-only wide traversal of the BVH2's leaves took 15.94 M): LANE_COST 1.5 merges
 * its perpendicular wall and block quads into six leaves of 3 and 4, 17.87 M
 * (+12 %: closest-hit rays lose the culling of separate flat boxes); 1.8 to
 * 2.2 merge only its two pairs of coplanar quads, 16.33 M (+2.4 %); no merging
 * at all, 17.22 M (+8 %: this traversal with only scalar leaves). A 1M mesh
 * at 2.0 puts 70 % of its triangles in leaves of 3 or 4. */
#define LANE_COST 2.0
#define SLOT_COST 0.3

typedef struct {
    spm_u32 *count; /* triangles under each BVH2 node */
    spm_u32 *first; /* the first of them */
    double *cost;   /* best cost per ray entering the node's box (subtrees of <= 4) */
    unsigned char *leaf; /* 1: the node is a wide leaf */
} leaf_plan;

static void leaf_costs(const spm_bvh_node *nodes, spm_u32 r, leaf_plan *p)
{
    const spm_bvh_node *nd = &nodes[r];
    if (nd->count > 0) {
        p->count[r] = nd->count;
        p->first[r] = nd->first;
        p->cost[r] = nd->count <= SPM_LEAF_SCALAR ? (double)nd->count : LANE_COST;
        p->leaf[r] = 1;
        return;
    }
    spm_u32 a = nd->first, b = nd->first + 1;
    leaf_costs(nodes, a, p);
    leaf_costs(nodes, b, p);
    p->count[r] = p->count[a] + p->count[b];
    p->first[r] = p->first[a] < p->first[b] ? p->first[a] : p->first[b];
    p->leaf[r] = 0;
    p->cost[r] = 1e300;
    if (p->count[r] > SPM_WIDE)
        return;
    double ar = half_area(nd);
    double lone = p->count[r] <= SPM_LEAF_SCALAR ? (double)p->count[r] : LANE_COST;
    /* cost per ray entering r: as one leaf, or its two parts apart */
    double apart = SLOT_COST;
    if (ar > 0.0)
        apart += (half_area(&nodes[a]) * p->cost[a] + half_area(&nodes[b]) * p->cost[b]) / ar;
    else
        apart += p->cost[a] + p->cost[b];
    p->leaf[r] = lone <= apart;
    p->cost[r] = lone <= apart ? lone : apart;
}

/* The BVH2 nodes under BVH2 node r that become one wide node's children. */
static int gather(const spm_bvh_node *nodes, const leaf_plan *p, spm_u32 r, spm_u32 ch[SPM_WIDE])
{
    if (p->leaf[r]) { /* a leaf root: one child, itself */
        ch[0] = r;
        return 1;
    }
    int n = 2;
    ch[0] = nodes[r].first;
    ch[1] = nodes[r].first + 1;
    while (n < SPM_WIDE) {
        int k = -1;
        double best = -1.0;
        for (int i = 0; i < n; i++)
            if (!p->leaf[ch[i]] && half_area(&nodes[ch[i]]) > best)
                best = half_area(&nodes[ch[i]]), k = i;
        if (k < 0)
            break;
        spm_u32 c = nodes[ch[k]].first;
        ch[k] = c;
        ch[n++] = c + 1;
    }
    return n;
}

int spm_bvh_wide_build(spm_geometry *g, spm_error *err)
{
    g->wide = NULL;
    g->nwide = 0;
    if (g->nnodes == 0)
        return 0;
    if (g->ntris > SPM_WIDE_MAX_TRIS) {
        spm_errorf(err, "%d triangles: the wide BVH holds at most %d", g->ntris, SPM_WIDE_MAX_TRIS);
        return 1;
    }
    const spm_bvh_node *nodes = g->nodes;
    size_t nn = (size_t)g->nnodes;
    leaf_plan p = {spm_xmalloc(nn * sizeof *p.count), spm_xmalloc(nn * sizeof *p.first),
                   spm_xmalloc(nn * sizeof *p.cost), spm_xmalloc(nn)};
    leaf_costs(nodes, 0, &p);
    /* the planes' slots after the root; at most as many wide nodes as BVH2
     * interior nodes, plus one (a wide node has at least two BVH2 children
     * unless it is a leaf root) */
    size_t nplanes = SPM_LEAF_PLANES_FLOATS((size_t)g->ntris);
    spm_u32 pslots = (spm_u32)((nplanes * sizeof(float) + sizeof(spm_bvh4_node) - 1) /
                               sizeof(spm_bvh4_node));
    size_t cap = 1 + pslots + nn;
    spm_bvh4_node *w = spm_xmalloc(cap * sizeof *w);
    memset(&w[1], 0, (size_t)pslots * sizeof *w);
    float *planes = (float *)&w[1];
    spm_u32 *src = spm_xmalloc(nn * sizeof *src);
    int nw = 1; /* wide nodes so far; node k > 0 lives in slot pslots + k */
    src[0] = 0;
    for (int k = 0; k < nw; k++) {
        spm_u32 ch[SPM_WIDE];
        int n = gather(nodes, &p, src[k], ch);
        spm_bvh4_node *o = &w[k ? pslots + (spm_u32)k : 0];
        memset(o, 0, sizeof *o);
        for (int i = 0; i < SPM_WIDE; i++) {
            if (i >= n) {
                o->child[i] = SPM_WIDE_EMPTY;
                continue;
            }
            const spm_bvh_node *c = &nodes[ch[i]];
            o->bmin_x[i] = c->bmin[0], o->bmax_x[i] = c->bmax[0];
            o->bmin_y[i] = c->bmin[1], o->bmax_y[i] = c->bmax[1];
            o->bmin_z[i] = c->bmin[2], o->bmax_z[i] = c->bmax[2];
            if (p.leaf[ch[i]]) { /* count <= SPM_WIDE: leaf_costs */
                spm_u32 first = p.first[ch[i]], cnt = p.count[ch[i]];
                o->child[i] = SPM_WIDE_LEAF | first << 2 | (cnt - 1);
                /* plane 3 * vertex + axis of the leaf: cnt floats at
                 * 9 * first + plane * cnt, lane l for triangle first + l */
                float *lp = planes + (size_t)9 * first;
                for (spm_u32 l = 0; l < cnt; l++) {
                    const spm_tri *t = &g->tris[first + l];
                    for (int a = 0; a < 3; a++) {
                        lp[(0 + a) * cnt + l] = t->v0[a];
                        lp[(3 + a) * cnt + l] = t->v1[a];
                        lp[(6 + a) * cnt + l] = t->v2[a];
                    }
                }
            } else {
                src[nw] = ch[i];
                o->child[i] = pslots + (spm_u32)nw++;
            }
        }
    }
    free(src);
    free(p.count);
    free(p.first);
    free(p.cost);
    free(p.leaf);
    g->nwide = (int)(pslots + (spm_u32)nw);
    g->wide = spm_xrealloc(w, (size_t)g->nwide * sizeof *w);
    return 0;
}

