/* Everything a render needs, prepared from the command line: scene, geometry,
 * spectral tables and backends. Shared by `render` and `bench`. */
#ifndef SPM_RENDER_SETUP_H
#define SPM_RENDER_SETUP_H
#include "backend.h"
#include "modes.h"
#include "render_run.h"
#include "scene_camera.h"

typedef struct {
    const char *scene_path;   /* NULL: the built-in default scene */
    int mode;
    int spp;                  /* 0: the scene's, else 16 */
    spm_u32 seed;
    int width, height;        /* 0: the scene's */
    const spm_backend_kind *backend; /* --backend (backends.h's list; the default OpenCL) */
    int devices[SPM_MAX_BACKENDS];
    int ndevices;             /* 0: device 0 */
    int all_devices;          /* --device all */
    /* Opens one device as a backend; NULL: backend->create (tests
     * put one here that fails for a chosen device, as a kernel build would). */
    spm_backend *(*open_device)(int device, const spm_render_plan *plan, spm_error *err);
    spm_pretest_opts pretest;
    int verbose;
    /* Spectral output: bins of this many nm (0: none); the plan then carries
     * spectral records and the host and device memory checks count them. */
    int spec_nm;
    /* What the outputs record beside the image (render_meta.h): the film file
     * kept beside them (its name, in their directory; NULL: none) and the
     * render loop's time budget (0: none). */
    const char *film_name;
    double time_s;
    spm_camera_override cam;  /* --look-from, --look-at, --fov */
    int integrator;           /* --integrator (render_plan.h SPM_INTEGRATOR_*; 0: path) */
    int light_sampler;        /* --light-sampler (SPM_LIGHT_SAMPLER_*; 0: by the scene) */
} spm_render_config;

/* How next-event estimation picks a light (--light-sampler): by the scene
 * (the tree from SPM_LIGHT_TREE_AUTO_MIN placed lights on), in proportion
 * to power, or through the light tree (host/geometry/light_tree.h). */
enum { SPM_LIGHT_SAMPLER_AUTO, SPM_LIGHT_SAMPLER_POWER, SPM_LIGHT_SAMPLER_TREE };
#define SPM_LIGHT_TREE_AUTO_MIN 64
/* the sampler a name gives (-1: none) */
int spm_light_sampler_parse(const char *name);

/* Wall seconds of each stage of a render (`render --stats`); setup fills the
 * first four, the command the rest. */
typedef struct {
    double load_s;    /* reading and parsing the scene and its spectra */
    double bvh_s;     /* triangles, emitters and the BVH */
    double tables_s;  /* spectral tables and the pretest's levels */
    double kernels_s; /* opening the devices: buffers and kernel builds */
    double render_s;  /* the render loop */
    double output_s;  /* writing the images */
    int compiled_in_render; /* PoCL compiled during the render loop (pocl_cache.h): 1, 0,
                               -1 not watched (the CPU backend, or no PoCL cache) */
} spm_stage_times;

typedef struct {
    spm_scene scene;
    spm_geometry geom;
    spm_tables tables;
    spm_render_plan plan;     /* what every backend renders */
    spm_backend *b[SPM_MAX_BACKENDS];
    int device[SPM_MAX_BACKENDS]; /* b[i]'s device index (0 for a kind without devices) */
    int nb;
    spm_stage_times times;
} spm_render_setup;

/* Samples per pixel: --spp, else the scene's, else 16. */
int spm_render_spp(const spm_render_config *c, const spm_scene *sc);
/* Returns 0, or an exit code (2 input error, 1 runtime, 130 interrupted:
 * loading, BVH build and pretests stop at a signal, a program build is
 * followed through first) with err filled.
 * Several devices are opened (programs built) concurrently; one that cannot be
 * opened is reported by name on stderr and left out, and only when none is
 * left is that an error. A device index listed twice is an input error. */
int spm_render_setup_open(const spm_render_config *c, spm_render_setup *s, spm_error *err);
/* The pretest c's mode reads, into s->tables (spm_tables_levels; nothing for
 * a mode without levels): spm_render_setup_open runs it, and a caller that
 * keeps s's tables for renders in another mode runs it again. 0 or 1. */
int spm_render_setup_levels(const spm_render_config *c, spm_render_setup *s, spm_error *err);
/* *w x *h (the scene's size) after --width want_w / --height want_h (0: not
 * given): one alone keeps the scene's aspect ratio. */
void spm_render_size(int want_w, int want_h, int *w, int *h);
/* The second half of spm_render_setup_open, for a process given the prepared
 * scene rather than reading it: from s->geom, s->tables and s->scene's width,
 * height and spp, the plan and the backends. Same return values. */
int spm_render_setup_backends(const spm_render_config *c, spm_render_setup *s, spm_error *err);
void spm_render_setup_close(spm_render_setup *s);
#endif
