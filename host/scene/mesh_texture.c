/* A mesh material's base-colour texture (mesh_texture.h): found through
 * Assimp in the importer's child (an embedded image, "*N" or by file name, or
 * a file beside the model), averaged by mesh_texture_io.cpp; in the parent,
 * an image file on a textured type's reflectance read into the scene, else its
 * mean colour with a warning. */
#include "mesh_texture.h"
#include "colour.h"
#include "materials.h"
#include "texture.h"
#include <assimp/material.h>
#include <assimp/scene.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* An embedded image stored as texels (Assimp's mHeight > 0): BGRA8 codes,
 * sRGB-encoded. */
static void texel_mean(const struct aiTexture *t, float mean[3])
{
    double sum[3] = {0, 0, 0};
    size_t n = (size_t)t->mWidth * t->mHeight;
    for (size_t i = 0; i < n; i++) {
        const struct aiTexel *p = &t->pcData[i];
        sum[0] += spm_srgb_decode(p->r / 255.0);
        sum[1] += spm_srgb_decode(p->g / 255.0);
        sum[2] += spm_srgb_decode(p->b / 255.0);
    }
    for (int c = 0; c < 3; c++)
        mean[c] = (float)(sum[c] / (double)n);
}

/* The embedded image a texture path names ("*N", or an image's file name), or NULL. */
static const struct aiTexture *embedded(const struct aiScene *sc, const char *path, int *index)
{
    if (path[0] == '*') {
        char *end;
        unsigned long i = strtoul(path + 1, &end, 10);
        if (end == path + 1 || *end || i >= sc->mNumTextures || !sc->mTextures[i])
            return NULL;
        *index = (int)i;
        return sc->mTextures[i];
    }
    for (unsigned i = 0; i < sc->mNumTextures; i++)
        if (sc->mTextures[i] && sc->mTextures[i]->mFilename.length &&
            !strcmp(sc->mTextures[i]->mFilename.data, path)) {
            *index = (int)i;
            return sc->mTextures[i];
        }
    return NULL;
}

int spm_mesh_embedded(const struct aiScene *sc, const char *path)
{
    int index = -1;
    const struct aiTexture *t = embedded(sc, path, &index);
    return t && t->mHeight == 0 && t->pcData && t->mWidth > 0 ? index + 1 : 0;
}

/* Where one texture of a material is described: its name as the file gives
 * it, why it was not read, its file's path (checked) or embedded image, its
 * mean. */
typedef struct {
    char (*name)[96];
    char (*why)[128];
    char (*file)[SPM_PATH_MAX];
    int32_t *embed;
    float *mean;
} image_slot;

/* The mean of the texture `path` names into slot *out: 0, or 1 with why
 * filled, or 2 with why the path rule's error. */
static int texture_mean(const struct aiScene *sc, const char *model, const char *path,
                        const image_slot *out, spm_error *refused)
{
    int index = -1;
    const struct aiTexture *t = embedded(sc, path, &index);
    if (t || path[0] == '*') {
        snprintf(*out->name, sizeof *out->name, "embedded image %d", index);
        if (!t) {
            snprintf(*out->name, sizeof *out->name, "%.95s", path);
            snprintf(*out->why, sizeof *out->why, "the file has no such image");
            return 1;
        }
        if (t->mHeight > 0) {
            if ((long long)t->mWidth * t->mHeight > SPM_TEXTURE_MAX_PIXELS || !t->pcData) {
                snprintf(*out->why, sizeof *out->why, "unsupported image");
                return 1;
            }
            texel_mean(t, out->mean);
            return 0;
        }
        /* compressed (PNG, JPEG...): mWidth bytes; the hint is the format's
         * extension. The parent reads the bytes of one that can be read. */
        int rc = spm_texture_mean_data(t->achFormatHint[0] ? t->achFormatHint : "png",
                                       t->pcData, t->mWidth, out->mean, *out->why,
                                       sizeof *out->why);
        *out->embed = rc ? 0 : spm_mesh_embedded(sc, path);
        return rc;
    }
    /* a file: relative to the model's folder; Windows separators as '/' */
    snprintf(*out->name, sizeof *out->name, "%.95s", path);
    char rel[1024], dir[SPM_PATH_MAX], where[SPM_PATH_MAX + 32];
    snprintf(rel, sizeof rel, "%s", path);
    for (char *c = rel; *c; c++)
        if (*c == '\\')
            *c = '/';
    snprintf(where, sizeof where, "%s: image", model);
    spm_file file;
    if (spm_path_check(spm_path_dir(model, dir, sizeof dir), rel, where, &file, refused))
        return 2;
    snprintf(*out->file, sizeof *out->file, "%s", file.path);
    struct stat st;
    if (stat(file.path, &st) != 0 || !S_ISREG(st.st_mode)) {
        snprintf(*out->why, sizeof *out->why, "no such file beside the model");
        return 1;
    }
    return spm_texture_mean_file(&file, out->mean, *out->why,
                                 sizeof *out->why);
}

int spm_mesh_texture_apply(const struct aiScene *sc, const struct aiMaterial *m,
                           const char *model, spm_mesh_material *out, spm_error *refused)
{
    /* glTF's base colour texture, else the diffuse one (OBJ's map_Kd; Assimp
     * gives a glTF's base colour texture as both) */
    enum aiTextureType type = aiTextureType_BASE_COLOR;
    if (aiGetMaterialTextureCount(m, type) == 0)
        type = aiTextureType_DIFFUSE;
    if (aiGetMaterialTextureCount(m, type) == 0)
        return 0;
    struct aiString path;
    if (aiGetMaterialTexture(m, type, 0, &path, NULL, NULL, NULL, NULL, NULL, NULL) !=
        aiReturn_SUCCESS)
        return 0;
    image_slot slot = {&out->texture_name, &out->texture_why, &out->texture_file,
                       &out->texture_embed, out->texture_mean};
    int rc = texture_mean(sc, model, path.data, &slot, refused);
    if (rc) {
        out->texture = SPM_MESH_TEX_UNREAD;
        return rc == 2 ? 2 : 1;
    }
    out->texture = SPM_MESH_TEX_MEAN;
    for (int c = 0; c < 3; c++) {
        out->factor[c] = out->diffuse[c];
        out->diffuse[c] *= out->texture_mean[c];
    }
    return 1;
}

int spm_mesh_etexture_apply(const struct aiScene *sc, const struct aiMaterial *m,
                            const char *model, spm_mesh_material *out, spm_error *refused)
{
    struct aiString path;
    if (aiGetMaterialTextureCount(m, aiTextureType_EMISSIVE) == 0 ||
        aiGetMaterialTexture(m, aiTextureType_EMISSIVE, 0, &path, NULL, NULL, NULL, NULL, NULL,
                             NULL) != aiReturn_SUCCESS)
        return 0;
    image_slot slot = {&out->etexture_name, &out->etexture_why, &out->etexture_file,
                       &out->etexture_embed, out->etexture_mean};
    int rc = texture_mean(sc, model, path.data, &slot, refused);
    out->etexture = rc ? SPM_MESH_TEX_UNREAD : SPM_MESH_TEX_MEAN;
    return rc == 2 ? 2 : 1;
}

int spm_mesh_map_image(const spm_mesh_data *d, int32_t embed, const char *file,
                       const char *mwhere, spm_file *f, spm_image_src *src, char *why,
                       size_t whylen)
{
    if (embed > 0 && (uint32_t)embed <= d->nimages && d->images[embed - 1].size) {
        const spm_mesh_image *m = &d->images[embed - 1];
        *src = (spm_image_src){NULL, m->data, (size_t)m->size, m->hint};
        return 0;
    }
    if (!file[0]) {
        snprintf(why, whylen, "an embedded image that is not the bytes of an image file");
        return 1;
    }
    spm_error e;
    if (spm_path_check_joined(file, mwhere, f, &e)) {
        snprintf(why, whylen, "%.290s", e.msg);
        return 1;
    }
    *src = (spm_image_src){f, NULL, 0, NULL};
    return 0;
}

/* The image a map names (mesh.h spm_mesh_map_image), times factor per
 * channel, read through the transform uvx, into the scene: its index, or -1
 * with why filled. */
static int bind_image(spm_scene_builder *b, const spm_mesh_data *d, int32_t embed,
                      const char *path, const float factor[3], const spm_uvx *uvx,
                      const char *mwhere, char *why, size_t whylen)
{
    spm_file f;
    spm_image_src src;
    float *rgb;
    int w, h;
    if (spm_mesh_map_image(d, embed, path, mwhere, &f, &src, why, whylen) ||
        spm_texture_read(&src, SPM_IMAGE_COLOUR, &rgb, &w, &h, why, whylen))
        return -1;
    for (size_t i = 0; i < (size_t)3 * w * h; i++)
        rgb[i] *= factor[i % 3];
    spm_texture t;
    spm_texture_from_pixels(w, h, rgb, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT, &t);
    t.uvx = *uvx;
    free(rgb);
    return spm_sb_texture(b, &t);
}

int spm_mesh_texture_bind(spm_scene_builder *b, const spm_mesh_data *d,
                          const spm_mesh_material *m, int material, const char *mwhere,
                          spm_error *err)
{
    char why[300] = "";
    spm_scene_material proto = b->s->materials[material];
    if (m->texture != SPM_MESH_TEX_MEAN) {
        spm_mesh_texture_warn(m, mwhere, NULL);
        return material;
    }
    if (!d->uvs)
        snprintf(why, sizeof why, "the mesh has no texture coordinates");
    else if (!spm_material_textured(proto.type))
        snprintf(why, sizeof why, "%s", SPM_TEXTURED_TYPES_WHY);
    int t = why[0] ? -1
                   : bind_image(b, d, m->texture_embed, m->texture_file, m->factor,
                                &m->uvx[SPM_MESH_MAP_BASE], mwhere, why, sizeof why);
    if (t < 0) {
        spm_mesh_texture_warn(m, mwhere, why);
        return material;
    }
    proto.tex = 1 + t;
    return spm_sb_material_typed(b, &proto, mwhere, err);
}
void spm_mesh_texture_warn(const spm_mesh_material *m, const char *mwhere, const char *why)
{
    if (m->texture == SPM_MESH_TEX_MEAN)
        spm_warnf("%s: base-colour texture '%s' replaced by its mean colour (%.3g %.3g %.3g, "
                  "linear) times the material's colour: %s",
                  mwhere, m->texture_name, m->texture_mean[0], m->texture_mean[1],
                  m->texture_mean[2], why);
    else if (m->texture == SPM_MESH_TEX_UNREAD)
        spm_warnf("%s: base-colour texture '%s' cannot be read (%s): the material's colour "
                  "alone is used", mwhere, m->texture_name, m->texture_why);
}

int spm_mesh_etexture_bind(spm_scene_builder *b, const spm_mesh_data *d,
                           const spm_mesh_material *m, int material, const char *mwhere,
                           spm_error *err)
{
    spm_scene_material proto = b->s->materials[material];
    if (m->etexture == SPM_MESH_TEX_NONE || proto.emit < 0)
        return material; /* no texture, or a factor of 0: nothing emits */
    if (m->etexture == SPM_MESH_TEX_UNREAD) {
        spm_warnf("%s: emissive texture '%s' cannot be read (%s): the emissive factor alone "
                  "is used", mwhere, m->etexture_name, m->etexture_why);
        return material;
    }
    /* the texels times the factor over its largest component, which is the
     * emission's scale: the texels stay within the colour grid's [0, 1] */
    float fm = fmaxf(m->emission[0], fmaxf(m->emission[1], m->emission[2])), f[3];
    double mean[3];
    for (int c = 0; c < 3; c++)
        f[c] = m->emission[c] / fm, mean[c] = (double)m->emission[c] * m->etexture_mean[c];
    char why[300] = "the mesh has no texture coordinates";
    int t = !d->uvs ? -1
                    : bind_image(b, d, m->etexture_embed, m->etexture_file, f,
                                 &m->uvx[SPM_MESH_MAP_EMIT], mwhere, why, sizeof why);
    if (t < 0)
        spm_warnf("%s: emissive texture '%s' replaced by its mean colour (%.3g %.3g %.3g, "
                  "linear) times the emissive factor: %s", mwhere, m->etexture_name,
                  m->etexture_mean[0], m->etexture_mean[1], m->etexture_mean[2], why);
    spm_names fits;
    spm_names_init(&fits);
    int e = spm_sb_rgb_colour(b, &fits, mean, SPM_KIND_EMISSION, mwhere, err);
    spm_names_free(&fits);
    if (e < -1)
        return -1;
    proto.emit = e; /* the mean's: what the light pick reads (-1: a black image, dark) */
    if (t >= 0 && e >= 0)
        proto.etex = 1 + t, proto.escale = fm;
    return spm_sb_material_typed(b, &proto, mwhere, err);
}
