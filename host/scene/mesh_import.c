/* Mesh import through Assimp's C API, run in a child process: the child reads
 * the file under address-space, CPU and wall-clock limits, flattens the node
 * hierarchy and writes its triangles to a pipe (mesh_wire.c); the parent waits
 * on the pipe, polling for a stop request, and treats a crash or a limit hit
 * as an error in the file. Options: triangulate only; joining identical
 * vertices would cost about a second and 380 MB per million triangles and
 * nothing needs it (smooth shading takes the file's own vertex normals, per
 * triangle). */
#define _GNU_SOURCE /* memmem */
#include "mesh.h"
#include "mesh_gltf.h"
#include "interrupt.h"
#include "mesh_ply.h"
#include "mesh_texture.h"
#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#define SPM_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SPM_ASAN 1
#endif
#endif

/* ---- the child ------------------------------------------------------------- */

typedef struct {
    int fd;
    unsigned char buf[1 << 16];
    size_t n;
    int failed;
} writer;

static void w_flush(writer *w)
{
    size_t off = 0;
    while (off < w->n && !w->failed) {
        ssize_t k = write(w->fd, w->buf + off, w->n - off);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            w->failed = 1;
        else
            off += (size_t)k;
    }
    w->n = 0;
}

static void w_put(writer *w, const void *p, size_t n)
{
    const unsigned char *c = p;
    while (n) {
        size_t k = sizeof w->buf - w->n < n ? sizeof w->buf - w->n : n;
        memcpy(w->buf + w->n, c, k);
        w->n += k;
        c += k;
        n -= k;
        if (w->n == sizeof w->buf)
            w_flush(w);
    }
}

static void child_fail(writer *w, const char *msg)
{
    uint32_t h[SPM_MESH_WIRE_HEAD / 4] = {0x4d4d5053u, 1};
    w_put(w, h, sizeof h);
    w_put(w, msg, strlen(msg));
    w_flush(w);
    _exit(0);
}

/* x' = M x for a 3x4 row-major affine map */
typedef double affine[3][4];

static void affine_mul(const affine a, const affine b, affine out)
{
    affine r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++) {
            r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
            if (j == 3)
                r[i][j] += a[i][3];
        }
    memcpy(out, r, sizeof r);
}

static double affine_det(const affine m)
{
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* The normals' map of x' = M x + t: the inverse transpose of M,
 * cofactor(M) / det(M) (row-major 3x3). */
static void normal_matrix(const affine m, double out[3][3])
{
    double det = affine_det(m), inv = det != 0.0 ? 1.0 / det : 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            out[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) * inv;
        }
}

typedef struct {
    const struct aiScene *sc;
    writer *w;
    uint64_t count;    /* triangles so far */
    int emit;          /* 0: count only, 1: write the triangles, 2: their vertex normals,
                          3: their texture coordinates, 4: their tangents */
    uint32_t ignored;
    int stl;
    unsigned char *used; /* per material: a triangle uses it */
} walk;

/* Whether Assimp kept a mesh's tangents: glTF's TANGENT gives mTangents and
 * mBitangents = w (N x T), which only exist with normals. */
static int has_tangents(const struct aiMesh *m)
{
    return m->mTangents && m->mBitangents && m->mNormals;
}

/* A face's file tangents (zero where its mesh has none): each vertex's T
 * through x's linear part, as a direction on the surface is, and its
 * handedness w, the side of N x T its bitangent is on, reversed by a mirror
 * (det < 0 turns (M N') x (M T) against M B). */
static void face_tangents(const struct aiMesh *m, const unsigned idx[3], const affine x,
                          spm_mesh_tangents *out)
{
    memset(out, 0, sizeof *out);
    if (!has_tangents(m))
        return;
    double mirror = affine_det(x) < 0 ? -1.0 : 1.0;
    for (int v = 0; v < 3; v++) {
        const struct aiVector3D *t = &m->mTangents[idx[v]], *b = &m->mBitangents[idx[v]],
                                *n = &m->mNormals[idx[v]];
        double c[3] = {n->y * t->z - n->z * t->y, n->z * t->x - n->x * t->z,
                       n->x * t->y - n->y * t->x};
        double side = c[0] * b->x + c[1] * b->y + c[2] * b->z;
        for (int i = 0; i < 3; i++)
            out->t[v][i] = (float)(x[i][0] * t->x + x[i][1] * t->y + x[i][2] * t->z);
        out->t[v][3] = (float)(side < 0 ? -mirror : mirror);
    }
}

static int mesh_tris(walk *k, const struct aiMesh *m, const affine x)
{
    int flip = affine_det(x) < 0; /* a mirror: keep each face's front side */
    if (m->mMaterialIndex >= k->sc->mNumMaterials)
        child_fail(k->w, "a mesh refers to a material the file does not have");
    for (unsigned f = 0; f < m->mNumFaces; f++) {
        const struct aiFace *face = &m->mFaces[f];
        if (face->mNumIndices != 3) {
            k->ignored |= SPM_MESH_IGN_POINTS_LINES;
            continue;
        }
        if (++k->count > SPM_SCENE_MAX_TRIS)
            return 1;
        k->used[m->mMaterialIndex] = 1;
        /* checked while counting, before anything is written */
        for (int v = 0; v < 3; v++)
            if (face->mIndices[v] >= m->mNumVertices)
                child_fail(k->w, "a face refers to a vertex the file does not have");
        if (!k->emit)
            continue;
        if (k->emit == 4) {
            unsigned idx[3];
            for (int v = 0; v < 3; v++)
                idx[v] = face->mIndices[flip && v ? 3 - v : v];
            spm_mesh_tangents tg;
            face_tangents(m, idx, x, &tg);
            w_put(k->w, &tg, sizeof tg);
            continue;
        }
        if (k->emit == 3) { /* zero where the mesh has none */
            spm_mesh_uvs tu;
            memset(&tu, 0, sizeof tu);
            for (int v = 0; v < 3 && m->mTextureCoords[0]; v++) {
                const struct aiVector3D *q =
                    &m->mTextureCoords[0][face->mIndices[flip && v ? 3 - v : v]];
                tu.uv[v][0] = (float)q->x;
                tu.uv[v][1] = (float)q->y;
            }
            w_put(k->w, &tu, sizeof tu);
            continue;
        }
        if (k->emit == 2) { /* zero where the mesh has none */
            spm_mesh_normals nt;
            memset(&nt, 0, sizeof nt);
            double nm[3][3];
            normal_matrix(x, nm);
            for (int v = 0; v < 3 && m->mNormals && !k->stl; v++) {
                const struct aiVector3D *q = &m->mNormals[face->mIndices[flip && v ? 3 - v : v]];
                for (int i = 0; i < 3; i++)
                    nt.n[v][i] = (float)(nm[i][0] * q->x + nm[i][1] * q->y + nm[i][2] * q->z);
            }
            w_put(k->w, &nt, sizeof nt);
            continue;
        }
        spm_mesh_tri t;
        for (int v = 0; v < 3; v++) {
            unsigned idx = face->mIndices[flip && v ? 3 - v : v];
            const struct aiVector3D *p = &m->mVertices[idx];
            for (int i = 0; i < 3; i++)
                t.p[v][i] = (float)(x[i][0] * p->x + x[i][1] * p->y + x[i][2] * p->z + x[i][3]);
        }
        t.mat = m->mMaterialIndex;
        w_put(k->w, &t, sizeof t);
    }
    return 0;
}

/* Node transforms applied and instances expanded (a mesh used by two nodes
 * is two sets of triangles). */
static int walk_node(walk *k, const struct aiNode *n, const affine parent, int depth)
{
    if (depth > SPM_MESH_MAX_DEPTH)
        child_fail(k->w, "the node hierarchy is deeper than 256 levels");
    const struct aiMatrix4x4 *t = &n->mTransformation;
    affine local = {{t->a1, t->a2, t->a3, t->a4}, {t->b1, t->b2, t->b3, t->b4},
                    {t->c1, t->c2, t->c3, t->c4}};
    affine x;
    affine_mul(parent, local, x);
    for (unsigned i = 0; i < n->mNumMeshes; i++) {
        if (n->mMeshes[i] >= k->sc->mNumMeshes)
            child_fail(k->w, "a node refers to a mesh the file does not have");
        if (mesh_tris(k, k->sc->mMeshes[n->mMeshes[i]], x))
            return 1;
    }
    for (unsigned i = 0; i < n->mNumChildren; i++)
        if (walk_node(k, n->mChildren[i], x, depth + 1))
            return 1;
    return 0;
}

static int file_mentions(const spm_file *file, const char *needle);
static int ends_with_ci(const char *s, const char *suffix);

static int has_colour(const struct aiMaterial *m, const char *key, unsigned type, unsigned idx,
                      float out[3])
{
    struct aiColor4D c;
    if (aiGetMaterialColor(m, key, type, idx, &c) != aiReturn_SUCCESS)
        return 0;
    out[0] = c.r;
    out[1] = c.g;
    out[2] = c.b;
    return 1;
}

/* 1 when a texture of `type` is read through a transform (glTF's
 * KHR_texture_transform, which Assimp gives as a UV transform) or from
 * another coordinate set than the first (texCoord): neither is applied. */
static int uv_transformed(const struct aiMaterial *m, enum aiTextureType type)
{
    struct aiUVTransform t;
    int src = 0;
    if (aiGetMaterialIntegerArray(m, AI_MATKEY_UVWSRC(type, 0), &src, NULL) == aiReturn_SUCCESS &&
        src != 0)
        return 1;
    if (aiGetMaterialUVTransform(m, AI_MATKEY_UVTRANSFORM(type, 0), &t) != aiReturn_SUCCESS)
        return 0;
    return t.mTranslation.x != 0 || t.mTranslation.y != 0 || t.mScaling.x != 1 ||
           t.mScaling.y != 1 || t.mRotation != 0;
}

/* A material; what it holds that is ignored goes to *ignored. Assimp's own
 * default material (for files without materials) gets no name: such a mesh
 * needs a `material` clause. A base-colour texture's mean multiplies the
 * colour (mesh_texture.c). */
static int material(const struct aiScene *sc, const spm_file *file, const struct aiMaterial *m,
                    spm_mesh_material *out, uint32_t *ignored, spm_error *refused)
{
    const char *path = file->shown;
    memset(out, 0, sizeof *out);
    struct aiString s;
    if (aiGetMaterialString(m, AI_MATKEY_NAME, &s) == aiReturn_SUCCESS &&
        strcmp(s.data, AI_DEFAULT_MATERIAL_NAME) != 0)
        snprintf(out->name, sizeof out->name, "%.*s", (int)(s.length < 63 ? s.length : 63),
                 s.data);
    if (!out->name[0])
        return 0; /* its colours and defaults are Assimp's, not the file's */
    /* glTF's base colour where there is one, else the diffuse colour */
    if (!has_colour(m, AI_MATKEY_BASE_COLOR, out->diffuse) &&
        !has_colour(m, AI_MATKEY_COLOR_DIFFUSE, out->diffuse))
        out->diffuse[0] = out->diffuse[1] = out->diffuse[2] = 0.0f;
    int base_tex = spm_mesh_texture_apply(sc, m, file->path, out, refused);
    if (base_tex == 2)
        return 1;
    int emit_tex = spm_mesh_etexture_apply(sc, m, file->path, out, refused);
    if (emit_tex == 2)
        return 1;
    if (has_colour(m, AI_MATKEY_COLOR_EMISSIVE, out->emission)) {
        float strength;
        if (!spm_mesh_gltf_is(path) && /* a glTF's: from its JSON (mesh_gltf.c) */
            aiGetMaterialFloatArray(m, AI_MATKEY_EMISSIVE_INTENSITY, &strength, NULL) ==
                aiReturn_SUCCESS)
            for (int i = 0; i < 3; i++)
                out->emission[i] *= strength;
    }
    /* what mesh_pbr.c maps, each as the format means it (Assimp 5.2 fills
     * the metallic-roughness keys for glTF only, and Ks, Ns for OBJ) */
    int gltf = ends_with_ci(path, ".gltf") || ends_with_ci(path, ".glb"), obj = ends_with_ci(path, ".obj");
    out->format = gltf ? SPM_MESH_FMT_GLTF : obj ? SPM_MESH_FMT_OBJ : SPM_MESH_FMT_OTHER;
#define GETF(key, field, bit) \
    if (aiGetMaterialFloatArray(m, key, &out->field, NULL) == aiReturn_SUCCESS) out->has |= bit;
    if (gltf) {
        GETF(AI_MATKEY_METALLIC_FACTOR, metallic, SPM_MESH_HAS_METALLIC)
        GETF(AI_MATKEY_ROUGHNESS_FACTOR, roughness, SPM_MESH_HAS_ROUGHNESS)
        GETF(AI_MATKEY_TRANSMISSION_FACTOR, transmission, SPM_MESH_HAS_TRANSMISSION)
        GETF(AI_MATKEY_VOLUME_THICKNESS_FACTOR, thickness, SPM_MESH_HAS_VOLUME)
        GETF(AI_MATKEY_VOLUME_ATTENUATION_DISTANCE, atten_dist, SPM_MESH_HAS_VOLUME)
        if (has_colour(m, AI_MATKEY_VOLUME_ATTENUATION_COLOR, out->atten_colour))
            out->has |= SPM_MESH_HAS_VOLUME;
        /* Assimp gives every glTF material an index: only KHR_materials_ior's counts */
        static int ior_ext = -1; /* one file per child: looked for once */
        if (ior_ext < 0)
            ior_ext = file_mentions(file, "KHR_materials_ior");
        if (ior_ext)
            GETF(AI_MATKEY_REFRACTI, ior, SPM_MESH_HAS_IOR)
    }
    if (obj) {
        if (has_colour(m, AI_MATKEY_COLOR_SPECULAR, out->specular))
            out->has |= SPM_MESH_HAS_SPECULAR;
        GETF(AI_MATKEY_SHININESS, shininess, SPM_MESH_HAS_SHININESS)
        GETF(AI_MATKEY_REFRACTI, ior, SPM_MESH_HAS_IOR)
    }
    GETF(AI_MATKEY_OPACITY, opacity, SPM_MESH_HAS_OPACITY)
#undef GETF
    if (spm_mesh_alpha_read(m, file->path, out, refused) ||
        spm_mesh_nmap_read(m, file->path, out, refused))
        return 1;
    if (spm_mesh_mix_read(m, file->path, out, refused))
        return 1;
    if (out->mr_map == SPM_MESH_MRMAP_EMBEDDED)
        out->mr_embed = spm_mesh_embedded(sc, out->mr_name);
    if (out->nmap && !out->nmap_file[0])
        out->nmap_embed = spm_mesh_embedded(sc, out->nmap_name);
    for (int type = 1; type <= AI_TEXTURE_TYPE_MAX; type++) {
        if (aiGetMaterialTextureCount(m, (enum aiTextureType)type) > 0 &&
            uv_transformed(m, (enum aiTextureType)type))
            *ignored |= SPM_MESH_IGN_TEX_TRANSFORM;
        if (aiGetMaterialTextureCount(m, (enum aiTextureType)type) > 0 &&
            !(base_tex && (type == aiTextureType_BASE_COLOR || type == aiTextureType_DIFFUSE)) &&
            !(out->alpha_map == SPM_MESH_AMAP_FILE && type == aiTextureType_OPACITY) &&
            !(out->mr_map && (type == aiTextureType_UNKNOWN || type == aiTextureType_METALNESS ||
                              type == aiTextureType_DIFFUSE_ROUGHNESS ||
                              (obj && type == aiTextureType_SHININESS))) &&
            !(emit_tex && type == aiTextureType_EMISSIVE) &&
            !(out->nmap && (type == aiTextureType_NORMALS || type == aiTextureType_HEIGHT)))
            *ignored |= type == aiTextureType_NORMALS || type == aiTextureType_HEIGHT ||
                                  type == aiTextureType_NORMAL_CAMERA
                              ? SPM_MESH_IGN_NORMAL_MAPS
                          : type == aiTextureType_EMISSIVE || type == aiTextureType_EMISSION_COLOR
                              ? SPM_MESH_IGN_EMISSIVE_TEXTURES
                        : type == aiTextureType_LIGHTMAP || type == aiTextureType_AMBIENT_OCCLUSION
                              ? SPM_MESH_IGN_OCCLUSION
                        : obj && type == aiTextureType_SPECULAR
                              ? SPM_MESH_IGN_SPECULAR_MAPS
                              : SPM_MESH_IGN_TEXTURES;
    }
    return 0;
}

static int ends_with_ci(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    if (n < m)
        return 0;
    for (size_t i = 0; i < m; i++)
        if (tolower((unsigned char)s[n - m + i]) != suffix[i])
            return 0;
    return 1;
}

/* Whether the file's bytes (the first 64 MiB: glTF's JSON comes first)
 * contain `needle`. Assimp 5.2 drops glTF's emissive strength without a word. */
static int file_mentions(const spm_file *file, const char *needle)
{
    FILE *f = spm_path_fopen(file, "rb");
    if (!f)
        return 0;
    static char buf[(1 << 20) + 64];
    size_t keep = 0, m = strlen(needle);
    int found = 0;
    for (int i = 0; i < 64 && !found; i++) {
        size_t n = fread(buf + keep, 1, 1 << 20, f);
        if (n == 0)
            break;
        found = memmem(buf, keep + n, needle, m) != NULL;
        size_t tail = keep + n < m ? keep + n : m - 1;
        memmove(buf, buf + keep + n - tail, tail);
        keep = tail;
    }
    fclose(f);
    return found;
}

/* ---- the child's files: each one the importer opens goes through the path
 * rule (paths.h), and the first refusal ends the import with its error ---- */

static spm_error io_refused;
static int io_was_refused;
static const char *io_model;

static size_t io_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    return fread(buf, size, count, (FILE *)f->UserData);
}

static size_t io_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0;
}

static size_t io_tell(struct aiFile *f)
{
    long at = ftell((FILE *)f->UserData);
    return at < 0 ? 0 : (size_t)at;
}

static size_t io_size(struct aiFile *f)
{
    FILE *fp = (FILE *)f->UserData;
    long at = ftell(fp), n = fseek(fp, 0, SEEK_END) ? -1 : ftell(fp);
    fseek(fp, at, SEEK_SET);
    return n < 0 ? 0 : (size_t)n;
}

static enum aiReturn io_seek(struct aiFile *f, size_t off, enum aiOrigin o)
{
    int whence = o == aiOrigin_SET ? SEEK_SET : o == aiOrigin_CUR ? SEEK_CUR : SEEK_END;
    return fseek((FILE *)f->UserData, (long)off, whence) ? aiReturn_FAILURE : aiReturn_SUCCESS;
}

static void io_flush(struct aiFile *f)
{
    (void)f;
}

static struct aiFile *io_open(struct aiFileIO *io, const char *name, const char *mode)
{
    (void)io;
    char where[SPM_PATH_MAX + 48];
    snprintf(where, sizeof where, "%s: a file its importer asked for", io_model);
    spm_file p;
    spm_error e;
    if (strpbrk(mode, "wa+"))
        return NULL;
    if (spm_path_check_joined(name, where, &p, &e)) {
        if (!io_was_refused)
            io_refused = e;
        io_was_refused = 1;
        return NULL;
    }
    FILE *fp = spm_path_fopen(&p, "rb");
    if (!fp)
        return NULL;
    struct aiFile *f = calloc(1, sizeof *f);
    if (!f) {
        fclose(fp);
        return NULL;
    }
    *f = (struct aiFile){io_read, io_write, io_tell, io_size, io_seek, io_flush, (char *)fp};
    return f;
}

static void io_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    fclose((FILE *)f->UserData);
    free(f);
}

/* The child's limits and signals (and the test hook of mesh.h: a crash, a
 * hang, or a smaller address-space limit); its address-space limit in bytes. */
static rlim_t child_limits(pid_t parent)
{
    signal(SIGINT, SIG_DFL); /* Ctrl-C reaches the whole process group: end at once */
    signal(SIGTERM, SIG_DFL);
    signal(SIGPIPE, SIG_DFL);
    struct rlimit cpu = {SPM_MESH_CHILD_CPU_SECONDS, SPM_MESH_CHILD_CPU_SECONDS + 5};
    setrlimit(RLIMIT_CPU, &cpu);
    const char *hook = getenv("SPECMIP_TEST_MESH_CHILD");
    if (hook && !strcmp(hook, "crash")) {
        signal(SIGSEGV, SIG_DFL); /* past a sanitizer's handler */
        raise(SIGSEGV);
    }
    rlim_t as_bytes = SPM_MESH_CHILD_AS_BYTES;
    if (hook && !strncmp(hook, "as=", 3) && strtoul(hook + 3, NULL, 10) > 0)
        as_bytes = (rlim_t)strtoul(hook + 3, NULL, 10) << 20;
#ifndef SPM_ASAN /* ASan reserves terabytes of shadow address space */
    struct rlimit as = {as_bytes, as_bytes};
    setrlimit(RLIMIT_AS, &as);
#endif
    alarm(SPM_MESH_CHILD_WALL_SECONDS);
    prctl(PR_SET_PDEATHSIG, SIGKILL); /* a parent killed outright takes the child along */
    if (getppid() != parent)
        _exit(1);
    while (hook && !strcmp(hook, "hang"))
        pause();
    return as_bytes;
}

/* The records of the file's embedded images: the bytes of each that a map of
 * a used material reads (a compressed image: PNG, JPEG...), size 0 for the
 * others, which are ignored textures unless a material's colour took their
 * mean (texture_name). */
static spm_mesh_image *child_images(const struct aiScene *sc, const spm_mesh_material *mats,
                                    const unsigned char *used, uint32_t *ignored, writer *w)
{
    uint64_t total = 0;
    if (sc->mNumTextures > SPM_MESH_MAX_IMAGES)
        child_fail(w, "more than 4096 embedded images");
    spm_mesh_image *imgs = calloc(sc->mNumTextures + 1, sizeof *imgs);
    if (!imgs)
        child_fail(w, "out of memory");
    for (unsigned i = 0; i < sc->mNumTextures; i++) {
        char name[32];
        snprintf(name, sizeof name, "embedded image %u", i);
        int32_t e = (int32_t)i + 1;
        int read = 0, base = 0;
        for (unsigned j = 0; j < sc->mNumMaterials; j++) {
            const spm_mesh_material *m = &mats[j];
            read |= used[j] && (m->texture_embed == e || m->etexture_embed == e ||
                                m->mr_embed == e || m->nmap_embed == e);
            base |= used[j] && ((m->texture && !strcmp(m->texture_name, name)) ||
                                (m->etexture && !strcmp(m->etexture_name, name)));
        }
        const struct aiTexture *t = sc->mTextures[i];
        if (read && t && t->mHeight == 0) {
            imgs[i].size = t->mWidth;
            imgs[i].data = (const unsigned char *)t->pcData;
            snprintf(imgs[i].hint, sizeof imgs[i].hint, "%.7s",
                     t->achFormatHint[0] ? t->achFormatHint : "png");
            total += t->mWidth;
        }
        if (!read && !base)
            *ignored |= SPM_MESH_IGN_TEXTURES;
    }
    if (total > SPM_MESH_MAX_IMAGE_BYTES)
        child_fail(w, "embedded images of more than 1 GiB");
    return imgs;
}

static void child_main(const spm_file *file, int fd, pid_t parent)
{
    const char *path = file->shown;
    rlim_t as_bytes = child_limits(parent);
    static writer w;
    w.fd = fd;
    struct aiFileIO io = {io_open, io_close, NULL};
    io_model = path;
    /* a glTF's lights from its JSON (KHR_lights_punctual), before Assimp,
     * whose messages on a bad light mislead (an unknown type is "missing its
     * spot parameters"); other formats' lights are ignored */
    spm_mesh_light *lights = NULL;
    int range_set = 0;
    spm_error lerr;
    long nlights = spm_mesh_gltf_lights(file, &lights, &range_set, &lerr);
    if (nlights < 0)
        child_fail(&w, lerr.msg);
    const struct aiScene *sc = aiImportFileEx(file->path, aiProcess_Triangulate, &io);
    if (io_was_refused)
        child_fail(&w, io_refused.msg);
    if (!sc) {
        char msg[700];
        const char *why = aiGetErrorString();
        if (why && why[0])
            snprintf(msg, sizeof msg, "Assimp: %s", why);
        else /* what Assimp says when an allocation fails */
            snprintf(msg, sizeof msg, "the importer failed without saying why (it may have run "
                                      "out of memory: its limit is %llu MiB)",
                     (unsigned long long)(as_bytes >> 20));
        child_fail(&w, msg);
    }
    if (!sc->mRootNode)
        child_fail(&w, "the file has no scene (no root node)");
    walk k = {sc, &w, 0, 0, 0, ends_with_ci(path, ".stl"), NULL};
    if (sc->mNumMaterials > SPM_MESH_MAX_MATERIALS)
        child_fail(&w, "more than 4096 materials");
    k.used = calloc(sc->mNumMaterials + 1, 1);
    if (!k.used)
        child_fail(&w, "out of memory");
    affine id = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    if (walk_node(&k, sc->mRootNode, id, 0)) {
        char msg[128];
        snprintf(msg, sizeof msg, "more than %d triangles (node instances expanded)",
                 SPM_SCENE_MAX_TRIS);
        child_fail(&w, msg);
    }
    if (k.count == 0)
        child_fail(&w, "the file has no triangles");
    spm_mesh_material *mats = calloc(sc->mNumMaterials, sizeof *mats);
    if (!mats)
        child_fail(&w, "out of memory");
    for (unsigned i = 0; i < sc->mNumMaterials; i++) {
        uint32_t ign = 0;
        spm_error refused;
        if (material(sc, file, sc->mMaterials[i], &mats[i], &ign, &refused))
            child_fail(&w, refused.msg);
        if (k.used[i])
            k.ignored |= ign;
    }
    int normals = 0, uvs = 0, tangents = 0; /* STL's facet normals are no vertex normals */
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *m = sc->mMeshes[i];
        normals |= m->mNormals && !k.stl;
        uvs |= m->mTextureCoords[0] != NULL;
        tangents |= has_tangents(m) && !k.stl;
        if (m->mColors[0])
            k.ignored |= SPM_MESH_IGN_COLOURS;
        if (m->mNumBones || m->mNumAnimMeshes)
            k.ignored |= SPM_MESH_IGN_ANIMATION;
    }
    spm_mesh_image *imgs = child_images(sc, mats, k.used, &k.ignored, &w);
    if (sc->mNumCameras)
        k.ignored |= SPM_MESH_IGN_CAMERAS;
    if (sc->mNumLights && !spm_mesh_gltf_is(path))
        k.ignored |= SPM_MESH_IGN_LIGHTS;
    if (range_set)
        k.ignored |= SPM_MESH_IGN_LIGHT_RANGE;
    if (sc->mNumAnimations)
        k.ignored |= SPM_MESH_IGN_ANIMATION;
    uint32_t flags = (normals ? SPM_MESH_WIRE_NORMALS : 0u) | (uvs ? SPM_MESH_WIRE_UVS : 0u) |
                     (tangents ? SPM_MESH_WIRE_TANGENTS : 0u);
    uint32_t h[SPM_MESH_WIRE_HEAD / 4] = {
        0x4d4d5053u, 0, k.ignored, sc->mNumMaterials, 0, 0, flags, (uint32_t)nlights,
        sc->mNumTextures};
    uint64_t n = k.count, nb = 0;
    for (unsigned i = 0; i < sc->mNumTextures; i++)
        nb += imgs[i].size;
    memcpy(&h[4], &n, sizeof n);
    memcpy(&h[10], &nb, sizeof nb);
    w_put(&w, h, sizeof h);
    w_put(&w, mats, sc->mNumMaterials * sizeof *mats);
    k.emit = 1;
    k.count = 0;
    walk_node(&k, sc->mRootNode, id, 0);
    int arrays[3] = {normals, uvs, tangents}; /* emit 2, 3, 4 */
    for (int a = 0; a < 3; a++) /* the same walk again, the same triangles in the same order */
        if (arrays[a]) {
            k.emit = 2 + a;
            k.count = 0;
            walk_node(&k, sc->mRootNode, id, 0);
        }
    w_put(&w, lights, (size_t)nlights * sizeof *lights);
    /* the images' records at a multiple of 8, then their bytes */
    size_t end = sizeof h + sc->mNumMaterials * sizeof *mats +
                 n * (sizeof(spm_mesh_tri) + (normals ? sizeof(spm_mesh_normals) : 0) +
                      (uvs ? sizeof(spm_mesh_uvs) : 0) +
                      (tangents ? sizeof(spm_mesh_tangents) : 0)) +
                 (size_t)nlights * sizeof *lights;
    static const unsigned char zeros[8];
    w_put(&w, zeros, spm_mesh_wire_size(sc->mNumMaterials, n, flags, (uint32_t)nlights, 0, 0) - end);
    w_put(&w, imgs, sc->mNumTextures * sizeof *imgs);
    for (unsigned i = 0; i < sc->mNumTextures; i++)
        w_put(&w, imgs[i].data, imgs[i].size);
    w_flush(&w);
    _exit(w.failed ? 3 : 0);
}

/* ---- the parent ------------------------------------------------------------ */

static int child_error(const char *path, int status, spm_error *err)
{
    if (WIFSIGNALED(status)) {
        int sig = WTERMSIG(status);
        if (sig == SIGXCPU)
            spm_errorf(err, "%s: the importer ran out of CPU time (limit %d s)", path,
                       SPM_MESH_CHILD_CPU_SECONDS);
        else if (sig == SIGALRM)
            spm_errorf(err, "%s: the importer took too long (limit %d s)", path,
                       SPM_MESH_CHILD_WALL_SECONDS);
        else
            spm_errorf(err, "%s: the importer crashed (%s)", path, strsignal(sig));
    } else {
        spm_errorf(err, "%s: the importer failed (exit status %d%s)", path, WEXITSTATUS(status),
                   WEXITSTATUS(status) == 127 ? "" : "; it may have run out of memory");
    }
    return 1;
}

/* The importer's child started on `file`, reading end of its pipe in fds[0];
 * its pid, or -1 with err. */
static pid_t start_child(const spm_file *file, int fds[2], spm_error *err)
{
    if (pipe(fds)) {
        spm_errorf(err, "%s: cannot start the importer: %s", file->shown, strerror(errno));
        return -1;
    }
    fflush(stdout);
    fflush(stderr);
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        spm_errorf(err, "%s: cannot start the importer: %s", file->shown, strerror(errno));
        return -1;
    }
    if (pid == 0) {
        close(fds[0]);
        child_main(file, fds[1], parent);
    }
    close(fds[1]);
    return pid;
}

int spm_mesh_import(const spm_file *file, spm_mesh_data *out, spm_error *err)
{
    memset(out, 0, sizeof *out);
    const char *path = file->shown;
    /* test hook (mesh.h): without the check before the import, the child's own */
    const char *refs = getenv("SPECMIP_TEST_MESH_REFS");
    char unrendered[sizeof out->extensions] = "";
    if (!(refs && !strcmp(refs, "skip")) &&
        spm_mesh_refs_check(file, unrendered, sizeof unrendered, err))
        return 1;
    /* PLY by the project's own reader (mesh_ply.h), but for polygons */
    if (ends_with_ci(path, ".ply")) {
        int rc = spm_ply_read(file, out, err);
        if (rc != SPM_PLY_POLYGONS)
            return rc;
    }
    int fds[2];
    pid_t pid = start_child(file, fds, err);
    if (pid < 0)
        return 1;
    spm_test_pause("mesh");
    /* the header first: it says how much follows, so memory is allocated once */
    unsigned char head[SPM_MESH_WIRE_HEAD];
    size_t have = 0, want = sizeof head, max_err = sizeof head + 1024;
    unsigned char *buf = NULL;
    int rc = 0, eof = 0;
    double t0 = spm_now();
    while (!eof) {
        if (spm_stop_requested()) {
            spm_errorf(err, "interrupted while loading %s", path);
            rc = 2;
            break;
        }
        if (spm_now() - t0 > SPM_MESH_CHILD_WALL_SECONDS + 10) {
            spm_errorf(err, "%s: the importer took too long (limit %d s)", path,
                       SPM_MESH_CHILD_WALL_SECONDS);
            rc = 2;
            break;
        }
        struct pollfd pfd = {fds[0], POLLIN, 0};
        int pr = poll(&pfd, 1, 100);
        if (pr < 0 && errno != EINTR) {
            spm_errorf(err, "%s: waiting for the importer: %s", path, strerror(errno));
            rc = 2;
            break;
        }
        if (pr <= 0)
            continue;
        unsigned char *dst = buf ? buf + have : head + have;
        size_t room = buf ? want - have : sizeof head - have;
        unsigned char sink[256];
        if (room == 0) { /* more than announced: read to see it */
            dst = sink;
            room = sizeof sink;
        }
        ssize_t k = read(fds[0], dst, room);
        if (k < 0 && (errno == EINTR || errno == EAGAIN))
            continue;
        if (k <= 0) {
            eof = 1;
            break;
        }
        if (dst == sink) {
            have = want + 1; /* marks the excess for the decoder's size check */
            continue;
        }
        have += (size_t)k;
        if (!buf && have == sizeof head) {
            uint32_t status, nmats, flags, nlights, nimages;
            uint64_t ntris, image_bytes;
            memcpy(&status, head + 4, 4);
            memcpy(&nmats, head + 12, 4);
            memcpy(&ntris, head + 16, 8);
            memcpy(&flags, head + 24, 4);
            memcpy(&nlights, head + 28, 4);
            memcpy(&nimages, head + 32, 4);
            memcpy(&image_bytes, head + 40, 8);
            size_t size = spm_mesh_wire_size(nmats, ntris, flags, nlights, nimages, image_bytes);
            if (status != 0)
                want = max_err;
            else if (nmats <= SPM_MESH_MAX_MATERIALS && ntris <= SPM_SCENE_MAX_TRIS)
                want = size ? size : sizeof head; /* decode refuses it */
            buf = spm_xmalloc(want > sizeof head ? want : sizeof head);
            memcpy(buf, head, sizeof head);
        }
    }
    close(fds[0]);
    int status = 0;
    if (rc)
        kill(pid, SIGKILL);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (rc) {
        free(buf);
        return 1;
    }
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
        free(buf);
        return child_error(path, status, err);
    }
    if (!buf) {
        spm_errorf(err, "%s: the importer returned no data", path);
        return 1;
    }
    if (spm_mesh_decode(buf, have > want ? want + 1 : have, path, out, err)) {
        free(buf);
        return 1;
    }
    memcpy(out->extensions, unrendered, sizeof unrendered);
    spm_mesh_gltf_materials(file, out);
    return 0;
}
