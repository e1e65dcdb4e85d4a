/* The child importer's answer on its pipe: a header, the file's materials and
 * the triangles, in this machine's byte order. The parent checks everything
 * before use: a child that misbehaves must not take the renderer down. */
#include "mesh.h"
#include <stdlib.h>
#include <string.h>

#define WIRE_MAGIC 0x4d4d5053u /* "SPMM" */

typedef struct {
    uint32_t magic, status, ignored, nmats;
    uint64_t ntris;
    uint32_t flags, nlights; /* SPM_MESH_WIRE_* */
    uint32_t nimages, spare;
    uint64_t image_bytes;
} wire_header;
_Static_assert(sizeof(wire_header) == SPM_MESH_WIRE_HEAD, "mesh.h's header size");

/* Where the images' records start: after the lights, at a multiple of 8
 * (they hold 64-bit sizes and pointers). */
static size_t images_at(uint32_t nmats, uint64_t ntris, uint32_t flags, uint32_t nlights)
{
    size_t n = sizeof(wire_header) + nmats * sizeof(spm_mesh_material) +
               ntris * sizeof(spm_mesh_tri) +
               (flags & SPM_MESH_WIRE_NORMALS ? ntris * sizeof(spm_mesh_normals) : 0) +
               (flags & SPM_MESH_WIRE_UVS ? ntris * sizeof(spm_mesh_uvs) : 0) +
               (flags & SPM_MESH_WIRE_TANGENTS ? ntris * sizeof(spm_mesh_tangents) : 0) +
               nlights * sizeof(spm_mesh_light);
    return (n + 7) & ~(size_t)7;
}

size_t spm_mesh_wire_size(uint32_t nmats, uint64_t ntris, uint32_t flags, uint32_t nlights,
                          uint32_t nimages, uint64_t image_bytes)
{
    if (flags & ~(SPM_MESH_WIRE_NORMALS | SPM_MESH_WIRE_UVS | SPM_MESH_WIRE_TANGENTS) || nlights > SPM_MESH_MAX_LIGHTS ||
        nimages > SPM_MESH_MAX_IMAGES || image_bytes > SPM_MESH_MAX_IMAGE_BYTES)
        return 0;
    return images_at(nmats, ntris, flags, nlights) + nimages * sizeof(spm_mesh_image) +
           image_bytes;
}

void *spm_mesh_encode(const spm_mesh_data *d, size_t *size)
{
    uint32_t flags = (d->normals ? SPM_MESH_WIRE_NORMALS : 0u) | (d->uvs ? SPM_MESH_WIRE_UVS : 0u) |
                     (d->tangents ? SPM_MESH_WIRE_TANGENTS : 0u);
    uint64_t nb = 0;
    for (uint32_t i = 0; i < d->nimages; i++)
        nb += d->images[i].size;
    wire_header h = {WIRE_MAGIC, 0, d->ignored, d->nmats, d->ntris, flags, d->nlights,
                     d->nimages, 0, nb};
    size_t nn = d->normals ? d->ntris * sizeof *d->normals : 0;
    size_t nu = d->uvs ? d->ntris * sizeof *d->uvs : 0;
    size_t nt = d->tangents ? d->ntris * sizeof *d->tangents : 0;
    size_t ni = images_at(d->nmats, d->ntris, flags, d->nlights);
    size_t nl = d->nlights * sizeof *d->lights;
    size_t n = spm_mesh_wire_size(d->nmats, d->ntris, flags, d->nlights, d->nimages, nb);
    unsigned char *buf = spm_xmalloc(n);
    memset(buf, 0, n);
    memcpy(buf, &h, sizeof h);
    if (d->nmats)
        memcpy(buf + sizeof h, d->mats, d->nmats * sizeof *d->mats);
    if (d->ntris)
        memcpy(buf + sizeof h + d->nmats * sizeof *d->mats, d->tris, d->ntris * sizeof *d->tris);
    size_t end = sizeof h + d->nmats * sizeof *d->mats + d->ntris * sizeof *d->tris + nn + nu + nt;
    if (nn)
        memcpy(buf + end - nt - nu - nn, d->normals, nn);
    if (nu)
        memcpy(buf + end - nt - nu, d->uvs, nu);
    if (nt)
        memcpy(buf + end - nt, d->tangents, nt);
    if (nl)
        memcpy(buf + end, d->lights, nl);
    unsigned char *at = buf + ni;
    if (d->nimages)
        memcpy(at, d->images, d->nimages * sizeof *d->images);
    at += d->nimages * sizeof *d->images;
    for (uint32_t i = 0; i < d->nimages; i++) {
        if (d->images[i].size)
            memcpy(at, d->images[i].data, d->images[i].size);
        at += d->images[i].size;
    }
    *size = n;
    return buf;
}

static int embed_ok(int32_t embed, uint32_t nimages)
{
    return embed >= 0 && (uint32_t)embed <= nimages;
}

/* The images' records at `at`: their sizes summed against the header's,
 * their hints terminated, their bytes located. */
static int images(unsigned char *at, const wire_header *h, spm_mesh_data *out, const char *path,
                  spm_error *err)
{
    out->nimages = h->nimages;
    out->images = h->nimages ? (spm_mesh_image *)at : NULL;
    at += h->nimages * sizeof(spm_mesh_image);
    uint64_t left = h->image_bytes;
    for (uint32_t i = 0; i < h->nimages; i++) {
        spm_mesh_image *m = &out->images[i];
        if (m->size > left) {
            spm_errorf(err, "%s: the importer returned a bad image", path);
            memset(out, 0, sizeof *out);
            return 1;
        }
        m->hint[sizeof m->hint - 1] = 0;
        m->data = at;
        at += m->size;
        left -= m->size;
    }
    if (left) {
        spm_errorf(err, "%s: the importer returned a bad image", path);
        memset(out, 0, sizeof *out);
        return 1;
    }
    return 0;
}

int spm_mesh_decode(void *buf, size_t size, const char *path, spm_mesh_data *out,
                    spm_error *err)
{
    memset(out, 0, sizeof *out);
    wire_header h;
    if (size < sizeof h) {
        spm_errorf(err, "%s: the importer returned no data", path);
        return 1;
    }
    memcpy(&h, buf, sizeof h);
    if (h.magic != WIRE_MAGIC) {
        spm_errorf(err, "%s: the importer returned garbage", path);
        return 1;
    }
    if (h.status != 0) {
        char msg[600];
        size_t n = size - sizeof h < sizeof msg - 1 ? size - sizeof h : sizeof msg - 1;
        memcpy(msg, (char *)buf + sizeof h, n);
        msg[n] = 0;
        for (size_t i = 0; i < n; i++)
            if ((unsigned char)msg[i] < 32 || msg[i] == 127)
                msg[i] = ' ';
        while (n > 0 && msg[n - 1] == ' ')
            msg[--n] = 0;
        spm_errorf(err, "%s: %s", path, msg[0] ? msg : "the importer failed");
        return 1;
    }
    if (h.nmats > SPM_MESH_MAX_MATERIALS) {
        spm_errorf(err, "%s: more than %d materials", path, SPM_MESH_MAX_MATERIALS);
        return 1;
    }
    if (h.ntris == 0) {
        spm_errorf(err, "%s: the file has no triangles", path);
        return 1;
    }
    if (h.ntris > SPM_SCENE_MAX_TRIS) {
        spm_errorf(err, "%s: more than %d triangles", path, SPM_SCENE_MAX_TRIS);
        return 1;
    }
    int has_n = (h.flags & SPM_MESH_WIRE_NORMALS) != 0, has_uv = (h.flags & SPM_MESH_WIRE_UVS) != 0;
    int has_t = (h.flags & SPM_MESH_WIRE_TANGENTS) != 0;
    size_t want = spm_mesh_wire_size(h.nmats, h.ntris, h.flags, h.nlights, h.nimages,
                                     h.image_bytes);
    if (size != want || (h.ntris > 0 && h.nmats == 0) || want == 0) {
        spm_errorf(err, "%s: the importer returned %zu bytes where %zu were due", path, size,
                   want);
        return 1;
    }
    spm_mesh_material *mats = (spm_mesh_material *)((char *)buf + sizeof h);
    spm_mesh_tri *tris = (spm_mesh_tri *)((char *)buf + sizeof h + h.nmats * sizeof *mats);
    for (uint32_t i = 0; i < h.nmats; i++) {
        mats[i].name[SPM_NAME_MAX - 1] = 0;
        mats[i].texture_name[sizeof mats[i].texture_name - 1] = 0;
        mats[i].texture_why[sizeof mats[i].texture_why - 1] = 0;
        mats[i].texture_file[sizeof mats[i].texture_file - 1] = 0;
        mats[i].alpha_name[sizeof mats[i].alpha_name - 1] = 0;
        mats[i].etexture_name[sizeof mats[i].etexture_name - 1] = 0;
        mats[i].etexture_why[sizeof mats[i].etexture_why - 1] = 0;
        mats[i].etexture_file[sizeof mats[i].etexture_file - 1] = 0;
        mats[i].alpha_file[sizeof mats[i].alpha_file - 1] = 0;
        mats[i].mr_name[sizeof mats[i].mr_name - 1] = 0;
        mats[i].mr_file[sizeof mats[i].mr_file - 1] = 0;
        mats[i].nmap_name[sizeof mats[i].nmap_name - 1] = 0;
        mats[i].nmap_file[sizeof mats[i].nmap_file - 1] = 0;
        if (mats[i].nmap < SPM_MESH_NMAP_NONE || mats[i].nmap > SPM_MESH_NMAP_BUMP)
            mats[i].nmap = SPM_MESH_NMAP_NONE, mats[i].nmap_file[0] = 0;
        if (mats[i].texture < SPM_MESH_TEX_NONE || mats[i].texture > SPM_MESH_TEX_UNREAD ||
            mats[i].etexture < SPM_MESH_TEX_NONE || mats[i].etexture > SPM_MESH_TEX_UNREAD ||
            mats[i].alpha_mode < SPM_MESH_ALPHA_OPAQUE || mats[i].alpha_mode > SPM_MESH_ALPHA_BLEND ||
            mats[i].alpha_map < SPM_MESH_AMAP_NONE || mats[i].alpha_map > SPM_MESH_AMAP_FILE ||
            mats[i].mr_map < SPM_MESH_MRMAP_NONE || mats[i].mr_map > SPM_MESH_MRMAP_EMBEDDED ||
            !embed_ok(mats[i].texture_embed, h.nimages) ||
            !embed_ok(mats[i].etexture_embed, h.nimages) ||
            !embed_ok(mats[i].mr_embed, h.nimages) || !embed_ok(mats[i].nmap_embed, h.nimages)) {
            spm_errorf(err, "%s: the importer returned a bad material", path);
            return 1;
        }
    }
    for (uint64_t t = 0; t < h.ntris; t++)
        if (tris[t].mat >= h.nmats) {
            spm_errorf(err, "%s: the importer returned a bad material index", path);
            return 1;
        }
    out->ignored = h.ignored & ((1u << SPM_MESH_IGN_COUNT) - 1);
    out->nmats = h.nmats;
    out->ntris = h.ntris;
    out->mats = mats;
    out->tris = tris;
    char *after = (char *)(tris + h.ntris); /* the per-triangle arrays, in order */
    out->normals = has_n ? (spm_mesh_normals *)after : NULL;
    after += has_n ? h.ntris * sizeof(spm_mesh_normals) : 0;
    out->uvs = has_uv ? (spm_mesh_uvs *)after : NULL;
    after += has_uv ? h.ntris * sizeof(spm_mesh_uvs) : 0;
    out->tangents = has_t ? (spm_mesh_tangents *)after : NULL;
    after += has_t ? h.ntris * sizeof(spm_mesh_tangents) : 0;
    size_t ni = images_at(h.nmats, h.ntris, h.flags, h.nlights);
    out->nlights = h.nlights;
    out->lights = h.nlights ? (spm_mesh_light *)after : NULL;
    if (images((unsigned char *)buf + ni, &h, out, path, err))
        return 1;
    for (uint32_t i = 0; i < h.nlights; i++) {
        out->lights[i].name[sizeof out->lights[i].name - 1] = 0;
        if (out->lights[i].type < SPM_MESH_LIGHT_POINT ||
            out->lights[i].type > SPM_MESH_LIGHT_DIRECTIONAL) {
            spm_errorf(err, "%s: the importer returned a bad light", path);
            memset(out, 0, sizeof *out);
            return 1;
        }
    }
    out->buf = buf;
    return 0;
}

void spm_mesh_free(spm_mesh_data *d)
{
    free(d->buf);
    memset(d, 0, sizeof *d);
}

const char *spm_mesh_ignored_name(int bit)
{
    static const char *names[SPM_MESH_IGN_COUNT] = {
        "vertex normals", "texture coordinates", "vertex colours", "textures", "normal maps",
        "glossy and metallic parameters", "opacity", "cameras", "lights",
        "animations, skins and morph targets", "points and lines",
        "glTF emissive strengths that are not a non-negative number "
        "(KHR_materials_emissive_strength: the emissiveFactor alone is used)",
        "glTF light ranges (KHR_lights_punctual `range`: specmip's point and spot lights fall "
        "as 1/d^2 without a cut-off)",
        "emissive textures (glTF emissiveTexture, MTL map_Ke: an emission is its factor alone, "
        "untextured)",
        "occlusion maps (a path tracer computes the occlusion they stand for)",
        "MTL specular colour maps (map_Ks: the Ks value is used throughout)",
        "texture transforms outside glTF's KHR_texture_transform and texture coordinate "
        "sets other than the first (texCoord other than 0: such textures are read "
        "untransformed at TEXCOORD_0)"};
    return bit >= 0 && bit < SPM_MESH_IGN_COUNT ? names[bit] : "?";
}
