/* One render across several processes (MPI ranks), e.g. on several machines:
 * `mpirun -np N specmip render ...`. Rank 0 reads the scene and everything it
 * names and sends the prepared scene (prepared.h) to the other ranks, which
 * open their own devices (--device applies per rank) and never open a scene
 * file. On rank 0 every device of another rank is a backend of the render
 * loop (render_run.h) like its own: the loop hands passes out dynamically,
 * gives a failed device's pass to the others and adds pass images to the film
 * in pass order, so the image is the one a single process makes. Only rank 0
 * writes outputs.
 *
 * MPI is called from one thread only, the one that called MPI_Init: on rank 0
 * the render loop runs in a thread of its own meanwhile. Without MPI at build
 * time (SPM_HAVE_MPI undefined), or when not started by mpirun, there is one
 * rank and nothing here calls MPI. */
#ifndef SPM_MPI_RENDER_H
#define SPM_MPI_RENDER_H
#include "render_setup.h"

typedef struct {
    int rank, size;   /* size 1: not under mpirun (or built without MPI) */
    int started;      /* MPI_Init was called */
} spm_mpi;

/* MPI_Init when started by mpirun (OMPI_COMM_WORLD_SIZE is set), so a plain
 * run does not pay for it. 0, or 1 with err filled. */
int spm_mpi_start(spm_mpi *m, spm_error *err);
/* MPI_Finalize (when started). After an interruption or a lost rank the job
 * is being torn down by mpirun: then MPI is left as it is. */
void spm_mpi_end(spm_mpi *m, int torn_down);

/* A rank above 0: the whole render from the prepared scene, in rank 0's mode
 * and seed on this rank's own devices (--device, --backend). Returns its exit
 * code (rank 0 reports every error). A test hook: SPECMIP_TEST_SLOW_PASS=S
 * in a rank's environment makes it wait S seconds after each of its passes. */
int spm_mpi_worker(spm_mpi *m, spm_render_config *c);

/* Rank 0, after spm_render_setup_open returned rc: tells the others whether
 * to go on (rc 0: sends them the prepared scene), then adds the devices they
 * opened as backends s->b[s->nb...]. A rank that opened none is reported and
 * left out. Returns rc, or SPM_EXIT_RUNTIME with err filled. */
int spm_mpi_share(spm_mpi *m, int rc, const spm_render_config *c, spm_render_setup *s,
                  spm_error *err);
/* Rank 0: spm_render_run over s's backends while this thread carries the
 * messages of the other ranks' devices. */
int spm_mpi_render_run(spm_mpi *m, spm_render_setup *s, size_t npix, const spm_run_opts *o,
                       spm_film *film, spm_run_result *r, spm_error *err);
/* Rank 0 after an interrupted render: every other rank says when it was
 * signalled too. 0 when all did (a signal to mpirun: the image so far is
 * written); 1 with err naming the rank that did not: it died, mpirun is
 * ending the job, and no image is written. */
int spm_mpi_check_signalled(spm_mpi *m, spm_error *err);
#endif
