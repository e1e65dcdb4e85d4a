/* The files a model names, checked against the path rule (paths.h) before
 * its importer runs, so that an error names the reference as the file holds
 * it: a glTF's buffers[i].uri and images[i].uri (percent-decoded; data: URIs
 * are the file's own bytes), an OBJ's mtllib files and their maps. A .glb's
 * header and chunks are checked against the file's size here too: Assimp
 * says "No suitable reader found" of a cut one. What Assimp itself opens is
 * checked again in the importer's child (mesh_import.c). */
#include "mesh.h"
#include "json.h"
#include "paths.h"
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define GLTF_MAX_JSON (256u << 20)

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

/* A MIME type: "type/subtype", each of one or more characters. */
static int mime_type(const char *s, size_t n)
{
    const char *slash = memchr(s, '/', n);
    return slash && slash > s && slash < s + n - 1;
}

/* A data: URI, "data:TYPE/SUBTYPE;base64,PAYLOAD": its media type a MIME
 * type and its payload base64 (RFC 4648: the 64 characters, at most two '='
 * to close a length that is a multiple of 4). Assimp reads either wrongly
 * (a media type without '/' takes it down). */
static int data_uri(const char *uri, const char *where, spm_error *err)
{
    const char *comma = strchr(uri, ','), *type = uri + 5;
    const char *b64 = comma && comma - type >= 7 ? comma - 7 : NULL;
    if (!b64 || strncasecmp(b64, ";base64", 7) || !mime_type(type, (size_t)(b64 - type))) {
        spm_errorf(err, "%s: a data: URI that is not 'data:TYPE/SUBTYPE;base64,...' (%.40s)",
                   where, uri);
        return 1;
    }
    const char *p = comma + 1;
    size_t n = strlen(p), pad = 0;
    for (size_t i = 0; i < n; i++) {
        int c = (unsigned char)p[i];
        if (c == '=' && i + 2 >= n && (i + 1 == n || p[i + 1] == '=')) {
            pad = n - i;
            break;
        }
        if (!isalnum(c) && c != '+' && c != '/') {
            spm_errorf(err, "%s: a data: URI whose base64 has '%c' (byte %d) at its character "
                            "%zu", where, isprint(c) ? c : '?', c, i + 1);
            return 1;
        }
    }
    if (n % 4 || (n == 0 && !pad)) {
        spm_errorf(err, "%s: a data: URI whose base64 is %zu characters long (not a multiple "
                        "of 4: cut short?)", where, n);
        return 1;
    }
    return 0;
}

/* One URI of a glTF, at `where`: data: URIs checked, others are decoded and
 * checked against the model's folder. */
static int gltf_uri(const char *dir, const char *uri, const char *where, spm_error *err)
{
    if (strncasecmp(uri, "data:", 5) == 0)
        return data_uri(uri, where, err);
    char path[SPM_PATH_MAX];
    if (spm_uri_decode(uri, path, sizeof path)) {
        spm_errorf(err, "%s: '%s' is not a valid URI (a '%%' not followed by two hexadecimal "
                        "digits, or an escaped NUL byte)", where, uri);
        return 1;
    }
    char at[SPM_PATH_MAX + 64];
    if (strcmp(path, uri))
        snprintf(at, sizeof at, "%.*s (written '%.*s')", 1024, where, 1024, uri);
    else
        snprintf(at, sizeof at, "%s", where);
    spm_file p;
    return spm_path_check(dir, path, at, &p, err);
}

/* The glTF extensions that reach the image: the materials mesh_pbr.c maps;
 * lights, emissive strengths and texture transforms have warnings of their
 * own (SPM_MESH_IGN_*). */
static const char *const gltf_rendered[] = {
    "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_dispersion",
    "KHR_texture_transform"};

static void gltf_extensions(const spm_json *doc, char *out, size_t size)
{
    const spm_json *used = spm_json_get(doc, "extensionsUsed");
    size_t n = 0, cut = 0;
    out[0] = '\0';
    for (size_t i = 0; used && used->type == SPM_JSON_ARRAY && i < used->n; i++) {
        const spm_json *e = &used->items[i];
        int known = e->type != SPM_JSON_STRING;
        for (size_t k = 0; !known && k < sizeof gltf_rendered / sizeof *gltf_rendered; k++)
            known = !strcmp(e->string, gltf_rendered[k]);
        if (known)
            continue;
        if (n + strlen(e->string) + 2 + 16 < size)
            n += (size_t)snprintf(out + n, size - n, "%s%s", n ? ", " : "", e->string);
        else
            cut++;
    }
    if (cut)
        snprintf(out + n, size - n, " and %zu more", cut);
}

static int gltf_uris(const spm_file *model, const spm_json *doc, spm_error *err)
{
    static const char *const arrays[] = {"buffers", "images"};
    char dir[SPM_PATH_MAX];
    spm_path_dir(model->path, dir, sizeof dir);
    for (int a = 0; a < 2; a++) {
        const spm_json *list = spm_json_get(doc, arrays[a]);
        for (size_t i = 0; list && list->type == SPM_JSON_ARRAY && i < list->n; i++) {
            const char *uri = spm_json_string(&list->items[i], "uri");
            char where[SPM_PATH_MAX + 64];
            snprintf(where, sizeof where, "%s: %s[%zu].uri", model->shown, arrays[a], i);
            if (uri && gltf_uri(dir, uri, where, err))
                return 1;
        }
    }
    return 0;
}

/* An index member of obj: -1 absent, -2 not an index below n. */
static double index_of(const spm_json *obj, const char *key, size_t n)
{
    const spm_json *v = spm_json_get(obj, key);
    if (!v)
        return -1;
    if (v->type != SPM_JSON_NUMBER || !(v->number >= 0 && v->number < (double)n) ||
        v->number != (double)(size_t)v->number)
        return -2;
    return v->number;
}

/* A byte count or offset member of obj: def when absent, -1 when not a
 * number. */
static double bytes_of(const spm_json *obj, const char *key, double def)
{
    const spm_json *v = spm_json_get(obj, key);
    return !v ? def : v->type == SPM_JSON_NUMBER ? v->number : -1;
}

static size_t count(const spm_json *doc, const char *key)
{
    const spm_json *a = spm_json_get(doc, key);
    return a && a->type == SPM_JSON_ARRAY ? a->n : 0;
}

/* images[i] at `where`: a uri (checked with the others) or a bufferView
 * with a mimeType, the view within its buffer; a mimeType a MIME type.
 * What the image holds is read with the maps: one that cannot be decoded
 * is warned about where a map names it. */
static int gltf_image(const spm_json *doc, const spm_json *img, const char *where,
                      spm_error *err)
{
    const char *mime = spm_json_string(img, "mimeType");
    if (spm_json_get(img, "mimeType") && !(mime && mime_type(mime, strlen(mime)))) {
        spm_errorf(err, "%s.mimeType: '%.40s' is not a MIME type (image/png, image/jpeg)", where,
                   mime ? mime : "(not a string)");
        return 1;
    }
    double v = index_of(img, "bufferView", count(doc, "bufferViews"));
    if (v == -1) {
        if (!spm_json_string(img, "uri")) {
            spm_errorf(err, "%s: neither a uri nor a bufferView", where);
            return 1;
        }
        return 0;
    }
    if (v == -2) {
        spm_errorf(err, "%s.bufferView: not the index of one of the file's %zu bufferViews",
                   where, count(doc, "bufferViews"));
        return 1;
    }
    if (!mime) {
        spm_errorf(err, "%s: an image in bufferView %g without a mimeType", where, v);
        return 1;
    }
    const spm_json *view = &spm_json_get(doc, "bufferViews")->items[(size_t)v];
    double b = index_of(view, "buffer", count(doc, "buffers"));
    double off = bytes_of(view, "byteOffset", 0), len = bytes_of(view, "byteLength", -1);
    double size = b >= 0 ? bytes_of(&spm_json_get(doc, "buffers")->items[(size_t)b],
                                    "byteLength", -1) : -1;
    if (b < 0 || !(off >= 0 && len > 0 && size >= 0 && off + len <= size)) {
        spm_errorf(err, "%s.bufferView %g: bytes %g to %g of buffer %g of %g bytes: not within "
                        "it", where, v, off, off + len, b, size);
        return 1;
    }
    return 0;
}

static int gltf_images(const spm_file *model, const spm_json *doc, spm_error *err)
{
    const spm_json *list = spm_json_get(doc, "images");
    for (size_t i = 0; list && list->type == SPM_JSON_ARRAY && i < list->n; i++) {
        char where[SPM_PATH_MAX + 64];
        snprintf(where, sizeof where, "%s: images[%zu]", model->shown, i);
        if (gltf_image(doc, &list->items[i], where, err))
            return 1;
    }
    return 0;
}

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

/* A .glb's JSON chunk into *json (malloc'd), its length in *len; the header's
 * length and every chunk's checked against the file's size. */
static int glb_json(const spm_file *model, FILE *f, char **json, size_t *len, spm_error *err)
{
    unsigned char h[20];
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    rewind(f);
    size_t got = fread(h, 1, sizeof h, f);
    if (got < 12 || memcmp(h, "glTF", 4)) {
        spm_errorf(err, "%s: not a binary glTF file (%s)", model->shown,
                   got < 12 ? "shorter than its 12-byte header" : "it does not start with 'glTF'");
        return 1;
    }
    if (le32(h + 4) != 2) {
        spm_errorf(err, "%s: binary glTF version %u (only version 2 is read)", model->shown,
                   le32(h + 4));
        return 1;
    }
    if ((long)le32(h + 8) > size) {
        spm_errorf(err, "%s: truncated: its header says %u bytes, the file has %ld",
                   model->shown, le32(h + 8), size);
        return 1;
    }
    uint32_t clen = got == sizeof h ? le32(h + 12) : 0;
    if (got < sizeof h || 20 + (long)clen > size || clen > GLTF_MAX_JSON) {
        spm_errorf(err, "%s: truncated: its JSON chunk (%u bytes) ends past the file's end "
                        "(%ld bytes)", model->shown, clen, size);
        return 1;
    }
    if (le32(h + 16) != 0x4E4F534Au) {
        spm_errorf(err, "%s: the first chunk is not JSON", model->shown);
        return 1;
    }
    *json = spm_xmalloc(clen + 1);
    *len = fread(*json, 1, clen, f);
    /* the chunks after it: each header's length within the file */
    for (long at = 20 + (long)((clen + 3) & ~3u); at < (long)le32(h + 8);) {
        unsigned char c[8];
        fseek(f, at, SEEK_SET);
        if (fread(c, 1, 8, f) != 8 || at + 8 + (long)le32(c) > size) {
            spm_errorf(err, "%s: truncated: a chunk at byte %ld ends past the file's end (%ld "
                            "bytes)", model->shown, at, size);
            free(*json);
            *json = NULL;
            return 1;
        }
        at += 8 + (long)((le32(c) + 3) & ~3u);
    }
    return 0;
}

spm_json *spm_mesh_gltf_doc(const spm_file *model, spm_error *err)
{
    FILE *f = spm_path_fopen(model, "rb");
    if (!f)
        return NULL; /* the importer says why */
    char *text = NULL;
    size_t len = 0;
    int rc = 0;
    if (ends_with(model->shown, ".glb")) {
        rc = glb_json(model, f, &text, &len, err);
    } else {
        fseek(f, 0, SEEK_END);
        long size = ftell(f);
        rewind(f);
        if (size > (long)GLTF_MAX_JSON) {
            spm_errorf(err, "%s: a glTF's JSON of %ld bytes (at most %u MiB)", model->shown, size,
                       GLTF_MAX_JSON >> 20);
            rc = 1;
        } else {
            text = spm_xmalloc((size_t)size + 1);
            len = fread(text, 1, (size_t)size, f);
        }
    }
    fclose(f);
    spm_json *doc = NULL;
    if (!rc) {
        char why[200];
        if (!(doc = spm_json_parse(text, len, why, sizeof why)))
            spm_errorf(err, "%s: its JSON: %s", model->shown, why);
    }
    free(text);
    return doc;
}

static int gltf_check(const spm_file *model, char *unrendered, size_t size, spm_error *err)
{
    err->msg[0] = '\0';
    spm_json *doc = spm_mesh_gltf_doc(model, err);
    if (!doc)
        return err->msg[0] != '\0';
    int rc = gltf_uris(model, doc, err) || gltf_images(model, doc, err);
    gltf_extensions(doc, unrendered, size);
    spm_json_free(doc);
    return rc;
}

/* An MTL statement's file: after the keyword, the options (-name and their
 * values) skipped, the rest of the line. NULL when the line names none. */
static char *mtl_map_file(char *line)
{
    char *s = line + strspn(line, " \t");
    size_t k = strcspn(s, " \t\r\n");
    int map = k > 4 && strncasecmp(s, "map_", 4) == 0;
    static const char *const others[] = {"bump", "disp", "decal", "refl", "norm"};
    for (size_t i = 0; i < sizeof others / sizeof others[0] && !map; i++)
        map = k == strlen(others[i]) && strncasecmp(s, others[i], k) == 0;
    if (!map)
        return NULL;
    s += k;
    for (;;) {
        s += strspn(s, " \t");
        if (*s != '-')
            break;
        s += strcspn(s, " \t\r\n"); /* the option, then its values: numbers or words */
        for (;;) {
            char *v = s + strspn(s, " \t");
            size_t n = strcspn(v, " \t\r\n");
            char *end;
            int word = (n == 2 && !strncasecmp(v, "on", 2)) || (n == 3 && !strncasecmp(v, "off", 3)) ||
                       (n == 1 && strchr("rgbmlz", v[0]));
            strtod(v, &end);
            if (n == 0 || (!word && end != v + n))
                break;
            s = v + n;
        }
    }
    char *e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = '\0';
    return *s ? s : NULL;
}

/* Every line of `f` that names a file (mtllib in an OBJ, a map in an MTL)
 * checked; an OBJ's MTL files read in turn (depth 1). */
static int text_refs(const spm_file *file, int obj, spm_error *err)
{
    FILE *f = spm_path_fopen(file, "r");
    if (!f)
        return 0; /* a missing MTL is warned about by spm_mesh_obj_mtl_check */
    char dir[SPM_PATH_MAX], line[4096], where[SPM_PATH_MAX + 64];
    spm_path_dir(file->path, dir, sizeof dir);
    int rc = 0;
    for (int n = 1; !rc && fgets(line, sizeof line, f); n++) {
        snprintf(where, sizeof where, "%s:%d", file->shown, n);
        if (!obj) {
            char *name = mtl_map_file(line);
            spm_file p;
            rc = name && spm_path_check(dir, name, where, &p, err);
            continue;
        }
        if (strncmp(line, "mtllib", 6) || (line[6] != ' ' && line[6] != '\t'))
            continue;
        for (char *save, *tok = strtok_r(line + 6, " \t\r\n", &save); tok && !rc;
             tok = strtok_r(NULL, " \t\r\n", &save)) {
            spm_file mtl;
            rc = spm_path_check(dir, tok, where, &mtl, err) || text_refs(&mtl, 0, err);
        }
    }
    fclose(f);
    return rc;
}

int spm_mesh_refs_check(const spm_file *model, char *unrendered, size_t size, spm_error *err)
{
    unrendered[0] = '\0';
    if (ends_with(model->shown, ".gltf") || ends_with(model->shown, ".glb"))
        return gltf_check(model, unrendered, size, err);
    if (ends_with(model->shown, ".obj"))
        return text_refs(model, 1, err);
    return 0;
}
