/* Hints on a scene that loads but may render nothing (warnings, not errors). */
#ifndef SPM_SCENE_HINTS_H
#define SPM_SCENE_HINTS_H
#include "scene.h"

/* Whether triangles t[0, n) are closed: every edge (its two vertices, matched
 * by value, -0 = +0, in either order) shared by exactly two of them. */
int spm_tris_closed(const spm_scene_tri *t, int n);
/* The edges of t[0, n) that are not shared by exactly two of them (the
 * boundary of an open surface, or an edge of three or more): 0 when closed. */
long spm_tris_unpaired_edges(const spm_scene_tri *t, int n);
/* The hints, together (the geometry's build runs them beside it): the camera
 * inside a closed mesh (below), and per mesh statement, its dielectric
 * triangles when they are not closed, with the count of edges not shared by
 * exactly two of them. Read s->tris: call it before they are consumed. */
void spm_scene_hints(const spm_scene *s);
/* Warns, per mesh statement, when the camera is inside the mesh's bounding
 * box and the mesh is closed: its inside faces may be all the camera sees.
 * Reads s->tris, so call it before they are consumed. Meshes above
 * SPM_HINT_CLOSED_MAX_TRIS triangles are not checked. */
void spm_scene_hint_camera_inside(const spm_scene *s);
#define SPM_HINT_CLOSED_MAX_TRIS (1 << 21) /* 2M triangles: 88 MB at most (the position table, the corners' vertex ids) */
#endif
