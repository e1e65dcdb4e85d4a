/* Definitions shared by the host, the CPU reference and the OpenCL kernels.
 * Only constants, plain structs and integer helpers live here: the kernel's
 * and the reference's floating-point arithmetic is each written separately. */
#ifndef SPM_SHARED_H
#define SPM_SHARED_H

#ifdef __OPENCL_VERSION__
typedef uint spm_u32;
typedef int spm_i32;
#define SPM_INLINE inline
#else
#include <stdint.h>
typedef uint32_t spm_u32;
typedef int32_t spm_i32;
#define SPM_INLINE static inline
#endif
/* the address space of the emitter table a shared helper reads (any OpenCL C
 * compiler defines __OPENCL_C_VERSION__; __OPENCL_VERSION__ is the device's) */
#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define SPM_EMIT_TABLE_SPACE __global
#else
#define SPM_EMIT_TABLE_SPACE
#endif

/* ---- spectral domain ---------------------------------------------------- */
#define SPM_LAMBDA_MIN 380
#define SPM_LAMBDA_MAX 780
#define SPM_TRUTH_BINS 400      /* 1 nm bins: ground truth */
#define SPM_NM5_BINS 80         /* 5 nm bins: ref, and the spectral images' default */
/* The mip chain: level 0 is the 1 nm truth, level 1 the 5 nm bins, and each
 * coarser level averages pairs: 400, 80, 40, 20, 10 bins, read by the shade
 * kernels as 25 x float16, then five vectors of 16, 8, 4, 2 floats. */
#define SPM_NUM_LEVELS 5
#define SPM_LEVEL_BINS(l) ((l) ? SPM_NM5_BINS >> ((l) - 1) : SPM_TRUTH_BINS)
#define SPM_LEVEL_WIDTH(l) ((l) <= 1 ? 16 : 32 >> (l))
#define SPM_REF_LEVEL 1         /* ref's level: every spectrum at 5 nm */
#define SPM_DEFAULT_COARSEST 3  /* the pretest's coarsest level unless told: 20 bins */
#define SPM_MAX_SPIKES 16       /* Composite Model: spike lanes per scene */
#define SPM_HERO_LANES 4
/* hero's wavelength density: pbrt-v4's visible importance a / cosh^2(a (l - c))
 * truncated to 380-780 nm (host/spectral/tables.c derives its inverse). */
#define SPM_HERO_CENTER 538.0f  /* nm */
#define SPM_HERO_A 0.0072f      /* per nm */
/* hero's table, one array: t0 = tanh(a (380 - c)), dt = tanh(a (780 - c)) - t0,
 * the density's factor a / dt; the tanh of each 1 nm bin edge (401 values:
 * bin j holds edge[j] <= y < edge[j + 1]); a direct index of the bins, one
 * per SPM_HERO_CELLS-th of the sample space (no later than the bin of the
 * cell's start, as a float); then truth's XYZ weights of each 1 nm bin as
 * (x, y, z, 0). */
#define SPM_HERO_CELLS 4096
#define SPM_HERO_T0 0
#define SPM_HERO_DT 1
#define SPM_HERO_PDFK 2
#define SPM_HERO_EDGE 4
#define SPM_HERO_INDEX (SPM_HERO_EDGE + SPM_TRUTH_BINS + 4)
#define SPM_HERO_CMF (SPM_HERO_INDEX + SPM_HERO_CELLS)
#define SPM_HERO_FLOATS (SPM_HERO_CMF + 4 * SPM_TRUTH_BINS)
/* mlc tables hold, per colour and level, the smooth bins then the spike lanes */
#define SPM_MLC_STRIDE(l) (SPM_LEVEL_BINS(l) + SPM_MAX_SPIKES)

/* ---- path records ------------------------------------------------------- */
#define SPM_MAX_DEPTH 64        /* vertices per path record (same in both backends) */
#define SPM_NONE 0xFFFFu        /* "no colour" in a 16-bit colour id */
#define SPM_NO_PIXEL 0xFFFFFFFFu /* "no splat" in a 32-bit pixel word (pixel 65535 is one) */
/* Pretest context B: k = 1..KMAX occurrences of a colour on one path. A path
 * meets at most SPM_MAX_DEPTH reflections, so the level feeler has a level for
 * every count it can see (a table that stopped short would give long chains
 * the level of a shorter one, whose error they exceed). */
#define SPM_PRETEST_KMAX SPM_MAX_DEPTH

/* How a path ended. */
#define SPM_END_ABSORBED 0u     /* Russian roulette ended it */
#define SPM_END_ESCAPED 1u      /* a ray left the scene (background term recorded) */
#define SPM_END_TRUNCATED 2u    /* SPM_MAX_DEPTH reached: counted in --stats */

/* One path vertex. ids: low 16 bits the reflectance colour at the vertex,
 * high 16 bits the emission colour of the sampled emitter (SPM_NONE when the
 * emitter was occluded, back-facing or absent). c is the emitter term's scalar
 * weight, with every level-independent factor folded in:
 *   (1 / pdf of the emitter triangle, spm_emitter) * cos_e * area / max(d^2, SPM_D2_MIN_REL * area) * |cos_i| / pi
 *   * prod over earlier vertices of 1 / mean reflectance (Russian roulette). */
typedef struct {
    spm_u32 ids;
    float c;
} spm_vertex;

/* A path's colour-independent record. Shading a path at any level is
 *   P = 1; L = first_emit_c * E[first_emit];
 *   for each vertex: P *= R[refl]; if emit != NONE: L += P * E[emit] * c;
 *   if bg != NONE: L += P * E[bg] * bg_c;
 * so every mode shades exactly the same geometry. */
typedef struct {
    spm_u32 nvert;       /* number of recorded vertices (0: camera ray escaped) */
    spm_u32 end;         /* SPM_END_* */
    spm_u32 first_emit;  /* emission colour seen at the first hit (front face) or SPM_NONE */
    float first_emit_c;  /* its weight (1 when present) */
    spm_u32 bg;          /* background colour seen by the escaping ray, or SPM_NONE */
    float bg_c;          /* its weight (product of 1/mean reflectance so far) */
    spm_u32 pad0, pad1;
} spm_path_head;

/* A vertex's spectral factor: a kind and a few words, for the scenes whose
 * types declare words (host/scene/materials.c vertex_u32; 4 words). The
 * kinds are SPM_FACTOR_KINDS below; each kind's rule, what it does to the
 * path weight P and the radiance L at every lane, is written once per
 * backend in the file of the type that records it (kernels/<type>.clh's
 * shade half, host/cpu/refcpu_<type>.c) and applied through one
 * vertex_apply (kernels/factors.clh, host/cpu/refcpu_factors.c). Fields:
 *   ids    bits 0-13  the kind's colour word: 1 + a colour id or a 1 nm bin
 *                     (0: none)
 *          bits 14-15 the kind (SPM_FK_*)
 *          bits 16-31 1 + the emission colour the vertex's sampled ray hit
 *                     (0: none, or not counted)
 *   lobe   the kind's argument for the sampled ray
 *   light  the kind's argument for the light sample (or a second word)
 *   hit_c  the scalar weight of the emission hit (its MIS weight and the
 *          throughput so far folded in)
 * so that a zero record (a Lambertian vertex of such a scene) is the plain
 * kind with no hit. Every kind shades the hit the same way, after its own
 * factor: L += P E[hit] hit_c. The spm_vertex's colour r and light-sample
 * emission e (weight c) are the kind's too. */
typedef struct {
    spm_u32 ids;
    float lobe;
    float light;
    float hit_c;
} spm_vertex_ext;

/* The factor kinds, X(NAME, STORED, ...): STORED 1 when the kind is written
 * in a record's bits 14-15 (at most 4 such), 0 when a vertex's colour says
 * it (no record needed). The rest of the arguments are the expander's.
 *   PLAIN    the vertex's colour R (a Lambertian's, a coated lobe's):
 *            P *= R; L += P E[e] c
 *   FRESNEL  a conductor (kernels/conductor.clh): r its eta colour, the
 *            colour word its k colour, lobe wo.m and light wo.h, F of
 *            eta + i k per lane: L += P F(light) E[e] c; P *= F(lobe)
 *   ABSORB   a dielectric (kernels/dielectric.clh): r its absorption sigma
 *            (per scene unit), lobe the length d of the sampled ray's
 *            segment inside (0: outside): L += P E[e] c; P *= exp(-sigma d);
 *            at a path's first dispersive vertex the colour word holds 1 + the
 *            1 nm bin b the path committed to and light 1 / pdf of b: the
 *            path is shaded as one lane, bin b, in every mode
 *            (docs/METHODS.md "Dispersion")
 *   REEMIT   a fluorescent vertex (kernels/fluor.clh): a colour from
 *            SPM_FLUOR_FIRST on names the pair of its diagonal R and its
 *            re-radiation block; such a path is walked from the light end,
 *            A = M (E[e] c + A). A fluorescent scene's record is a
 *            Lambertian's (no words).
 * Room for what comes next: a stored kind whose words do not fit (a texture
 * reference with its coordinates and footprint, an environment direction, a
 * medium segment with its own colour) declares more words in its type's
 * vertex_u32 and widens the record of the scenes that use it only. */
#define SPM_FACTOR_KINDS(X, ...)    \
    X(PLAIN, 1, __VA_ARGS__)        \
    X(FRESNEL, 1, __VA_ARGS__)      \
    X(ABSORB, 1, __VA_ARGS__)       \
    X(REEMIT, 0, __VA_ARGS__)
/* SPM_IF(c)(x): x when the condition c expands to 1, nothing at 0 (the
 * generated switches keep the cases of what a program is built for) */
#define SPM_IF_0(...)
#define SPM_IF_1(...) __VA_ARGS__
#define SPM_IF_(c) SPM_IF_##c
#define SPM_IF(c) SPM_IF_(c)
#define SPM_FK_ENUM_(NAME, STORED, ...) SPM_FK_##NAME,
enum spm_factor_kind { SPM_FACTOR_KINDS(SPM_FK_ENUM_, 0) SPM_FK_NKINDS };
#undef SPM_FK_ENUM_
#define SPM_VX_COLBITS 14
#define SPM_VX_COLMASK ((1u << SPM_VX_COLBITS) - 1u)
/* a record's kind, its colour word (SPM_NONE: none), its hit (SPM_NONE: none) */
#define SPM_VX_KIND(x) (((x).ids >> SPM_VX_COLBITS) & 3u)
#define SPM_VX_COL(x) ((((x).ids & SPM_VX_COLMASK) + 0xFFFFu) & 0xFFFFu)
#define SPM_VX_HIT(x) ((((x).ids >> 16) + 0xFFFFu) & 0xFFFFu)
/* the ids of a record of kind k and colour word col (SPM_NONE: none), no hit */
#define SPM_VX_IDS(k, col) ((((col) + 1u) & SPM_VX_COLMASK) | (spm_u32)(k) << SPM_VX_COLBITS)
/* the hit's bits: 1 + colour hit */
#define SPM_VX_HIT_BITS(hit) ((((hit) + 1u) & 0xFFFFu) << 16)
/* the 1 nm bin a record committed its path to (SPM_NONE: none) */
#define SPM_VX_LAMBDA(x) (SPM_VX_KIND(x) == SPM_FK_ABSORB ? SPM_VX_COL(x) : SPM_NONE)
/* colour ids of scenes with records stay below this (host/spectral/tables.c) */
#define SPM_VX_MAX_COLOURS (SPM_VX_COLMASK - 1u)

/* The host's record of a path: x[] is written only in scenes whose types
 * declare vertex words (zero otherwise). */
typedef struct {
    spm_path_head h;
    spm_vertex v[SPM_MAX_DEPTH];
    spm_vertex_ext x[SPM_MAX_DEPTH];
} spm_path;

/* ---- path records on the device (OpenCL backend) --------------------------
 * The same records, laid out for the device as structure of arrays,
 * vertex-major. For a pass of n paths, path i is
 *   heads[i]          spm_dev_head (16 bytes: four headers per cache line)
 *   verts[j * n + i]  its vertex j, for j < nvert
 * so work-items i, i+1, ... read neighbouring memory, and a path costs memory
 * traffic in proportion to its own length: an spm_path is 544 bytes however
 * short the path (default-scene paths average 1.6 vertices), and read that way
 * ~60% of the shade stage was waiting for memory. The vertex buffer has room
 * for SPM_MAX_DEPTH slabs of n vertices; slab j is touched only if some path
 * of the pass reaches depth j. The host converts from and to spm_path arrays
 * (render_cl.h's test hooks) with the two helpers below, losslessly: colour
 * ids fit 16 bits (spm_vertex packs them so too) and nvert <= SPM_MAX_DEPTH.
 * A scene whose types declare vertex words (spm_vertex_ext) has, after the
 * SPM_MAX_DEPTH spm_vertex slabs, SPM_MAX_DEPTH slabs of spm_vertex_ext laid
 * out the same way, in the same buffer (SPM_VERTEX_EXT below); other scenes
 * have none, and their buffer is what it always was. */
#define SPM_VERTEX_EXT(verts, n) ((verts) + (size_t)SPM_MAX_DEPTH * (n))
typedef struct {
    spm_u32 colours;   /* first_emit (low 16 bits) | bg << 16 */
    spm_u32 nvert_end; /* nvert (low 16 bits) | end << 16 */
    float first_emit_c;
    float bg_c;
} spm_dev_head;

SPM_INLINE spm_dev_head spm_dev_head_pack(const spm_path_head *h)
{
    spm_dev_head d;
    d.colours = (h->first_emit & 0xFFFFu) | (h->bg << 16);
    d.nvert_end = (h->nvert & 0xFFFFu) | (h->end << 16);
    d.first_emit_c = h->first_emit_c;
    d.bg_c = h->bg_c;
    return d;
}

SPM_INLINE spm_path_head spm_dev_head_unpack(const spm_dev_head *d)
{
    spm_path_head h;
    h.nvert = d->nvert_end & 0xFFFFu;
    h.end = d->nvert_end >> 16;
    h.first_emit = d->colours & 0xFFFFu;
    h.first_emit_c = d->first_emit_c;
    h.bg = d->colours >> 16;
    h.bg_c = d->bg_c;
    h.pad0 = 0;
    h.pad1 = 0;
    return h;
}

/* Per-path level byte written by the trace stage (the level feeler):
 * bits 0-2 the finest level the path's colours need, bits 4-5 what set it. */
#define SPM_LEVEL_MASK 0x07u
#define SPM_SETBY_SHIFT 4
#define SPM_SETBY_NONE 0u       /* path met no colour finer than the coarsest */
#define SPM_SETBY_EMITTER 1u    /* an emission (light or background) set it */
#define SPM_SETBY_REFLECTOR 2u  /* a reflectance set it */

/* ---- geometry ------------------------------------------------------------ */
/* Triangle: its three vertices as the scene gave them, then MiniLight's
 * shading data: unit normal normalise((v1 - v0) x (v2 - v0)), unit tangent
 * normalise(v1 - v0), area; vn says whether it shades smooth: 0 flat (every
 * triangle of a scene without vertex normals), k > 0 its three unit vertex
 * normals (n0, n1, n2, oriented to the front face's side) are the nine
 * floats at 9 (k - 1) of the scene's vertex-normal array (spm_geometry
 * vnormals; the trace stage's vnormals buffer, only in scenes that have them,
 * whose kernels are built with SPM_WITH_SMOOTH). The watertight test reads the vertices only, and
 * needs them bit for bit: a neighbour's shared vertex must be the same floats
 * (v0 + (v1 - v0) is not v1). Each vertex starts a row of four floats (the
 * rows' fourth floats hold the area and the material), so what the test reads
 * is the first 48 bytes, a vertex per 16-byte row. 72 bytes a triangle, as
 * v0/e1/e2 with their shading data were. */
typedef struct {
    float v0[3];
    float area;
    float v1[3];
    spm_u32 material;
    float v2[3];
    spm_u32 vn;
    float n[3];
    float t[3];
} spm_tri;

/* The BVH is at most this many levels deep (the builder refuses deeper), so a
 * traversal stack of this many entries suffices, in the kernel and on the host. */
#define SPM_BVH_STACK 64

/* Flattened BVH node. count > 0: leaf holding triangles [first, first+count)
 * of the (reordered) triangle array. count == 0: interior node whose children
 * are nodes `first` and `first + 1`. Node 0 is the root. */
typedef struct {
    float bmin[3];
    spm_u32 first;
    float bmax[3];
    spm_u32 count;
} spm_bvh_node;

/* The kernels' BVH: 4-wide nodes collapsed from the BVH2 above
 * (host/geometry/bvh_wide.c), the children's boxes as slabs of four floats
 * (structure of arrays) so one work-item tests all four with float4
 * arithmetic. child[i] is an interior node's slot (< 2^31), or a leaf,
 * SPM_WIDE_LEAF | first << 2 | (count - 1): triangles [first, first + count)
 * of the reordered triangle array, count <= 4 (a BVH2 subtree of up to four
 * triangles), or SPM_WIDE_EMPTY for an unused slot (its box is never read).
 * Slot 0 is the root; the slots from 1 on hold the leaves' triangle planes
 * (SPM_LEAF_PLANES), the other nodes follow them. 112 bytes a slot. */
#define SPM_WIDE 4
#define SPM_WIDE_LEAF 0x80000000u
#define SPM_WIDE_EMPTY 0xFFFFFFFFu
#define SPM_WIDE_MAX_TRIS 0x1FFFFFFF /* a leaf's first triangle fits in 29 bits */
/* The traversal stack: a node pushes at most SPM_WIDE - 1 entries more than it
 * pops, and the wide tree is no deeper than the BVH2 (SPM_BVH_STACK). */
#define SPM_WIDE_STACK ((SPM_WIDE - 1) * SPM_BVH_STACK + 1)
typedef struct {
    float bmin_x[SPM_WIDE], bmax_x[SPM_WIDE];
    float bmin_y[SPM_WIDE], bmax_y[SPM_WIDE];
    float bmin_z[SPM_WIDE], bmax_z[SPM_WIDE];
    spm_u32 child[SPM_WIDE];
} spm_bvh4_node;

/* SPM_LEAF_PLANES: the vertices of every leaf's triangles as nine planes
 * (3 * vertex + axis, vertex 0..2, axis x, y, z) of count floats each,
 * lane l for triangle first + l, from float 9 * first of the planes (the
 * floats from slot 1 on): a leaf is 36 * count contiguous bytes and one
 * unaligned four-float load per plane gives the four-lane test its lanes
 * (those past count read the next plane, and are masked). Three floats of
 * padding after the last leaf keep those loads in the buffer. Leaves of at
 * most SPM_LEAF_SCALAR triangles are tested one triangle at a time: with
 * fewer lanes in use the scalar test takes fewer instructions. */
#define SPM_LEAF_PLANES_FLOATS(ntris) (9 * (ntris) + 3)
#define SPM_LEAF_SCALAR 2

/* Material and emitter types: their tags SPM_MAT_NAME, SPM_EMIT_NAME, one
 * per entry of spm_types.h in its order (the same entries are the
 * descriptors, host/scene/materials.c: scene keyword and clauses, colours,
 * record fields, random-number dimensions, the kernel define that compiles
 * its code in). Each backend dispatches on the tag once per stage (a switch:
 * trace.cl's vertex_lobe / vertex_emission, refcpu_trace.c's likewise). */
#define SPM_MATERIAL_TYPE(name, ...) SPM_MAT_##name,
#define SPM_EMITTER_TYPE(name, ...)
enum spm_material_tag {
#include "spm_types.h"
    SPM_MAT_NTYPES
};
#undef SPM_MATERIAL_TYPE
#undef SPM_EMITTER_TYPE
#define SPM_MATERIAL_TYPE(name, ...)
#define SPM_EMITTER_TYPE(name, ...) SPM_EMIT_##name,
enum spm_emitter_tag {
#include "spm_types.h"
    SPM_EMIT_NTYPES
};
#undef SPM_MATERIAL_TYPE
#undef SPM_EMITTER_TYPE
#define SPM_MAT_TYPES 8u        /* tags below this (materials.c checks) */
#define SPM_EMIT_TYPES 8u
#define SPM_MAT_PARAMS 4        /* a type's own floats per material */
#define SPM_EMIT_PARAMS 1       /* its emitter type's own floats */
/* the conductor's p[]: its GGX width alpha (0: the smooth lobe; host widths
 * below SPM_COND_MIN_ALPHA become 0: a narrower GGX lobe's D overflows float) */
#define SPM_COND_P_ALPHA 0
#define SPM_COND_MIN_ALPHA 1e-3
/* the dielectric's p[]: its index of refraction (inside over outside, the
 * front face's side being outside) and GGX width (0: smooth; below
 * SPM_COND_MIN_ALPHA, 0 as the conductor's) */
#define SPM_DIEL_P_IOR 0
#define SPM_DIEL_P_ALPHA 1
/* (the scene material's only, for the pretest: the longest segment inside) */
#define SPM_DIEL_P_LEN 2
/* 1 + the material's row of the index table (spm_geometry disp: n at the
 * centre of each 1 nm bin), 0 for one index; a dispersive material's
 * SPM_DIEL_P_IOR holds n at the d-line (SPM_DISP_REF_NM), which a mode whose
 * lanes are no wavelengths (rgb) traces with */
#define SPM_DIEL_P_DISP 3
#define SPM_DISP_REF_NM 587.5618 /* helium d-line: the catalogues' n_d */
/* the coated type's p[] (host/scene/materials.c coated_fill): the coating's
 * GGX width (0: smooth; below SPM_COND_MIN_ALPHA smooth), its index of
 * refraction eta, the diffuse lobe's scalar factor 1 / (eta^2 (1 - Fdr_i))
 * and the specular lobe's sampling weight (kernels/coated.clh) */
#define SPM_COAT_P_ALPHA 0
#define SPM_COAT_P_ETA 1
#define SPM_COAT_P_KD 2
#define SPM_COAT_P_SPEC 3

/* Material as the device sees it: colour ids into the spectral tables, the
 * type tags and each type's parameters (its descriptor's `fill` sets them). */
typedef struct {
    spm_u32 refl;      /* reflectance colour id (SPM_NONE: black) */
    spm_u32 emit;      /* emission colour id (SPM_NONE: not an emitter) */
    float mean;        /* mean reflectance (the same at every level): Russian roulette survival */
    float inv_mean;    /* 1 / mean (0 when mean == 0) */
    spm_u32 type;      /* material tag (low 16 bits) | emitter tag << 16 */
    spm_u32 col2;      /* a type's second colour id (SPM_NONE: none) */
    float p[SPM_MAT_PARAMS]; /* a type's parameters (0 when unused) */
    float ep[SPM_EMIT_PARAMS]; /* its emitter type's parameters (0 when unused) */
} spm_material;
#define SPM_MAT_TAG(m) ((m).type & 0xFFFFu)
#define SPM_EMIT_TAG(m) (((m).type >> 16) & 0x7FFFu)
/* in type: the emitter emits from both faces ('twosided', host/scene/materials.c) */
#define SPM_EMIT_TWOSIDED 0x80000000u

/* The camera, resolved on the host (host/geometry spm_camera_of_scene; its
 * rays and importance: kernels/camera.clh, host/cpu/refcpu_camera.c).
 * Pixel (x, y), y = 0 at the top, has film coordinates cx = 2 (x + u) / w - 1,
 * cy = 1 - 2 (y + v) / h and the point s = tan_half (right cx + up cy h/w).
 * Perspective: the ray from eye along normalise(dir + s); a thin lens
 * (lens_radius > 0) moves its origin to a point of the lens disk and aims it
 * at the same point of the plane in focus, eye + focus (dir + s).
 * Orthographic: the ray from eye + s along dir (tan_half is then half the
 * view's width in scene units). */
typedef struct {
    float eye[3];
    float dir[3];
    float right[3];
    float up[3];
    float tan_half;
    spm_i32 width;
    spm_i32 height;
    spm_u32 ortho;       /* 1: orthographic */
    float lens_radius;   /* 0: a pinhole */
    float focus;         /* distance along dir of the plane in focus (lens_radius > 0) */
    spm_u32 pad0, pad1;
} spm_camera;

/* Scene-wide constants the trace stage needs besides its buffers. */
typedef struct {
    spm_camera cam;
    spm_u32 ntris;
    spm_u32 nemitters;
    spm_u32 bg_up;     /* background colour for an upward escaping ray, or SPM_NONE */
    spm_u32 bg_down;   /* for a downward one (MiniLight: sky x ground), or SPM_NONE */
    spm_u32 seed;
    spm_u32 spp_per_pass;  /* samples per pixel in one pass */
    spm_u32 first_sample;  /* sample index of this pass's first sample */
    spm_u32 emit_power;    /* 1: emitters picked by power (spm_emitter cdf); 0: uniformly */
    spm_u32 disperse;      /* 1: a path commits to a wavelength at its first dispersive
                              vertex (SPM_VX_LAMBDA); 0: dispersive glass takes n_d */
    spm_u32 light_tree;    /* 1: next-event estimation picks through the light tree
                              (spm_light_tree.h) after light_pdf's ntris words */
} spm_trace_params;

/* The environment map's buffer (spm_geometry env, the trace stage's envmap),
 * floats for a map of w x h texels, rows top (+y) to bottom: the marginal
 * cdf over the rows (h + 1), each row's conditional cdf (w + 1 a row), each
 * texel's density in (u, v) of the 2-D distribution, its luminance (the map's
 * scale in), its colour's base node on the palette grid (a uint's bits;
 * SPM_NONE: black) and its fractions toward the next nodes (two 16-bit
 * fixed-point numbers, a: low, b: high); then the nodes: the grid's stride
 * along a (a uint) and n nodes of two each, a scene colour id (a uint's
 * bits; SPM_NONE: unused) and the luminance of the node's RGB shape
 * (host/scene/envmap.h, kernels/light_envmap.clh env_node). 20 bytes a texel. */
#define SPM_ENV_COND(w, h) ((h) + 1u)
#define SPM_ENV_PDF(w, h) (SPM_ENV_COND(w, h) + (h) * ((w) + 1u))
#define SPM_ENV_LUM(w, h) (SPM_ENV_PDF(w, h) + (w) * (h))
#define SPM_ENV_NODE(w, h) (SPM_ENV_LUM(w, h) + (w) * (h))
#define SPM_ENV_FRAC(w, h) (SPM_ENV_NODE(w, h) + (w) * (h))
#define SPM_ENV_NODES(w, h) (SPM_ENV_FRAC(w, h) + (w) * (h))
#define SPM_ENV_FLOATS(w, h, n) (SPM_ENV_NODES(w, h) + 1u + 2u * (n))

/* The light kinds (include/spm_lights.h): their tags SPM_LIGHT_NAME, one
 * per entry in its order. */
#define SPM_LIGHT_KIND(name, ...) SPM_LIGHT_##name,
enum spm_light_kind {
#include "spm_lights.h"
    SPM_LIGHT_NKINDS
};
#undef SPM_LIGHT_KIND
/* A light's own parameters (spm_emitter.p), by slot: where it is, where it
 * points, three numbers of its kind, the factor its colour's spectrum takes
 * (a point light's intensity per unit of the spectrum, ...), and a fourth. */
#define SPM_LIGHT_PARAMS 11
#define SPM_LIGHT_P_POS 0
#define SPM_LIGHT_P_DIR 3
#define SPM_LIGHT_P_A 6
#define SPM_LIGHT_P_B 7
#define SPM_LIGHT_P_SCALE 8
#define SPM_LIGHT_P_C 9
#define SPM_LIGHT_P_D 10
/* A spot light's falloff between its beam angle b and cone angle c
 * (p[SPM_LIGHT_P_D]), as each peer writes it: linear in the angle (Mitsuba
 * 3's `spot`), a smoothstep in the cosine (pbrt-v4's), the square of a ramp
 * linear in the cosine (glTF KHR_lights_punctual's reference form). */
#define SPM_SPOT_LINEAR 0
#define SPM_SPOT_SMOOTHSTEP 1
#define SPM_SPOT_SQUARED 2

/* Light selection (next-event estimation). Light i of the emitter list (an
 * emitter triangle, or a light of another kind: spm_emitter.kind) is picked
 * in proportion to its power, for a triangle area * Y of its emission (the
 * CIE 1931 Y of the emission spectrum, scale included, over the truth bins;
 * another kind's radiant power is counted in the same unit, Y / pi),
 * through a cumulative table in whole counts of 2^-24: emitter i owns the
 * integers [cdf, next emitter's cdf) of the 24-bit draw U = spm_rng_u32(..,
 * SPM_DIM_EMITTER) >> 8 (the bits spm_rng turns into its float), found by
 * binary search. Every emitter owns at least one count, so the pdf the
 * estimator divides by, count / 2^24, is exactly the probability of the pick
 * (no emitter is left unreachable by rounding). When every emitter has the
 * same power (within SPM_EMIT_EQUAL_REL) the pick is MiniLight's uniform one,
 * k = (uint)(spm_rng * n), inv_pdf = n, as before (emit_power = 0), so such
 * scenes keep their images bit for bit. */
#define SPM_EMIT_CDF_BITS 24
#define SPM_EMIT_CDF_ONE (1u << SPM_EMIT_CDF_BITS)
/* Relative spread of power below which emitters count as equal: the two
 * triangles of a quad differ in area by a few float ulps (1e-7 each). */
#define SPM_EMIT_EQUAL_REL 1e-5
typedef struct {
    spm_u32 tri;       /* an area light's triangle (SPM_NONE: a light of another kind) */
    spm_u32 cdf;       /* first count of the 24-bit draw it owns */
    float pdf;         /* probability of picking it (count / 2^24, or 1 / n uniformly) */
    float inv_pdf;     /* 1 / pdf: the light sample's factor */
    spm_u32 kind;      /* SPM_LIGHT_* */
    spm_u32 colour;    /* a light not of a triangle: its emission's colour id */
    float p[SPM_LIGHT_PARAMS]; /* its kind's parameters (SPM_LIGHT_P_*) */
} spm_emitter;

/* The emitter a 24-bit draw u24 picks from the table em[0, n) (cdf ascending,
 * em[0].cdf == 0): the last entry whose cdf <= u24. Integer-only, so both
 * backends pick the same triangle. */
SPM_INLINE spm_u32 spm_emitter_search(const SPM_EMIT_TABLE_SPACE spm_emitter *em, spm_u32 n,
                                      spm_u32 u24)
{
    spm_u32 lo = 0, hi = n; /* em[lo].cdf <= u24 < em[hi].cdf (em[n].cdf taken as 2^24) */
    while (hi - lo > 1u) {
        spm_u32 mid = lo + (hi - lo) / 2u;
        if (em[mid].cdf <= u24)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* A ray replayed by `specmip bench --rays` (kernels/rays.cl, host/bench/bench_rays.c):
 * one of the rays a render's paths trace, with what the traversal is asked.
 * emitter == SPM_RAY_CLOSEST: the closest hit other than `skip` (a camera or
 * bounce ray); otherwise a shadow ray towards a point on emitter triangle
 * `emitter`, asking whether the closest hit other than `skip` is that
 * emitter or nothing (trace.cl's shadow test). */
typedef struct {
    float o[3];
    spm_u32 skip;      /* the triangle the ray leaves; 0xFFFFFFFF: none (a camera ray) */
    float d[3];
    spm_u32 emitter;
} spm_ray;
#define SPM_RAY_CLOSEST 0xFFFFFFFFu

/* Division by a divisor d fixed for a launch, as a multiply and two shifts
 * (Granlund & Montgomery 1994, fig. 4.1): exact for every 32-bit n and d >= 1.
 * The host makes it (spm_divisor_make); the shade kernels divide a path's
 * index by spp with it, 16 paths at a time (x86 has no vector division). */
typedef struct {
    spm_u32 d;
    spm_u32 mul;       /* floor(2^32 (2^l - d) / d) + 1, l = ceil(log2 d) */
    spm_u32 sh1, sh2;  /* min(l, 1), max(l - 1, 0) */
} spm_divisor;
/* n / d from t1 = the high 32 bits of n * mul (any integer vector type) */
#define SPM_DIVISOR_QUOTIENT(n, t1, dv) (((t1) + (((n) - (t1)) >> (dv).sh1)) >> (dv).sh2)

#ifndef __OPENCL_VERSION__
SPM_INLINE spm_divisor spm_divisor_make(spm_u32 d)
{
    spm_u32 l = 0;
    while (l < 32 && ((uint64_t)1 << l) < d)
        l++;
    spm_divisor v = {d, (spm_u32)((((uint64_t)1 << l) - d) * ((uint64_t)1 << 32) / d + 1),
                     l < 1 ? l : 1, l > 1 ? l - 1 : 0};
    return v;
}

SPM_INLINE spm_u32 spm_divisor_div(spm_u32 n, spm_divisor dv)
{
    spm_u32 t1 = (spm_u32)(((uint64_t)n * dv.mul) >> 32);
    return SPM_DIVISOR_QUOTIENT(n, t1, dv);
}
#endif

/* Next-event estimation divides the emitter's area by the squared distance
 * to the sampled point; MiniLight clamps that distance^2 below at 1e-6 (m^2),
 * an absolute bound. Relative to the emitter triangle's own area it is the
 * same for a scene in any unit: the factor area / d^2 is at most 1e6, reached
 * within a thousandth of the triangle's size of the point. */
#define SPM_D2_MIN_REL 1e-6f

/* A ray leaving a surface starts off it (host/geometry/bvh.c spm_ray_spawn,
 * kernels/traverse.clh ray_spawn): at least 2 e inside every edge of the
 * triangle it leaves and e off its plane on the ray's side, e this many
 * FLT_EPSILON of the triangle's largest |coordinate| (the rounding of a hit
 * point and of a neighbour's plane is a few; docs/ARCHITECTURE.md "Rays
 * leaving a surface"). Relative to the coordinates: the same in any unit. */
#define SPM_SPAWN_ULPS 16.0f
#define SPM_PI_F 3.14159265358979323846f

/* Image textures on a reflectance (kernels/texture.clh, host/cpu/refcpu_texture.c,
 * host/geometry/geometry_texture.c; docs/METHODS.md "Textures"). A textured
 * vertex records a colour of the scene, as any vertex does: the trace stage
 * picks one texel of the trilinear filter's eight at random in proportion to
 * its weight (stochastic texture filtering, Pharr et al. 2024), and one
 * corner of the colour grid's cell around the texel's linear RGB in
 * proportion to its trilinear weight; each corner is a scene colour, lifted
 * once. The expected colour is the filtered one, every mode and level shades
 * the texture from its colours' rows, and the record does not grow.
 * The grid's nodes: SPM_TEX_GRID per axis, linear values of the sRGB codes
 * 255 k / (SPM_TEX_GRID - 1) (8-bit colours that are nodes are met exactly).
 * The scene's texture words (one uint buffer; floats as their bits):
 *   [SPM_TEXD_MATS]    offset of a word per material: 1 + its texture (0 none)
 *                      in the low 16 bits, its palette in the high ones
 *   [SPM_TEXD_PALETTE] offset of the palettes, SPM_TEX_GRID^3 colour ids each,
 *                      node (r, g, b) at (r G + g) G + b (SPM_NONE: no texel
 *                      uses it); the first the lifted colours, the others
 *                      colours a type derives from them (the coated base's)
 *   [SPM_TEXD_NODES]   offset of the SPM_TEX_GRID node values (floats)
 *   [SPM_TEXD_TEXS]    offset of a word per texture: its header's offset
 *   [SPM_TEXD_NPAL]    the number of palettes
 *   [SPM_TEXD_MIX]     offset of a word per material: its metallic-roughness
 *                      record's offset, 0 none (SPM_MIX_* below); 0: no material has one
 *   [SPM_TEXD_ALPHA]   offset of a word per material: its opacity record's
 *                      offset, 0 opaque (SPM_ALPHA_* below); 0: no material has one
 *   [SPM_TEXD_SURVIVE] offset of a float per palette entry: its colour's mean
 *                      over the largest mean of its palette, r in
 *                      [SPM_TEX_SURVIVE_MIN, 1]; Russian roulette at a
 *                      textured vertex survives with P r and weighs 1 / (P r)
 *                      (unbiased for any r > 0; P alone is the palette's
 *                      brightest colour's)
 *   [SPM_TEXD_EMIT]    offset of two words per material: 1 + the texture on its
 *                      emission (0 none) in the low 16 bits, its palette (of
 *                      emission spectra) in the high ones; the factor its
 *                      radiance takes (float bits); 0: no material has one
 *   [SPM_TEXD_NMAP]    offset of a word per material: its normal map record's
 *                      offset, 0 none (SPM_NMAP_* below); 0: no material has one
 *   [SPM_TEXD_TANGENT] offset of 12 floats per triangle (in the triangles'
 *                      order): a tangent and its handedness at each vertex
 * a header: nlevels, wrap along u, wrap along v (spm_wrap), its transform's
 * offset (SPM_TEX_UVX), then per level its texels' offset, width, height, 0;
 * texels 3 floats (linear RGB), rows top to bottom. Texture coordinates: 6 floats per triangle (u, v at each vertex),
 * in the triangles' order, only in scenes with textures. */
#define SPM_TEX_GRID 16
/* A map's texture coordinate transform (glTF KHR_texture_transform; each
 * binding of an image its own): the word SPM_TEX_UVX of a texture's header
 * (and SPM_ALPHA_UVX, SPM_NMAP_UVX of the one-byte and normal maps' heads)
 * is the offset of six floats m, 0 for none; the lookup reads the map at
 *   u' = m0 u + m1 v + m2,  v' = m3 u + m4 v + m5
 * and a colour texture's footprint grows by sqrt |m0 m4 - m1 m3| (the
 * area the transform scales uv by; the ray cone's width is isotropic). */
#define SPM_TEX_UVX 3
/* The least survival ratio: a path on the darkest texel survives at least a
 * quarter as often as on the brightest. Where the continuation carries the
 * light (a sky that next-event estimation does not sample), the texel's own
 * ratio (0.008 on a near-black texel) leaves too few paths: on
 * tests/cli_texture_quad.sh's quad the worst block is 1.2-1.3 ΔE00 off at
 * 512 spp with it, 0.6-1.0 with a quarter (docs/METHODS.md "Textures"). */
#define SPM_TEX_SURVIVE_MIN 0.25
#define SPM_TEXD_MATS 0
#define SPM_TEXD_PALETTE 1
#define SPM_TEXD_NODES 2
#define SPM_TEXD_TEXS 3
#define SPM_TEXD_NPAL 4
#define SPM_TEXD_ALPHA 5
#define SPM_TEXD_MIX 6
#define SPM_TEXD_SURVIVE 7
#define SPM_TEXD_EMIT 8
#define SPM_TEXD_NMAP 9
#define SPM_TEXD_TANGENT 10
#define SPM_TEXD_HEAD 11
#define SPM_TEX_NODES_ALL (SPM_TEX_GRID * SPM_TEX_GRID * SPM_TEX_GRID)
#define SPM_TEX_HEADER(nlevels) (4 + 4 * (nlevels))

/* Opacity (alpha): a material's cut-out or stochastic transparency, decided
 * in traversal, closest hit and shadow rays alike (kernels/alpha.clh,
 * host/geometry/geometry_alpha.c; docs/METHODS.md "Opacity"). A candidate
 * hit on a triangle whose material has an opacity record counts only where
 * the surface is there: alpha = factor x the map's bilinear value at the
 * hit's (u, v) (the factor alone without a map);
 *   MASK   there when alpha >= cutoff (glTF alphaMode MASK);
 *   BLEND  there when u < alpha, u = a hash of the ray's six floats and the
 *          triangle (spm_rng.h spm_alpha_hash): stochastic opacity whose
 *          decision depends on the ray and the triangle only, never on the
 *          order the traversal meets triangles in.
 * The record, from its offset in the texture words: mode, cutoff (float
 * bits), factor (float bits), the map's offset (0: none). A map: width,
 * height, wrap along u, wrap along v (spm_wrap), its transform's offset
 * (SPM_TEX_UVX), then one byte a texel
 * (alpha x 255 rounded), rows top to bottom, four to a word, the first
 * texel in the low byte. Kernels of scenes with one are built with
 * SPM_WITH_ALPHA; the others' traversal is unchanged. */
#define SPM_ALPHA_MASK 1u
#define SPM_ALPHA_BLEND 2u
#define SPM_ALPHA_RECORD 4
#define SPM_ALPHA_MAP_HEAD 5
#define SPM_ALPHA_UVX 4

/* glTF's metallic-roughness model (kernels/metalrough.clh,
 * host/cpu/refcpu_metalrough.c, host/geometry/geometry_alpha.c; docs/METHODS.md
 * "Metallic-roughness"): a material with a mix record is, at each hit, its
 * own (dielectric-coated) self or its metal, another material of the scene
 * (a conductor of F0 = its base colour), the metal with probability the
 * metallic value m = factor x the map's bilinear value at the hit's (u, v);
 * the material chosen takes alpha = (roughness factor x its map's value)^2
 * (below SPM_COND_MIN_ALPHA: 0). The record, from its offset: the metal's
 * material index, the metallic factor, the roughness factor (float bits),
 * the metallic map's and the roughness map's offsets (0: none; maps as the
 * opacity's, one byte a texel). The draw is SPM_DIM_MIX(j). */
#define SPM_MIX_RECORD 5
/* Normal maps (kernels/shading.clh, host/cpu/refcpu_shading.c,
 * host/geometry/geometry_nmap.c; docs/METHODS.md "Normal maps"): a tangent-space
 * normal m = (2 c - 1) (scale, scale, 1) of texel c, bilinear at the hit's
 * (u, v), bends the interpolated normal N (the face's on a flat triangle) to
 * unit(m.x T + m.y B + m.z N), T the interpolated vertex tangent and
 * B = s (N x T) (MikkTSpace's, glTF's: s the handedness), both turned to
 * run along +u' and +v' of the map's transform (SPM_TEX_UVX); then the smooth
 * shading's rule against leaks applies. The record: scale (float bits), the
 * map's offset. A map: width, height, wrap along u, wrap along v, its
 * transform's offset (SPM_TEX_UVX), then one word a texel, (m + 1) / 2 in 10 bits a component (x lowest) on the codes
 * k = 511 (1 + m) so that m = 0 and m = 1 are exact: a flat map (0.5, 0.5, 1)
 * leaves the normal as it is. Kernels of scenes with one are built with
 * SPM_WITH_NMAP (and SPM_WITH_SMOOTH). */
#define SPM_NMAP_RECORD 2
#define SPM_NMAP_MAP_HEAD 5
#define SPM_NMAP_UVX 4
#define SPM_NMAP_CODE 511.0f

/* The ray cone's widening past a lobe that is not a delta, as a fraction of
 * the half-angle of a cone of the lobe's solid angle (kernels/texture.clh
 * tex_cone_bounce). The whole half-angle blurs the texture over as wide a
 * patch as the lobe integrates, which biases colour bleeding: against
 * Mitsuba 3's unfiltered bitmap (docs/VALIDATION_MITSUBA.md "Textures") the
 * 4 x 4-block mean dE00 was 0.67 with it, 0.27 with no widening, 0.30 with an
 * eighth (the seed floor 0.15); an eighth still takes a diffuse bounce's
 * lookups 3 levels coarser at the same distance. */
#define SPM_CONE_LOBE 0.125f

/* Smooth shading (kernels/shading.clh, host/cpu/refcpu_shading.c): where the
 * mirror reflection of the viewer about the interpolated normal falls below
 * the geometric surface, the reflection is lifted to this cosine above it
 * and the shading normal bent to the half vector (Keller et al. 2017). A
 * cosine, so the same in every scene unit. */
#define SPM_SMOOTH_LIFT 0.01f

#endif
