/* PLY files with triangle strips, read by the project's own code (Assimp 5.2
 * makes one triangle of a strip): the header, ASCII and both binary byte
 * orders, a `vertex` element (x, y, z of any scalar type; other properties
 * skipped), `face` lists (fan-triangulated) and `tristrips` lists (an index
 * list, -1 restarting a strip, every other triangle's winding reversed);
 * other elements skipped. mesh_import.c sends a PLY here when its header
 * declares `element tristrips`. */
#ifndef SPM_MESH_PLY_H
#define SPM_MESH_PLY_H
#include "mesh.h"

/* Bounds on what a header may declare (a hostile file must not make the
 * reader allocate for counts it does not hold: memory grows with what is read). */
#define SPM_PLY_MAX_HEADER_LINES 10000
#define SPM_PLY_MAX_ELEMENTS 64
#define SPM_PLY_MAX_PROPERTIES 64

/* 1 if the file starts with a PLY header declaring `element tristrips`. */
int spm_ply_has_strips(const char *path);

/* Reads the PLY file: 0 and *out (one unnamed material: a `material` clause
 * is needed, as for other PLY files; free with spm_mesh_free), or 1 with err
 * naming the file, the line (ASCII and the header) or the element, item and
 * byte offset (binary), and the problem. A strip's triangles with a repeated
 * index (the joins of strips) are left out. */
int spm_ply_read(const char *path, spm_mesh_data *out, spm_error *err);
#endif
