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

/* Sorts keys a[0, n) of at most `bits` significant bits, LSD radix by bytes
 * (tmp holds n keys). */
static void radix_sort_u64(uint64_t *a, uint64_t *tmp, size_t n, int bits)
{
    for (int shift = 0; shift < bits; shift += 8) {
        size_t count[257] = {0};
        for (size_t k = 0; k < n; k++)
            count[(a[k] >> shift & 0xff) + 1]++;
        for (int d = 0; d < 256; d++)
            count[d + 1] += count[d];
        for (size_t k = 0; k < n; k++)
            tmp[count[a[k] >> shift & 0xff]++] = a[k];
        uint64_t *t = a;
        a = tmp;
        tmp = t;
    }
    if ((bits + 7) / 8 % 2) /* an odd number of passes left the keys in tmp */
        memcpy(tmp, a, n * sizeof *a);
}

/* Vertices numbered by position (an open-addressing table of corners keyed
 * on the position's bits: a mesh's corners repeat each vertex ~6 times close
 * together, so most lookups hit the cache), then the edges as (lower id,
 * higher id) keys, radix-sorted: closed when every key occurs exactly twice.
 * O(n). */
int spm_tris_closed(const spm_scene_tri *t, int n)
{
    if (n < 4) /* a tetrahedron is the smallest closed mesh */
        return 0;
    size_t nc = 3 * (size_t)n, cap = 1;
    while (cap < 2 * nc) /* load at most 1/2 */
        cap <<= 1;
    uint32_t *slot = spm_xmalloc(cap * sizeof *slot); /* corner + 1, 0 = empty */
    memset(slot, 0, cap * sizeof *slot);
    uint32_t *id = spm_xmalloc(nc * sizeof *id);
    uint32_t nv = 0;
    for (size_t k = 0; k < nc; k++) {
        uint32_t key[3], other[3];
        position_bits(t[k / 3].p[k % 3], key);
        for (size_t h = hash3(key) & (cap - 1);; h = (h + 1) & (cap - 1)) {
            if (!slot[h]) {
                slot[h] = (uint32_t)k + 1;
                id[k] = nv++;
                break;
            }
            size_t j = slot[h] - 1;
            position_bits(t[j / 3].p[j % 3], other);
            if (!memcmp(key, other, sizeof key)) {
                id[k] = id[j];
                break;
            }
        }
    }
    free(slot);
    int idbits = 1;
    while (idbits < 32 && (nv - 1) >> idbits)
        idbits++;
    uint64_t *e = spm_xmalloc(2 * nc * sizeof *e);
    for (size_t k = 0; k < nc; k++) {
        uint64_t a = id[k], b = id[k - k % 3 + (k % 3 + 1) % 3];
        e[k] = a < b ? a << idbits | b : b << idbits | a;
    }
    free(id);
    radix_sort_u64(e, e + nc, nc, 2 * idbits);
    int closed = 1;
    for (size_t k = 0; k < nc && closed; k += 2)
        closed = k + 1 < nc && e[k] == e[k + 1] && (k + 2 >= nc || e[k + 2] != e[k]);
    free(e);
    return closed;
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
