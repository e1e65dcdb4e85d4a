/* PLY files, read by the project's own code: the header, ASCII and both
 * binary byte orders, a `vertex` element (x, y, z of any scalar type; nx, ny,
 * nz when all three are there; other properties skipped), `face` lists and
 * `tristrips` lists (an index list, -1 restarting a strip, every other
 * triangle's winding reversed); other elements skipped. In-process, so a
 * scan of millions of triangles skips the importer's child and its pipe;
 * Assimp 5.2 would also make one triangle of a strip (its issue 2337). A face
 * of more than three vertices in a file without strips is left to Assimp's
 * triangulation (mesh_import.c), which handles concave polygons; beside
 * strips it is split as a fan from its first vertex. */
#ifndef SPM_MESH_PLY_H
#define SPM_MESH_PLY_H
#include "mesh.h"

/* Bounds on what a header may declare (a hostile file must not make the
 * reader allocate for counts it does not hold: memory grows with what is read). */
#define SPM_PLY_MAX_HEADER_LINES 10000
#define SPM_PLY_MAX_ELEMENTS 64
#define SPM_PLY_MAX_PROPERTIES 64

/* spm_ply_read's answer for a file with polygons for Assimp to triangulate */
#define SPM_PLY_POLYGONS 3

/* Reads the PLY file: 0 and *out (one unnamed material: a `material` clause
 * is needed, as for other PLY files; free with spm_mesh_free), or 1 with err
 * naming the file, the line (ASCII and the header) or the element, item and
 * byte offset (binary), and the problem, or SPM_PLY_POLYGONS (nothing in *out,
 * err untouched). A strip's triangles with a repeated index (the joins of
 * strips) are left out. */
int spm_ply_read(const spm_file *file, spm_mesh_data *out, spm_error *err);
#endif
