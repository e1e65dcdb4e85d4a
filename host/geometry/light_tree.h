/* The light tree (include/spm_light_tree.h): built over g's emitters. */
#ifndef SPM_GEOMETRY_LIGHT_TREE_H
#define SPM_GEOMETRY_LIGHT_TREE_H
#include "geometry.h"
#include "spm_light_tree.h"

/* Builds the tree over g's lights (their powers g->light_w; a triangle's
 * material from mats says whether it emits from both faces) and writes it
 * after the ntris per-triangle pmfs of g->light_pdf: g->ntree its words. */
void spm_light_tree_attach(spm_geometry *g, const spm_material *mats);
/* 1: a light of kind k is in the tree (it has a place); 0: beside it */
int spm_light_placed(spm_u32 kind);
#endif
