/* The kernels' 4-wide BVH (spm_bvh4_node), collapsed from the binned-SAH
 * BVH2: a wide node takes a BVH2 node's two children and, while it has fewer
 * than four, opens the interior child of largest surface area into its two
 * children (the child a ray is likeliest to enter gains most from being
 * opened). The BVH2's leaves stay leaves, triangles and boxes (padded) stay
 * as they are, so both trees bound the same triangles with the same boxes
 * and answer every ray alike; the CPU reference keeps traversing the BVH2. */
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

/* The BVH2 nodes under BVH2 node r that become one wide node's children. */
static int gather(const spm_bvh_node *nodes, spm_u32 r, spm_u32 ch[SPM_WIDE])
{
    if (nodes[r].count > 0) { /* a leaf root: one child, itself */
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
            if (nodes[ch[i]].count == 0 && half_area(&nodes[ch[i]]) > best)
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
    /* a wide node has at least two BVH2 children unless it is a leaf root:
     * at most as many wide nodes as BVH2 interior nodes, plus one */
    spm_bvh4_node *w = spm_xmalloc((size_t)g->nnodes * sizeof *w);
    spm_u32 *src = spm_xmalloc((size_t)g->nnodes * sizeof *src);
    int nw = 1;
    src[0] = 0;
    for (int k = 0; k < nw; k++) {
        spm_u32 ch[SPM_WIDE];
        int n = gather(nodes, src[k], ch);
        spm_bvh4_node *o = &w[k];
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
            if (c->count > 0) { /* count <= LEAF_MAX (bvh_build.c) <= 4 */
                o->child[i] = SPM_WIDE_LEAF | c->first << 2 | (c->count - 1);
            } else {
                src[nw] = ch[i];
                o->child[i] = (spm_u32)nw++;
            }
        }
    }
    free(src);
    g->wide = spm_xrealloc(w, (size_t)nw * sizeof *w);
    g->nwide = nw;
    return 0;
}
