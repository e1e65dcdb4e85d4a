/* The parallel BVH builder's tree: every triangle in exactly one leaf, child
 * boxes inside their parents, leaves bounding their triangles, the same tree
 * (nodes and triangle order, bit for bit) on 1, 2 and 3 threads and as the
 * serial reference builder (bvh_reference.h) makes, an SAH cost below a plain
 * object-median build's, and a clean stop when interrupted. Meshes: a
 * triangle soup, a bumpy sphere, walls of axis-aligned quads (exact ties) and
 * a stack of coincident triangles (no SAH split: object medians). */
#include "bvh_reference.h"
#include "testutil.h"

static unsigned long long rng_state;
static double rnd(void)
{
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

/* Triangles as the builder reads them (its vertices); vn holds the input index
 * so the reordering can be followed. */
static spm_geometry make_geom(int n)
{
    spm_geometry g;
    memset(&g, 0, sizeof g);
    g.ntris = n;
    g.tris = calloc((size_t)n, sizeof *g.tris);
    g.cam.eye[2] = -3.0f;
    return g;
}

static void set_tri(spm_geometry *g, int i, const double a[3], const double b[3],
                    const double c[3])
{
    spm_tri *t = &g->tris[i];
    for (int k = 0; k < 3; k++) {
        t->v0[k] = (float)a[k];
        t->v1[k] = (float)b[k];
        t->v2[k] = (float)c[k];
    }
    t->material = 0;
    t->vn = (spm_u32)i;
}

static spm_geometry soup(int n)
{
    spm_geometry g = make_geom(n);
    rng_state = 12345;
    for (int i = 0; i < n; i++) {
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = rnd() * 2 - 1;
            b[k] = a[k] + (rnd() - 0.5) * 0.1;
            c[k] = a[k] + (rnd() - 0.5) * 0.1;
        }
        set_tri(&g, i, a, b, c);
    }
    return g;
}

static spm_geometry sphere(int rings, int segs)
{
    spm_geometry g = make_geom(2 * rings * segs);
    int k = 0;
    for (int i = 0; i < rings; i++)
        for (int j = 0; j < segs; j++) {
            double p[4][3];
            for (int q = 0; q < 4; q++) {
                double th = M_PI * (i + (q >> 1)) / rings, ph = 2 * M_PI * (j + (q & 1)) / segs;
                double r = 1.0 + 0.05 * sin(7 * th) * cos(5 * ph);
                p[q][0] = r * sin(th) * cos(ph);
                p[q][1] = r * cos(th);
                p[q][2] = r * sin(th) * sin(ph);
            }
            set_tri(&g, k++, p[0], p[1], p[3]);
            set_tri(&g, k++, p[0], p[3], p[2]);
        }
    return g;
}

/* Unit quads on three axis-aligned walls, two triangles each: many equal
 * boxes, centroids and SAH costs. */
static spm_geometry walls(int side)
{
    spm_geometry g = make_geom(3 * side * side * 2);
    int k = 0;
    for (int w = 0; w < 3; w++)
        for (int u = 0; u < side; u++)
            for (int v = 0; v < side; v++) {
                double p[4][3];
                for (int q = 0; q < 4; q++) {
                    p[q][w] = 0;
                    p[q][(w + 1) % 3] = u + (q & 1);
                    p[q][(w + 2) % 3] = v + (q >> 1);
                }
                set_tri(&g, k++, p[0], p[1], p[3]);
                set_tri(&g, k++, p[0], p[3], p[2]);
            }
    return g;
}

static spm_geometry coincident(int n)
{
    spm_geometry g = make_geom(n);
    for (int i = 0; i < n; i++)
        set_tri(&g, i, (double[]){0, 0, 0}, (double[]){1, 0, 0}, (double[]){0, 1, 0});
    return g;
}

static spm_geometry copy_geom(const spm_geometry *src)
{
    spm_geometry g = *src;
    g.tris = malloc((size_t)src->ntris * sizeof *g.tris);
    memcpy(g.tris, src->tris, (size_t)src->ntris * sizeof *g.tris);
    g.nodes = NULL;
    return g;
}

static int inside(const float lo[3], const float hi[3], const float plo[3], const float phi[3])
{
    for (int k = 0; k < 3; k++)
        if (!(lo[k] >= plo[k] && hi[k] <= phi[k]))
            return 0;
    return 1;
}

/* The structure of one tree: reached once each from the root, children boxes
 * inside parents, leaves over disjoint ranges covering every triangle once,
 * each leaf bounding its triangles, and the triangles a permutation of the
 * input. */
static void check_tree(const spm_geometry *g, const char *name)
{
    int n = g->ntris, nn = g->nnodes;
    char *seen_node = calloc((size_t)nn, 1), *seen_slot = calloc((size_t)n, 1);
    char *seen_id = calloc((size_t)n, 1);
    int *stack = malloc((size_t)nn * sizeof *stack), top = 0, bad_box = 0, bad_leaf = 0;
    int twice = 0, leaves = 0;
    stack[top++] = 0;
    while (top > 0) {
        int k = stack[--top];
        if (k < 0 || k >= nn || seen_node[k]++) {
            twice++;
            continue;
        }
        const spm_bvh_node *nd = &g->nodes[k];
        if (nd->count) {
            leaves++;
            for (spm_u32 i = nd->first; i < nd->first + nd->count && i < (spm_u32)n; i++) {
                if (seen_slot[i]++)
                    twice++;
                const spm_tri *t = &g->tris[i];
                float lo[3], hi[3];
                for (int a = 0; a < 3; a++) {
                    float p0 = t->v0[a], p1 = t->v1[a], p2 = t->v2[a];
                    lo[a] = fminf(p0, fminf(p1, p2));
                    hi[a] = fmaxf(p0, fmaxf(p1, p2));
                }
                bad_leaf += !inside(lo, hi, nd->bmin, nd->bmax);
            }
            continue;
        }
        for (int c = 0; c < 2; c++) {
            int ch = (int)nd->first + c;
            if (ch >= nn) {
                twice++;
                continue;
            }
            bad_box += !inside(g->nodes[ch].bmin, g->nodes[ch].bmax, nd->bmin, nd->bmax);
            stack[top++] = ch;
        }
    }
    int unseen = 0;
    for (int i = 0; i < n; i++) {
        unseen += !seen_slot[i];
        if (g->tris[i].vn < (spm_u32)n && !seen_id[g->tris[i].vn]++)
            continue;
        twice++;
    }
    for (int k = 0; k < nn; k++)
        unseen += !seen_node[k];
    CHECK(twice == 0 && unseen == 0, "%s: every node and triangle once (%d twice, %d unseen)",
          name, twice, unseen);
    CHECK(bad_box == 0, "%s: %d child boxes outside their parents", name, bad_box);
    CHECK(bad_leaf == 0, "%s: %d triangles outside their leaf's box", name, bad_leaf);
    CHECK(leaves == g->bvh.leaves && nn == 2 * leaves - 1, "%s: %d nodes, %d leaves (stats %d)",
          name, nn, leaves, g->bvh.leaves);
    free(seen_node);
    free(seen_slot);
    free(seen_id);
    free(stack);
}

static void check_mesh(const spm_geometry *mesh, const char *name)
{
    spm_error err;
    spm_geometry ref = copy_geom(mesh), med = copy_geom(mesh);
    CHECK(ref_bvh_build(&ref, 32, &err) == 0, "%s: reference build: %s", name, err.msg);
    CHECK(ref_bvh_build(&med, 0, &err) == 0, "%s: median build: %s", name, err.msg);
    spm_geometry one = copy_geom(mesh);
    CHECK(spm_bvh_build_threads(&one, 1, &err) == 0, "%s: build: %s", name, err.msg);
    check_tree(&one, name);
    /* equal boxes in the tree: the SAH cost the same to the last bit */
    CHECK(one.bvh.sah_cost <= ref.bvh.sah_cost, "%s: SAH cost %.9g, reference's %.9g", name,
          one.bvh.sah_cost, ref.bvh.sah_cost);
    CHECK(one.nnodes == ref.nnodes &&
              !memcmp(one.nodes, ref.nodes, (size_t)ref.nnodes * sizeof *ref.nodes) &&
              !memcmp(one.tris, ref.tris, (size_t)ref.ntris * sizeof *ref.tris),
          "%s: the reference builder's tree (%d nodes against %d)", name, one.nnodes,
          ref.nnodes);
    /* the median build is a valid tree too, only a worse one, unless every
     * centroid coincides (then SAH falls back to medians as well) */
    check_tree(&med, name);
    printf("%s: %d triangles, %d nodes, SAH cost %.3f (object medians %.3f)\n", name,
           mesh->ntris, one.nnodes, one.bvh.sah_cost, med.bvh.sah_cost);
    for (int t = 2; t <= 3; t++) {
        spm_geometry many = copy_geom(mesh);
        CHECK(spm_bvh_build_threads(&many, t, &err) == 0, "%s: %d threads: %s", name, t, err.msg);
        CHECK(many.nnodes == one.nnodes &&
                  !memcmp(many.nodes, one.nodes, (size_t)one.nnodes * sizeof *one.nodes) &&
                  !memcmp(many.tris, one.tris, (size_t)one.ntris * sizeof *one.tris) &&
                  many.bvh.sah_cost == one.bvh.sah_cost,
              "%s: the same tree on %d threads as on one", name, t);
        CHECK(many.bvh.threads == (mesh->ntris >= 16384 ? t : 1), "%s: %d threads reported",
              name, many.bvh.threads);
        spm_geometry_free(&many);
    }
    spm_geometry_free(&one);
    spm_geometry_free(&ref);
    spm_geometry_free(&med);
}

static void test_meshes(void)
{
    struct {
        spm_geometry g;
        const char *name;
        int sah_beats_median;
    } m[] = {{soup(60000), "soup", 1},
             {sphere(120, 200), "sphere", 1},
             {walls(60), "walls", 1},
             {coincident(20000), "coincident", 0},
             {soup(40), "small soup", 1}};
    for (size_t i = 0; i < sizeof m / sizeof m[0]; i++) {
        check_mesh(&m[i].g, m[i].name);
        if (m[i].sah_beats_median) {
            spm_geometry sah = copy_geom(&m[i].g), med = copy_geom(&m[i].g);
            spm_error err;
            CHECK(spm_bvh_build(&sah, &err) == 0 && ref_bvh_build(&med, 0, &err) == 0,
                  "%s: builds", m[i].name);
            CHECK(sah.bvh.sah_cost < med.bvh.sah_cost, "%s: SAH %.3f below object medians %.3f",
                  m[i].name, sah.bvh.sah_cost, med.bvh.sah_cost);
            spm_geometry_free(&sah);
            spm_geometry_free(&med);
        }
        spm_geometry_free(&m[i].g);
    }
}

/* A stop request ends the build with an error and nothing left allocated,
 * on several threads as on one. */
static void test_interrupted(void)
{
    spm_geometry mesh = soup(40000);
    for (int t = 1; t <= 2; t++) {
        spm_geometry g = copy_geom(&mesh);
        spm_error err = {{0}};
        spm_stop_flag = 1;
        int rc = spm_bvh_build_threads(&g, t, &err);
        spm_stop_flag = 0;
        CHECK(rc != 0 && strstr(err.msg, "interrupted while building the BVH"),
              "%d threads: interrupted: %s", t, err.msg);
        CHECK(g.nodes == NULL && g.nnodes == 0, "%d threads: no tree left", t);
        free(g.tris);
    }
    free(mesh.tris);
}

int main(void)
{
    test_meshes();
    test_interrupted();
    TEST_END();
}
