/* The OpenCL backend's device buffers, listed once: the backend creates them
 * from these lists and the device-memory check (cl_resources.c) adds up the
 * same lists, so the two cannot drift apart. The shade tables are the mode's
 * (modes.h spm_mode_footprint). */
#ifndef SPM_CL_BUFFERS_H
#define SPM_CL_BUFFERS_H
#include "spm_shared.h"

/* Per batch, room for n paths (and up to n pixels):
 * X(field, what, bytes per path, flags, initial contents), evaluated where
 * pix_ch (render_plan.h: the floats of a path's record, 3 + spectral bins)
 * and vertex_bytes (render_plan.h: spm_vertex plus the words of the scene's
 * types, materials.h) are in scope. The vertex slabs
 * have room for every depth; only those some path reaches are touched.
 * IDENTITY: 0, 1, 2, ... (the bucket list when one kernel takes every path). */
#define SPM_CL_BATCH_BUFFERS(X)                                                     \
    X(heads, "path record headers", sizeof(spm_dev_head), CL_MEM_READ_WRITE, NONE)  \
    X(verts, "path records", SPM_MAX_DEPTH * vertex_bytes, CL_MEM_READ_WRITE, NONE)  \
    X(levels, "level bytes", 1, CL_MEM_READ_WRITE, NONE)                            \
    X(ident, "identity indices", sizeof(spm_u32), CL_MEM_READ_ONLY, IDENTITY)       \
    X(idx, "bucket indices", sizeof(spm_u32), CL_MEM_READ_ONLY, NONE)               \
    X(xyz, "path XYZ", (size_t)pix_ch * sizeof(float), CL_MEM_READ_WRITE, NONE)      \
    X(pass, "batch image", (size_t)pix_ch * sizeof(float), CL_MEM_WRITE_ONLY, NONE)

/* Per scene, read-only, copied from the host:
 * X(field, what, bytes, contents), evaluated where g (spm_geometry), t
 * (spm_tables) and lvlk (the mode's level table) are in scope. dtab and dcmf:
 * the 1 nm rows and weights a committed path shades from (modes.h nm1), only
 * in a scene with dispersive glass. */
#define SPM_CL_SCENE_BUFFERS(X)                                                     \
    X(tris, "triangles", (size_t)g->ntris * sizeof(spm_tri), g->tris)              \
    X(nodes, "BVH", (size_t)g->nwide * sizeof(spm_bvh4_node), g->wide)             \
    X(emitters, "emitters", (size_t)g->nemitters * sizeof(spm_emitter), g->emitters) \
    X(light_pdf, "light selection", ((size_t)g->ntris + (size_t)g->ntree) * sizeof(float),  \
      g->light_pdf)                                                                 \
    X(vnormals, "vertex normals", (size_t)g->nvn * 9 * sizeof(float), g->vnormals)  \
    X(disp, "dispersive indices", (size_t)g->ndisp * SPM_TRUTH_BINS * sizeof(float), g->disp) \
    X(tex, "textures", g->ntex * sizeof(spm_u32), g->tex)                          \
    X(uvs, "texture coordinates", g->uvs ? (size_t)g->ntris * 6 * sizeof(float) : 0, g->uvs) \
    X(envmap, "environment map", (size_t)g->nenv * sizeof(float), g->env)           \
    X(dtab, "1 nm colour table", g->ndisp ? (size_t)t->ncolours * SPM_TRUTH_BINS * sizeof(float) : 0, \
      t->truth)                                                                     \
    X(dcmf, "1 nm XYZ weights", g->ndisp ? 3 * SPM_TRUTH_BINS * sizeof(float) : 0,  \
      &t->cmf_truth[0][0])                                                          \
    X(mats, "materials", (size_t)t->nmaterials * sizeof(spm_material), t->materials) \
    X(lvlk, "level table", (size_t)t->ncolours * SPM_PRETEST_KMAX, lvlk)
#endif
