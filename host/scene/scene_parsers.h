/* The two scene formats' parsers, which spm_scene_load (scene_load.c)
 * dispatches to by the file's first line; each builds through scene_build.h. */
#ifndef SPM_SCENE_PARSERS_H
#define SPM_SCENE_PARSERS_H
#include "scene.h"
#include "paths.h"

/* The project's format (docs/SCENE_FORMAT.md), scene_parse.c. */
int spm_scene_parse_text(const spm_file *file, spm_scene *out, spm_error *err);
/* MiniLight's .ml.txt, scene_minilight.c. */
int spm_scene_parse_minilight(const spm_file *file, spm_scene *out, spm_error *err);
/* pbrt-v4's .pbrt files (docs/PBRT.md), pbrt_parse.c. */
int spm_scene_parse_pbrt(const spm_file *file, spm_scene *out, spm_error *err);
/* Mitsuba 3's .xml files (docs/MITSUBA.md), mitsuba_parse.c. */
int spm_scene_parse_mitsuba(const spm_file *file, spm_scene *out, spm_error *err);
/* A model file alone (.glb, .gltf, .obj, .ply, .stl), scene_model.c. */
int spm_scene_parse_model(const spm_file *file, spm_scene *out, spm_error *err);
/* 1 with err when --camera was given (spm_scene_model_camera) for a file
 * that is not a model file alone. */
int spm_scene_model_camera_unused(const char *path, spm_error *err);
#endif
