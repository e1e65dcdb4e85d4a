/* Ctrl-C and SIGTERM. The first signal sets spm_stop_flag, which every long
 * step polls at cheap points (the scene and CSV parsers per token or line, the
 * BVH build per node, the pretests per colour, a pass between its batches) and
 * answers by ending cleanly: the caller then writes what is complete and exits
 * 130. A second signal ends the process at once with exit 130, after removing
 * the temporary files of image writes in progress (spm_temp_register), so
 * existing outputs are left as they were.
 *
 * A test hook, always compiled in and active only when the environment sets it:
 * SPECMIP_TEST_PAUSE=STAGE[:N][,STAGE[:N]...] pauses the N-th time (default the
 * first) a named stage is reached, printing "specmip: test pause at STAGE" on
 * stderr, until a signal arrives (at most 60 s); then the program goes on as it
 * would have, so what it does next is what it does on a signal at that moment.
 * Stages: load (the scene, per line), csv (a spectrum file, per line), mesh (a
 * mesh file's importer started, its answer not read yet), bvh (per
 * node), pretest (per colour), build (before the OpenCL programs are built),
 * pass (inside a pass, at a batch boundary), write (an image file being
 * written: its temporary file exists, the data are not written yet), film (the
 * same for a film file, output/film_file.h), row (a bench CSV row written and
 * flushed). */
#ifndef SPM_INTERRUPT_H
#define SPM_INTERRUPT_H
#include <signal.h>
#ifdef __cplusplus
extern "C" {
#endif

/* Set by the first SIGINT/SIGTERM while they are caught. */
extern volatile sig_atomic_t spm_stop_flag;
static inline int spm_stop_requested(void) { return spm_stop_flag != 0; }

/* Catch SIGINT and SIGTERM (and arm the test hook from the environment);
 * release: back to the default actions. */
void spm_catch_interrupts(void);
void spm_release_interrupts(void);

/* A temporary file that a second signal removes before exiting. Register the
 * name before creating the file (a signal may come at any moment), unregister
 * once it is renamed or removed. At most SPM_TEMP_SLOTS at once; -1 when all
 * are taken (the file is then not removed on a second signal). */
#define SPM_TEMP_SLOTS 8
int spm_temp_register(const char *path);
void spm_temp_unregister(int slot);

/* The test hook (see above). */
extern int spm_test_pause_armed;
void spm_test_pause_at(const char *stage);
static inline void spm_test_pause(const char *stage)
{
    if (spm_test_pause_armed)
        spm_test_pause_at(stage);
}
#ifdef __cplusplus
}
#endif
#endif
