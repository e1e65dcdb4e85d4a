/* A string -> index table (open addressing), so that looking up a material or
 * a colour stays O(1) however many triangles refer to it. */
#ifndef SPM_SCENE_NAMES_H
#define SPM_SCENE_NAMES_H
#include <stddef.h>

typedef struct {
    char **keys;
    int *values;
    size_t cap, count;
} spm_names;

void spm_names_init(spm_names *t);
void spm_names_free(spm_names *t);
/* The value stored for key, or -1. */
int spm_names_get(const spm_names *t, const char *key);
/* Stores key -> value (value >= 0); replaces an existing value. */
void spm_names_put(spm_names *t, const char *key, int value);
#endif
