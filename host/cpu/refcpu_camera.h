/* The CPU reference's camera contract (kernels/camera.clh has the kernels'
 * own and says what each call means): the ray of a film point and lens
 * sample, the importance We, its densities pdf_We and sample_Wi (pbrt-v4
 * PerspectiveCamera). Plain scalar float C, in the kernels' operation order. */
#ifndef SPM_REFCPU_CAMERA_H
#define SPM_REFCPU_CAMERA_H
#include "spm_shared.h"

/* the ray of film point (cx, cy) in [-1, 1]^2 and lens sample (lu, lv) */
void spm_ref_camera_ray(const spm_camera *cam, float cx, float cy, float lu, float lv, float o[3],
                        float d[3]);
/* We of the ray from lens point o along unit d, and the film point it images
 * to (0: none) */
float spm_ref_camera_We(const spm_camera *cam, const float o[3], const float d[3], float film[2]);
/* the densities of the ray's origin (lens area) and direction (solid angle) */
void spm_ref_camera_pdf_We(const spm_camera *cam, const float o[3], const float d[3],
                           float *pdf_pos, float *pdf_dir);
/* a lens point seen from p: wi toward it, its distance, the film point and
 * wi's density in solid angle at p; returns We (0: p is not seen) */
float spm_ref_camera_sample_Wi(const spm_camera *cam, const float p[3], float lu, float lv,
                               float wi[3], float *dist, float *pdf, float film[2]);
#endif
