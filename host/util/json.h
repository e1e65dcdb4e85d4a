/* A small JSON reader (RFC 8259) for the parts of model files that their
 * importer does not hand on: a glTF's buffer and image URIs, its extensions.
 * The whole text becomes a tree of values; strings are decoded (escapes,
 * \u with surrogate pairs, to UTF-8). Depth and size are bounded, so a
 * hostile file costs at most its own size in memory. */
#ifndef SPM_JSON_H
#define SPM_JSON_H
#include <stddef.h>
#ifdef __cplusplus
extern "C" {
#endif

typedef enum { SPM_JSON_NULL, SPM_JSON_BOOL, SPM_JSON_NUMBER, SPM_JSON_STRING, SPM_JSON_ARRAY,
               SPM_JSON_OBJECT } spm_json_type;

typedef struct spm_json spm_json;
struct spm_json {
    spm_json_type type;
    double number;     /* NUMBER; BOOL as 0 or 1 */
    char *string;      /* STRING: decoded, NUL-terminated */
    char *key;         /* the member's name, inside an OBJECT */
    spm_json *items;   /* ARRAY and OBJECT: n values */
    size_t n;
};

/* Parses text[0, len): the tree (free with spm_json_free), or NULL with a
 * message "line L, column C: what was expected" in why. */
spm_json *spm_json_parse(const char *text, size_t len, char *why, size_t whylen);
void spm_json_free(spm_json *v);
/* An object's member by name, or NULL (also when v is not an object). */
const spm_json *spm_json_get(const spm_json *v, const char *key);
/* An object member's string, or NULL when it is absent or not a string. */
const char *spm_json_string(const spm_json *v, const char *key);

#ifdef __cplusplus
}
#endif
#endif
