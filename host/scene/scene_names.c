#include "scene_names.h"
#include "util.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint64_t hash(const char *s) { return spm_fnv1a64(SPM_FNV1A64_BASIS, s, strlen(s)); }

void spm_names_init(spm_names *t) { memset(t, 0, sizeof *t); }

void spm_names_free(spm_names *t)
{
    for (size_t i = 0; i < t->cap; i++)
        free(t->keys[i]);
    free(t->keys);
    free(t->values);
    memset(t, 0, sizeof *t);
}

/* Slot holding key, or the empty slot where it would go (cap is a power of 2). */
static size_t slot(const spm_names *t, const char *key)
{
    size_t i = (size_t)hash(key) & (t->cap - 1);
    while (t->keys[i] && strcmp(t->keys[i], key) != 0)
        i = (i + 1) & (t->cap - 1);
    return i;
}

int spm_names_get(const spm_names *t, const char *key)
{
    if (!t->cap)
        return -1;
    size_t i = slot(t, key);
    return t->keys[i] ? t->values[i] : -1;
}

static void grow(spm_names *t)
{
    spm_names old = *t;
    t->cap = old.cap ? old.cap * 2 : 64;
    t->keys = spm_xcalloc(t->cap, sizeof *t->keys);
    t->values = spm_xcalloc(t->cap, sizeof *t->values);
    for (size_t i = 0; i < old.cap; i++)
        if (old.keys[i]) {
            size_t j = slot(t, old.keys[i]);
            t->keys[j] = old.keys[i];
            t->values[j] = old.values[i];
        }
    free(old.keys);
    free(old.values);
}

void spm_names_put(spm_names *t, const char *key, int value)
{
    if (2 * (t->count + 1) > t->cap) /* keep the load factor at most 1/2 */
        grow(t);
    size_t i = slot(t, key);
    if (!t->keys[i]) {
        t->keys[i] = spm_xstrdup(key);
        t->count++;
    }
    t->values[i] = value;
}
