/* The kernels' 4-wide BVH (spm_bvh4_node, spm_leaf4), collapsed from the
 * binned-SAH BVH2.
 *
 * Leaves first: a BVH2 subtree of at most four triangles becomes one wide
 * leaf when the SAH prefers it. The kernel tests a leaf's four lanes at once,
 * so a leaf costs C_LEAF whatever its count, and a BVH2 interior node kept
 * costs about a third of the wide node that absorbs it (one of the three
 * BVH2 nodes a 4-wide node replaces). On half-areas A:
 *   leaf(r)  = A(r) * C_LEAF
 *   split(r) = A(r) * C_NODE / 3 + best(left) + best(right)
 *   best(r)  = min(leaf(r), split(r)) when r holds <= 4 triangles, else split(r)
 * (a BVH2 leaf is always a wide leaf: it holds at most 2). The triangles of
 * a subtree are contiguous in the BVH2's leaf order, so a wide leaf is a
 * range of the triangle array and the triangle indices, hence the ties' rule
 * (lowest index), are the BVH2's.
 *
 * Then nodes: a wide node takes a BVH2 node's two children and, while it has
 * fewer than four, opens the child of largest surface area that is neither
 * a leaf nor collapsed into one (the child a ray is likeliest to enter gains
 * most from being opened). Boxes are the BVH2's (padded), so both trees bound
 * the same triangles with the same boxes; the CPU reference keeps
 * traversing the BVH2. */
#include "geometry.h"
#include <stdlib.h>
#include <string.h>

/* Relative costs of the SAH above, a 4-wide node's slab tests being 1, and
 * the leaf's four-lane watertight test. Not sensitive: C_LEAF 0.5, 1 and 2
 * give nodes visited and triangle tests per ray within 1 % of each other on
 * the 1M sphere and soup of bench/scale.sh. */
#define C_NODE 1.0
#define C_LEAF 1.0

/* the kernel addresses the buffer in 16-byte units (spm_shared.h) */
_Static_assert(sizeof(spm_bvh4_node) == 16 * SPM_WIDE_NODE_UNITS, "wide node size");
_Static_assert(sizeof(spm_leaf4) == 16 * SPM_WIDE_LEAF_UNITS, "wide leaf size");

static double half_area(const spm_bvh_node *n)
{
    double d[3];
    for (int i = 0; i < 3; i++)
        d[i] = n->bmax[i] > n->bmin[i] ? (double)n->bmax[i] - (double)n->bmin[i] : 0.0;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

typedef struct {
    const spm_bvh_node *nodes;
    spm_u32 *first;      /* per BVH2 node: its subtree's first triangle */
    spm_u32 *count;      /* its triangles */
    unsigned char *leaf; /* 1: the subtree is one wide leaf */
} collapse_ctx;

/* best(r) above, marking the subtrees that become leaves. */
static double collapse(collapse_ctx *x, spm_u32 r)
{
    const spm_bvh_node *n = &x->nodes[r];
    double a = half_area(n);
    if (n->count > 0) {
        x->first[r] = n->first, x->count[r] = n->count, x->leaf[r] = 1;
        return a * C_LEAF;
    }
    spm_u32 l = n->first, h = n->first + 1;
    double split = a * (C_NODE / 3.0) + collapse(x, l) + collapse(x, h);
    spm_u32 lo = x->first[l] < x->first[h] ? x->first[l] : x->first[h];
    spm_u32 cnt = x->count[l] + x->count[h];
    x->first[r] = lo, x->count[r] = cnt, x->leaf[r] = 0;
    /* the children's ranges are adjacent (leaf order); checked, not assumed */
    int adjacent = (x->first[l] + x->count[l] == x->first[h]) ||
                   (x->first[h] + x->count[h] == x->first[l]);
    if (cnt <= SPM_WIDE && adjacent && a * C_LEAF <= split) {
        x->leaf[r] = 1;
        return a * C_LEAF;
    }
    return split;
}

/* The BVH2 nodes under BVH2 node r that become one wide node's children. */
static int gather(const collapse_ctx *x, spm_u32 r, spm_u32 ch[SPM_WIDE])
{
    const spm_bvh_node *nodes = x->nodes;
    if (x->leaf[r]) { /* a leaf root: one child, itself */
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
            if (!x->leaf[ch[i]] && half_area(&nodes[ch[i]]) > best)
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
    g->leaves = NULL;
    g->nwide = g->nleaves = 0;
    g->wide_bytes = 0;
    if (g->nnodes == 0)
        return 0;
    const spm_bvh_node *nodes = g->nodes;
    size_t nn = (size_t)g->nnodes;
    collapse_ctx x = {nodes, spm_xmalloc(nn * sizeof *x.first), spm_xmalloc(nn * sizeof *x.count),
                      spm_xmalloc(nn)};
    collapse(&x, 0);
    /* a wide node has at least two BVH2 children unless it is a leaf root:
     * at most as many wide nodes as BVH2 interior nodes, plus one; as many
     * leaves as BVH2 leaves at most */
    spm_bvh4_node *w = spm_xmalloc(nn * sizeof *w);
    spm_u32 *src = spm_xmalloc(nn * sizeof *src);
    spm_u32 *lsrc = spm_xmalloc(nn * sizeof *lsrc);
    int nw = 1, nl = 0;
    src[0] = 0;
    for (int k = 0; k < nw; k++) {
        spm_u32 ch[SPM_WIDE];
        int n = gather(&x, src[k], ch);
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
            if (x.leaf[ch[i]]) { /* the leaf's ordinal for now, its unit below */
                lsrc[nl] = ch[i];
                o->child[i] = SPM_WIDE_LEAF | (spm_u32)nl++;
            } else {
                src[nw] = ch[i];
                o->child[i] = (spm_u32)nw++;
            }
        }
    }
    free(src);
    size_t units = (size_t)nw * SPM_WIDE_NODE_UNITS + (size_t)nl * SPM_WIDE_LEAF_UNITS;
    if (units > SPM_WIDE_MAX_UNITS) {
        free(w), free(lsrc), free(x.first), free(x.count), free(x.leaf);
        spm_errorf(err, "%d triangles: the wide BVH (%zu bytes) exceeds its %d-unit address space",
                   g->ntris, units * 16, SPM_WIDE_MAX_UNITS);
        return 1;
    }
    for (int k = 0; k < nw; k++)
        for (int i = 0; i < SPM_WIDE; i++) {
            spm_u32 c = w[k].child[i];
            if (c != SPM_WIDE_EMPTY && (c & SPM_WIDE_LEAF)) {
                spm_u32 ord = c & ~SPM_WIDE_LEAF;
                spm_u32 unit = (spm_u32)nw * SPM_WIDE_NODE_UNITS + ord * SPM_WIDE_LEAF_UNITS;
                w[k].child[i] = SPM_WIDE_LEAF | unit << 2 | (x.count[lsrc[ord]] - 1);
            }
        }
    size_t bytes = (size_t)nw * sizeof *w + (size_t)nl * sizeof(spm_leaf4);
    char *buf = spm_xrealloc(w, bytes); /* the nodes stay, the leaves follow them */
    spm_leaf4 *lv = (spm_leaf4 *)(buf + (size_t)nw * sizeof(spm_bvh4_node));
    for (int l = 0; l < nl; l++) {
        spm_u32 first = x.first[lsrc[l]], cnt = x.count[lsrc[l]];
        memset(&lv[l], 0, sizeof lv[l]);
        lv[l].first = first;
        for (spm_u32 j = 0; j < SPM_WIDE; j++) {
            /* lanes past the count repeat the last triangle */
            const spm_tri *t = &g->tris[first + (j < cnt ? j : cnt - 1)];
            for (int c = 0; c < 3; c++) {
                lv[l].v[c][j] = t->v0[c];
                lv[l].v[3 + c][j] = t->v1[c];
                lv[l].v[6 + c][j] = t->v2[c];
            }
        }
    }
    free(lsrc), free(x.first), free(x.count), free(x.leaf);
    g->wide = (spm_bvh4_node *)buf;
    g->nwide = nw;
    g->leaves = lv;
    g->nleaves = nl;
    g->wide_bytes = bytes;
    return 0;
}
