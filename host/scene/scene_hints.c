#include "scene_hints.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* A position's bits, with -0 made +0 so that equal values share one key. */
static void position_bits(const float *p, uint32_t k[3])
{
    for (int i = 0; i < 3; i++) {
        float x = p[i] + 0.0f;
        memcpy(&k[i], &x, sizeof k[i]);
    }
}

/* A position's hash: three independent products and murmur3's finaliser (which
 * brings every bit to the low ones a table masks). Not spm_fnv1a64: its twelve
 * dependent multiplies per corner cost the 1M sphere's check 0.1 s more. */
static uint32_t hash3(const uint32_t k[3])
{
    uint32_t h = k[0] * 0x9e3779b1u ^ k[1] * 0x85ebca77u ^ k[2] * 0xc2b2ae3du;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    return h ^ h >> 16;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Sorts a[0, n): insertion for the few edges a vertex usually has, qsort for
 * a fan's many (no quadratic case). */
static void sort_u32(uint32_t *a, size_t n)
{
    if (n > 32) {
        qsort(a, n, sizeof *a, cmp_u32);
        return;
    }
    for (size_t i = 1; i < n; i++) {
        uint32_t x = a[i];
        size_t j = i;
        for (; j > 0 && a[j - 1] > x; j--)
            a[j] = a[j - 1];
        a[j] = x;
    }
}

/* A table slot: the first corner with its position (+ 1; 0 = empty) and the
 * position's hash, so that a probe reads the triangles only when the hashes
 * agree (and one cache line holds both). */
typedef struct {
    uint32_t corner, hash;
} slot;

/* The slot of position `key` (hash h) in a table of cap slots: its own, or
 * the empty one it would take. */
static size_t find_slot(const slot *tab, size_t cap, const spm_scene_tri *t,
                        const uint32_t key[3], uint32_t h)
{
    for (size_t s = h & (cap - 1);; s = (s + 1) & (cap - 1)) {
        if (!tab[s].corner)
            return s;
        if (tab[s].hash != h)
            continue;
        uint32_t other[3];
        size_t j = tab[s].corner - 1;
        position_bits(t[j / 3].p[j % 3], other);
        if (!memcmp(key, other, sizeof other))
            return s;
    }
}

/* Vertices numbered by position (an open-addressing table of corners keyed
 * on the position's bits), then each edge (lower id, higher id) put in its
 * lower vertex's bucket (a counting sort): closed when in every bucket each
 * higher id occurs exactly twice. O(n). The table starts at twice a closed
 * mesh's vertices (about n / 2) and doubles at half full, and each corner's
 * slot is fetched PREFETCH corners ahead: the table's cache misses were most
 * of the check's time (0.2 s for the 1M sphere with a table sized for 3n
 * corners, fetched on demand; radix-sorting the 3n edge keys took 0.08 s).
 * A closed mesh has at most 3n / 2 vertices (Euler: V = n / 2 + 2C - 2G with
 * at most n / 2 components, two faces each), so more ends the check early. */
#define PREFETCH 16
/* The edges of t[0, n) not shared by exactly two of them; with `first`, 1 at
 * the first such edge (or the vertex count past a closed mesh's). */
static long unpaired_edges(const spm_scene_tri *t, int n, int first)
{
    size_t nc = 3 * (size_t)n, cap = 1024;
    while (cap < (size_t)n)
        cap <<= 1;
    slot *tab = spm_xcalloc(cap, sizeof *tab);
    uint32_t *id = spm_xmalloc(nc * sizeof *id);
    uint32_t nv = 0, ahead[2 * PREFETCH]; /* hashes of corners c to k */
    for (size_t k = 0; k < nc + PREFETCH; k++) {
        uint32_t key[3], h;
        if (k < nc) { /* corner k hashed and its slot fetched ... */
            position_bits(t[k / 3].p[k % 3], key);
            h = ahead[k % (2 * PREFETCH)] = hash3(key);
            __builtin_prefetch(&tab[h & (cap - 1)]);
        }
        if (k < PREFETCH)
            continue;
        size_t c = k - PREFETCH; /* ... while corner c is placed */
        h = ahead[c % (2 * PREFETCH)];
        position_bits(t[c / 3].p[c % 3], key);
        size_t s = find_slot(tab, cap, t, key, h);
        if (tab[s].corner) {
            id[c] = id[tab[s].corner - 1];
            continue;
        }
        tab[s] = (slot){(uint32_t)c + 1, h};
        id[c] = nv++;
        if (first && nv > nc / 2) /* more than 3n / 2 vertices: open */
            break;
        if (2 * (size_t)nv > cap) { /* half full: twice the slots, every entry moved */
            size_t ncap = 2 * cap;
            slot *nt = spm_xcalloc(ncap, sizeof *nt);
            for (size_t i = 0; i < cap; i++) {
                if (!tab[i].corner)
                    continue;
                size_t d = tab[i].hash & (ncap - 1);
                while (nt[d].corner)
                    d = (d + 1) & (ncap - 1);
                nt[d] = tab[i];
            }
            free(tab);
            tab = nt, cap = ncap;
        }
    }
    free(tab);
    if (first && nv > nc / 2) {
        free(id);
        return 1;
    }
    /* start[v] .. start[v + 1]: the higher ends of the edges whose lower end is v */
    uint32_t *start = spm_xcalloc((size_t)nv + 1, sizeof *start);
    uint32_t *hi = spm_xmalloc(nc * sizeof *hi);
    for (size_t k = 0; k < nc; k++) {
        uint32_t a = id[k], b = id[k - k % 3 + (k % 3 + 1) % 3];
        start[(a < b ? a : b) + 1]++;
    }
    for (uint32_t v = 0; v < nv; v++)
        start[v + 1] += start[v];
    for (size_t k = 0; k < nc; k++) { /* start[v] moves to the end of v's bucket */
        uint32_t a = id[k], b = id[k - k % 3 + (k % 3 + 1) % 3];
        hi[start[a < b ? a : b]++] = a < b ? b : a;
    }
    free(id);
    long unpaired = 0; /* in each bucket, runs of one higher end: an edge each */
    for (uint32_t v = 0, begin = 0; v < nv && !(first && unpaired); begin = start[v++]) {
        uint32_t *h = hi + begin, d = start[v] - begin;
        sort_u32(h, d);
        for (uint32_t k = 0, run; k < d; k += run) {
            for (run = 1; k + run < d && h[k + run] == h[k]; run++)
                ;
            unpaired += run != 2;
        }
    }
    free(start);
    free(hi);
    return unpaired;
}

int spm_tris_closed(const spm_scene_tri *t, int n)
{
    return n >= 4 && unpaired_edges(t, n, 1) == 0; /* a tetrahedron is the smallest */
}

long spm_tris_unpaired_edges(const spm_scene_tri *t, int n)
{
    return n > 0 ? unpaired_edges(t, n, 0) : 0;
}

/* Per mesh statement, its dielectric triangles: a refraction that enters
 * must leave, so glass is a closed surface; warned with the count of edges
 * that are not shared by exactly two of them. */
static void hint_open_glass(const spm_scene *s)
{
    for (int i = 0; i < s->nmeshes; i++) {
        const spm_scene_mesh *m = &s->meshes[i];
        if (m->n > SPM_HINT_CLOSED_MAX_TRIS || m->first + m->n > s->ntris)
            continue;
        spm_scene_tri *glass = NULL;
        int n = 0, mat = -1;
        for (int k = m->first; k < m->first + m->n; k++) {
            const spm_scene_material *sm = &s->materials[s->tris[k].material];
            if (SPM_MAT_TAG(*sm) != SPM_MAT_DIELECTRIC)
                continue;
            if (!glass)
                glass = spm_xmalloc((size_t)m->n * sizeof *glass);
            glass[n++] = s->tris[k];
            mat = s->tris[k].material;
        }
        long open = spm_tris_unpaired_edges(glass, n);
        if (open)
            spm_warnf("%s: '%s': its glass ('%s', %d triangles) is not closed: %ld edges are not "
                      "shared by exactly two of its triangles; light refracted into an open "
                      "surface may not find its way out (docs/SCENE_FORMAT.md, meshes)", m->where,
                      m->name, s->materials[mat].name, n, open);
        free(glass);
    }
}

void spm_scene_hints(const spm_scene *s)
{
    spm_scene_hint_camera_inside(s);
    hint_open_glass(s);
}

void spm_scene_hint_camera_inside(const spm_scene *s)
{
    for (int i = 0; i < s->nmeshes; i++) {
        const spm_scene_mesh *m = &s->meshes[i];
        int inside = m->n <= SPM_HINT_CLOSED_MAX_TRIS && m->first + m->n <= s->ntris;
        for (int a = 0; a < 3 && inside; a++)
            inside = m->lo[a] <= s->eye[a] && s->eye[a] <= m->hi[a];
        if (inside && spm_tris_closed(s->tris + m->first, m->n))
            spm_warnf("%s: camera inside the closed mesh '%s' (bounding box (%g %g %g) to "
                      "(%g %g %g), camera at (%g %g %g)): it may hide the scene; a model in "
                      "millimetres? ('scale 0.001' makes it metres)", m->where, m->name,
                      m->lo[0], m->lo[1], m->lo[2], m->hi[0], m->hi[1], m->hi[2], s->eye[0],
                      s->eye[1], s->eye[2]);
    }
}
