/* The light tree (Conty Estevez and Kulla 2018; pbrt-v4's BVHLightSampler):
 * a binary tree over the lights that have a place (triangles, points,
 * spots), each node bounding its lights' box, orientation cone and power,
 * walked from the root by the importance of each child to a shading point;
 * the lights without a place (distant, sun, environment map) beside it,
 * each as likely as the whole tree. Built by host/geometry/light_tree.c,
 * walked by kernels/light_tree.clh and host/cpu/refcpu_light_tree.c.
 *
 * Its words follow the per-triangle pmfs in the light_pdf buffer (floats;
 * integers stored as their bits), from word ntris on:
 *   a head of SPM_LTREE_HEAD words: nodes, area emitters (the table's first
 *   entries, in triangle order), lights beside the tree;
 *   the emitter index of each light beside the tree;
 *   the nodes, SPM_LTREE_NODE words each, the root first, a node's first
 *   child right after it;
 *   for each emitter its trail (two words, low then high 32 bits): bit i
 *   chooses the child at depth i (0 the first, 1 the second). */
#ifndef SPM_LIGHT_TREE_H
#define SPM_LIGHT_TREE_H
#define SPM_LTREE_HEAD 4
#define SPM_LTREE_H_NODES 0
#define SPM_LTREE_H_AREA 1
#define SPM_LTREE_H_INF 2
#define SPM_LTREE_NODE 16
#define SPM_LTN_LO 0     /* box: lo x, y, z */
#define SPM_LTN_HI 3     /* hi x, y, z */
#define SPM_LTN_W 6      /* the cone's axis (unit) */
#define SPM_LTN_COS_O 9  /* cos theta_o: the normals' spread about the axis */
#define SPM_LTN_COS_E 10 /* cos theta_e: how far beyond its normal a light emits */
#define SPM_LTN_PHI 11   /* power, in the selection's unit */
#define SPM_LTN_NEXT 12  /* (bits) an inner node's second child; a leaf's emitter */
#define SPM_LTN_FLAGS 13 /* (bits) SPM_LTF_* */
#define SPM_LTF_LEAF 1u
#define SPM_LTF_TWOSIDED 2u
/* the share of a node's power over distance it weighs at least, facing
 * away or not (host/cpu/refcpu_light_tree.c): small, for the cones to steer
 * the choice; enough that where both children face away from a point the
 * float differences between devices move the pmf by ~1e-7 / 1e-3 */
#define SPM_LTREE_FLOOR (1.0f / 1024.0f)
/* the deepest a trail reaches */
#define SPM_LTREE_MAX_DEPTH 64
#endif
