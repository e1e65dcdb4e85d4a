/* The prepared scene as one block of bytes: what a render needs once the scene
 * and every file it names have been read (geometry with its BVH, the spectral
 * and level tables, the image size and samples per pixel), so that a process
 * that never opens a scene file can render it. Both ends must be builds of
 * the same program on machines of the same byte order and type sizes (the
 * structs travel as they are in memory). */
#ifndef SPM_PREPARED_H
#define SPM_PREPARED_H
#include <stddef.h>
#include "geometry.h"
#include "tables.h"

typedef struct {
    int width, height, spp; /* the image and samples per pixel the render uses */
    int mode;               /* the spectral mode (modes.h) */
    spm_u32 seed;
    int integrator;         /* render_plan.h SPM_INTEGRATOR_* */
} spm_prepared_info;

/* A malloc'ed block (*n bytes) holding g, t and info. */
void *spm_prepared_pack(const spm_geometry *g, const spm_tables *t, const spm_prepared_info *info,
                        size_t *n);
/* Rebuilds g, t and info from a block; 0, or 1 with err filled when the block
 * is not one spm_prepared_pack made (short, or of another build). g and t are
 * then freed with spm_geometry_free and spm_tables_free. */
int spm_prepared_unpack(const void *buf, size_t n, spm_geometry *g, spm_tables *t,
                        spm_prepared_info *info, spm_error *err);
/* The prepared scene's fingerprint (FNV-1a 64 of its block without the
 * image size, spp, mode and seed, and without the BVH build's statistics):
 * the same scene, files and pretest give the same number. */
uint64_t spm_prepared_hash(const spm_geometry *g, const spm_tables *t);
#endif
