/* One render across MPI ranks (mpi_render.h). */
#include "mpi_render.h"
#include <stdlib.h>
#include <string.h>
#include "interrupt.h"

#ifndef SPM_HAVE_MPI
int spm_mpi_start(spm_mpi *m, spm_error *err)
{
    (void)err;
    memset(m, 0, sizeof *m);
    m->size = 1;
    return 0;
}
void spm_mpi_end(spm_mpi *m, int torn_down) { (void)m, (void)torn_down; }
int spm_mpi_worker(spm_mpi *m, spm_render_config *c)
{
    (void)m, (void)c;
    return SPM_EXIT_RUNTIME;
}
int spm_mpi_share(spm_mpi *m, int rc, const spm_render_config *c, spm_render_setup *s,
                  spm_error *err)
{
    (void)m, (void)c, (void)s, (void)err;
    return rc;
}
int spm_mpi_render_run(spm_mpi *m, spm_render_setup *s, size_t npix, const spm_run_opts *o,
                       spm_film *film, spm_run_result *r, spm_error *err)
{
    (void)m;
    return spm_render_run(s->b, s->nb, npix, o, film, r, err);
}
int spm_mpi_check_signalled(spm_mpi *m, spm_error *err)
{
    (void)m, (void)err;
    return 0;
}
#else
#include <mpi.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <time.h>
#include <unistd.h>
#include "prepared.h"

enum {
    TAG_PASS = 1,   /* rank 0 -> rank: render a pass on one of your devices (pass_req) */
    TAG_HEAD,       /* rank -> 0: a pass's outcome (pass_head) ... */
    TAG_IMAGE,      /* ... then, when it succeeded, its image (npix * 3 floats) */
    TAG_DONE,       /* rank 0 -> rank: the render is over */
    TAG_SIGNALLED   /* rank -> 0: a signal arrived; this rank stops */
};

typedef struct {
    int32_t dev;
    uint32_t first_sample, spp;
} pass_req;

typedef struct {
    int32_t dev, rc;
    spm_pass_stats st;
    spm_error err;
} pass_head;

/* What a rank above 0 tells rank 0 once its devices are open. */
typedef struct {
    int32_t rc, nb;
    char host[64];
    char names[SPM_MAX_BACKENDS][256];
    spm_error err;
} rank_info;

static void nap(void)
{
    /* 1 ms: a pass takes far longer; at 0.2 ms the idle polling of rank 0's
     * MPI thread and the ranks' main threads cost the devices ~15 % of a core */
    struct timespec t = {0, 1000000};
    nanosleep(&t, NULL);
}

int spm_mpi_start(spm_mpi *m, spm_error *err)
{
    memset(m, 0, sizeof *m);
    m->size = 1;
    if (!getenv("OMPI_COMM_WORLD_SIZE"))
        return 0;
    int provided;
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        spm_errorf(err, "MPI_Init failed");
        return 1;
    }
    m->started = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &m->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m->size);
    return 0;
}

typedef struct hub hub;
typedef struct {
    hub *h;
    int rank, dev;
    int state; /* 0 idle, 1 requested, 2 sent, 3 answered */
    pass_req req;
    pass_head head;
    float *img;
} proxy;

struct hub {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    size_t npix;
    int nproxies;
    proxy *p[SPM_MAX_BACKENDS];
    int render_done;
    int signalled[1]; /* per rank, allocated with the hub */
};

static hub *the_hub;

void spm_mpi_end(spm_mpi *m, int torn_down)
{
    if (!m->started)
        return;
    if (torn_down && m->rank == 0 && the_hub) { /* the ranks that wait in signalled_exit */
        int zero = 0;
        for (int rk = 1; rk < m->size; rk++)
            if (the_hub->signalled[rk])
                MPI_Send(&zero, 1, MPI_INT, rk, TAG_DONE, MPI_COMM_WORLD);
    }
    if (!torn_down)
        MPI_Finalize();
    m->started = 0;
}

static void host_name(char *buf, size_t n)
{
    if (gethostname(buf, n))
        snprintf(buf, n, "?");
    buf[n - 1] = 0;
}

/* ---- ranks above 0 ---- */

/* One thread per device; the main thread alone calls MPI. */
typedef struct worker worker;
typedef struct {
    worker *w;
    int dev;
    int state; /* 0 idle, 1 a request to render, 2 done: head/img to send */
    pass_req req;
    pass_head head;
    float *img;
    pthread_t th;
    int threaded;
} dev_slot;

struct worker {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int quit;
    size_t npix;
    double slow_s; /* seconds added to every pass */
    spm_render_setup *s;
    dev_slot slot[SPM_MAX_BACKENDS];
};

static void render_request(worker *w, dev_slot *d)
{
    spm_backend *b = w->s->b[d->dev];
    memset(&d->head, 0, sizeof d->head);
    d->head.dev = d->dev;
    memset(d->img, 0, w->npix * 3 * sizeof(float));
    b->ctl = (spm_pass_ctl){&spm_stop_flag, NULL, NULL};
    d->head.rc = b->pass(b, d->req.first_sample, d->req.spp, d->img, &d->head.st, &d->head.err);
    if (w->slow_s > 0) { /* the test hook SPECMIP_TEST_SLOW_PASS */
        struct timespec t = {(time_t)w->slow_s, (long)((w->slow_s - (double)(time_t)w->slow_s) * 1e9)};
        nanosleep(&t, NULL);
    }
}

static void *dev_thread(void *arg)
{
    dev_slot *d = arg;
    worker *w = d->w;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while (d->state != 1 && !w->quit)
            pthread_cond_wait(&w->cv, &w->mu);
        if (w->quit)
            break;
        pthread_mutex_unlock(&w->mu);
        render_request(w, d);
        pthread_mutex_lock(&w->mu);
        d->state = 2;
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

/* A signal: rank 0 hears of it, and this rank ends once rank 0 has written
 * the image (mpirun ends the whole job as soon as one rank exits with an
 * error). MPI_Finalize is left out: it would wait for ranks that may be gone. */
static void signalled_exit(void)
{
    int one = 1, flag = 0;
    MPI_Send(&one, 1, MPI_INT, 0, TAG_SIGNALLED, MPI_COMM_WORLD);
    while (!flag) {
        MPI_Status st;
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (flag && st.MPI_TAG != TAG_DONE) { /* a pass request that crossed: dropped */
            pass_req q;
            MPI_Recv(&q, sizeof q, MPI_BYTE, 0, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            flag = 0;
        }
        if (!flag)
            nap();
    }
    _exit(SPM_EXIT_INTERRUPTED);
}

static int serve(worker *w)
{
    for (;;) {
        if (spm_stop_requested())
            signalled_exit();
        int busy = 0, flag;
        MPI_Status st;
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (flag) {
            busy = 1;
            if (st.MPI_TAG == TAG_DONE) {
                int dummy;
                MPI_Recv(&dummy, 1, MPI_INT, 0, TAG_DONE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                return 0;
            }
            pass_req q;
            MPI_Recv(&q, sizeof q, MPI_BYTE, 0, TAG_PASS, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (q.dev < 0 || q.dev >= w->s->nb)
                return SPM_EXIT_RUNTIME;
            dev_slot *d = &w->slot[q.dev];
            pthread_mutex_lock(&w->mu);
            d->req = q;
            d->state = 1;
            pthread_cond_broadcast(&w->cv);
            pthread_mutex_unlock(&w->mu);
            if (!d->threaded) {
                render_request(w, d);
                d->state = 2;
            }
        }
        for (int i = 0; i < w->s->nb; i++) {
            dev_slot *d = &w->slot[i];
            pthread_mutex_lock(&w->mu);
            int done = d->state == 2;
            pthread_mutex_unlock(&w->mu);
            if (!done)
                continue;
            busy = 1;
            if (d->head.rc == SPM_PASS_STOPPED)
                signalled_exit();
            MPI_Send(&d->head, sizeof d->head, MPI_BYTE, 0, TAG_HEAD, MPI_COMM_WORLD);
            if (d->head.rc == 0)
                MPI_Send(d->img, (int)(w->npix * 3), MPI_FLOAT, 0, TAG_IMAGE, MPI_COMM_WORLD);
            pthread_mutex_lock(&w->mu);
            d->state = 0;
            pthread_mutex_unlock(&w->mu);
        }
        if (!busy)
            nap();
    }
}

int spm_mpi_worker(spm_mpi *m, spm_render_config *c)
{
    int32_t go = 0;
    MPI_Bcast(&go, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (go) { /* rank 0 could not prepare the render and says why */
        spm_mpi_end(m, 0);
        return go;
    }
    uint64_t n = 0;
    MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    void *buf = spm_xmalloc((size_t)n + 1);
    MPI_Bcast(buf, (int)n, MPI_BYTE, 0, MPI_COMM_WORLD);
    spm_render_setup s;
    memset(&s, 0, sizeof s);
    rank_info info;
    memset(&info, 0, sizeof info);
    host_name(info.host, sizeof info.host);
    spm_prepared_info pi;
    if (spm_prepared_unpack(buf, (size_t)n, &s.geom, &s.tables, &pi, &info.err)) {
        info.rc = SPM_EXIT_RUNTIME;
    } else {
        s.scene.width = pi.width;
        s.scene.height = pi.height;
        c->spp = pi.spp; /* what rank 0 renders, whatever this rank's command line says */
        c->mode = pi.mode;
        c->seed = pi.seed;
        c->integrator = pi.integrator;
        info.rc = spm_render_setup_backends(c, &s, &info.err);
    }
    free(buf);
    info.nb = info.rc ? 0 : s.nb;
    for (int i = 0; i < info.nb; i++)
        snprintf(info.names[i], sizeof info.names[i], "%s", s.b[i]->name);
    MPI_Gather(&info, sizeof info, MPI_BYTE, NULL, 0, MPI_BYTE, 0, MPI_COMM_WORLD);
    int rc = 0;
    if (info.nb > 0) {
        worker *w = spm_xcalloc(1, sizeof *w);
        pthread_mutex_init(&w->mu, NULL);
        pthread_cond_init(&w->cv, NULL);
        w->s = &s;
        w->npix = (size_t)pi.width * (size_t)pi.height;
        const char *slow = getenv("SPECMIP_TEST_SLOW_PASS");
        w->slow_s = slow ? atof(slow) : 0.0;
        for (int i = 0; i < s.nb; i++) {
            dev_slot *d = &w->slot[i];
            d->w = w;
            d->dev = i;
            d->img = spm_xmalloc(w->npix * 3 * sizeof(float));
            d->threaded = pthread_create(&d->th, NULL, dev_thread, d) == 0;
        }
        rc = serve(w);
        pthread_mutex_lock(&w->mu);
        w->quit = 1;
        pthread_cond_broadcast(&w->cv);
        pthread_mutex_unlock(&w->mu);
        for (int i = 0; i < s.nb; i++) {
            if (w->slot[i].threaded)
                pthread_join(w->slot[i].th, NULL);
            free(w->slot[i].img);
        }
        pthread_mutex_destroy(&w->mu);
        pthread_cond_destroy(&w->cv);
        free(w);
    } else {
        /* rank 0 leaves this rank out; it still ends the render with TAG_DONE */
        for (int flag = 0; !flag;) {
            if (spm_stop_requested())
                signalled_exit();
            MPI_Iprobe(0, TAG_DONE, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
            if (!flag)
                nap();
        }
        int dummy;
        MPI_Recv(&dummy, 1, MPI_INT, 0, TAG_DONE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
    spm_render_setup_close(&s);
    spm_mpi_end(m, 0);
    return rc;
}

/* ---- rank 0 ---- */


/* The proxy's pass: rank 0's main thread sends the request and receives the
 * answer; this thread waits for it, or stops at a signal. */
static int proxy_pass(spm_backend *b, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                      spm_pass_stats *st, spm_error *err)
{
    proxy *p = b->impl;
    hub *h = p->h;
    pthread_mutex_lock(&h->mu);
    p->req = (pass_req){p->dev, first_sample, spp};
    p->state = 1;
    while (p->state != 3 && !(b->ctl.stop && *b->ctl.stop)) {
        struct timespec t;
        clock_gettime(CLOCK_REALTIME, &t);
        t.tv_nsec += 20000000; /* 20 ms: a signal is seen soon */
        if (t.tv_nsec >= 1000000000) {
            t.tv_sec++;
            t.tv_nsec -= 1000000000;
        }
        pthread_cond_timedwait(&h->cv, &h->mu, &t);
    }
    int rc;
    if (p->state != 3) {
        rc = SPM_PASS_STOPPED; /* an answer still coming is dropped */
    } else {
        rc = p->head.rc;
        *st = p->head.st;
        if (rc)
            *err = p->head.err;
        else
            memcpy(pass_xyz, p->img, h->npix * 3 * sizeof(float));
        p->state = 0;
    }
    pthread_mutex_unlock(&h->mu);
    return rc;
}

static void proxy_destroy(spm_backend *b)
{
    proxy *p = b->impl;
    free(p->img);
    free(p);
    free(b);
}

int spm_mpi_share(spm_mpi *m, int rc, const spm_render_config *c, spm_render_setup *s,
                  spm_error *err)
{
    if (m->size < 2)
        return rc;
    (void)c;
    int32_t go = rc;
    MPI_Bcast(&go, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (rc)
        return rc;
    spm_prepared_info pi = {s->scene.width, s->scene.height, spm_render_spp(c, &s->scene),
                            c->mode, c->seed, c->integrator};
    size_t n;
    void *buf = spm_prepared_pack(&s->geom, &s->tables, &pi, &n);
    uint64_t n64 = n;
    if (n > (size_t)INT32_MAX) {
        free(buf);
        spm_errorf(err, "the prepared scene (%zu bytes) is too large to send (2 GiB at most)", n);
        n64 = 0; /* the others fail to unpack it and end */
    }
    MPI_Bcast(&n64, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    MPI_Bcast(n64 ? buf : (void *)"", (int)n64, MPI_BYTE, 0, MPI_COMM_WORLD);
    if (n64)
        free(buf);
    rank_info *all = spm_xcalloc((size_t)m->size, sizeof *all);
    rank_info mine;
    memset(&mine, 0, sizeof mine);
    MPI_Gather(&mine, sizeof mine, MPI_BYTE, all, sizeof mine, MPI_BYTE, 0, MPI_COMM_WORLD);
    hub *h = spm_xcalloc(1, sizeof *h + (size_t)m->size * sizeof(int));
    pthread_mutex_init(&h->mu, NULL);
    pthread_cond_init(&h->cv, NULL);
    h->npix = (size_t)s->scene.width * (size_t)s->scene.height;
    the_hub = h;
    char host[64];
    host_name(host, sizeof host);
    for (int i = 0; i < s->nb; i++) { /* the statistics name every device's rank */
        char name[sizeof s->b[i]->name];
        snprintf(name, sizeof name, "rank 0 (%.64s): %.160s", host, s->b[i]->name);
        memcpy(s->b[i]->name, name, sizeof name);
    }
    for (int r = 1; r < m->size; r++) {
        if (all[r].rc || all[r].nb < 1) {
            fprintf(stderr, "specmip: rank %d (%s) left out: %s\n", r, all[r].host,
                    all[r].err.msg);
            continue;
        }
        for (int i = 0; i < all[r].nb; i++) {
            if (s->nb >= SPM_MAX_BACKENDS) {
                spm_warnf("more than %d devices in all; rank %d's device %d is left out",
                          SPM_MAX_BACKENDS, r, i);
                continue;
            }
            proxy *p = spm_xcalloc(1, sizeof *p);
            p->h = h;
            p->rank = r;
            p->dev = i;
            p->img = spm_xmalloc(h->npix * 3 * sizeof(float));
            spm_backend *b = spm_xcalloc(1, sizeof *b);
            snprintf(b->name, sizeof b->name, "rank %d (%.64s): %.160s", r, all[r].host, all[r].names[i]);
            b->pass = proxy_pass;
            b->destroy = proxy_destroy;
            b->impl = p;
            h->p[h->nproxies++] = p;
            s->b[s->nb++] = b;
        }
    }
    free(all);
    return 0;
}

typedef struct {
    spm_render_setup *s;
    size_t npix;
    const spm_run_opts *o;
    spm_film *film;
    spm_run_result *r;
    spm_error *err;
    int rc;
} run_job;

static void *run_thread(void *arg)
{
    run_job *j = arg;
    j->rc = spm_render_run(j->s->b, j->s->nb, j->npix, j->o, j->film, j->r, j->err);
    pthread_mutex_lock(&the_hub->mu);
    the_hub->render_done = 1;
    pthread_mutex_unlock(&the_hub->mu);
    return NULL;
}

static proxy *find_proxy(hub *h, int rank, int dev)
{
    for (int i = 0; i < h->nproxies; i++)
        if (h->p[i]->rank == rank && h->p[i]->dev == dev)
            return h->p[i];
    return NULL;
}

/* Carries one message from another rank, if one is waiting: 1 if it did. */
/* A pass image from rank src. A rank that dies between its head and its image
 * would leave a blocking receive waiting for ever; once a stop is requested
 * (mpirun signals every rank when one dies) the receive is given up after
 * 0.5 s and left pending: the job is being torn down (no MPI_Finalize
 * follows) and a dead sender writes nothing more into buf. 1: received. */
static int recv_image(float *buf, int n, int src)
{
    MPI_Request rq;
    MPI_Irecv(buf, n, MPI_FLOAT, src, TAG_IMAGE, MPI_COMM_WORLD, &rq);
    double stop_at = 0;
    for (;;) {
        int done = 0;
        MPI_Test(&rq, &done, MPI_STATUS_IGNORE);
        if (done)
            return 1;
        if (spm_stop_requested()) {
            double now = spm_now();
            if (!stop_at)
                stop_at = now;
            else if (now - stop_at > 0.5)
                return 0;
        }
        nap();
    }
}

static int take_message(hub *h, float *spare)
{
    int flag;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
    if (!flag)
        return 0;
    int src = st.MPI_SOURCE;
    if (st.MPI_TAG == TAG_SIGNALLED) {
        int one;
        MPI_Recv(&one, 1, MPI_INT, src, TAG_SIGNALLED, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        h->signalled[src] = 1;
        return 1;
    }
    pass_head head;
    MPI_Recv(&head, sizeof head, MPI_BYTE, src, TAG_HEAD, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    proxy *p = find_proxy(h, src, head.dev);
    pthread_mutex_lock(&h->mu);
    int wanted = p && p->state == 2;
    pthread_mutex_unlock(&h->mu);
    /* the image goes to the proxy while its pass waits for it; else it is dropped */
    if (head.rc == 0 && !recv_image(wanted ? p->img : spare, (int)(h->npix * 3), src))
        wanted = 0; /* the rank died between head and image: its pass is not answered */
    if (wanted) {
        pthread_mutex_lock(&h->mu);
        p->head = head;
        p->state = 3;
        pthread_cond_broadcast(&h->cv);
        pthread_mutex_unlock(&h->mu);
    }
    return 1;
}

int spm_mpi_render_run(spm_mpi *m, spm_render_setup *s, size_t npix, const spm_run_opts *o,
                       spm_film *film, spm_run_result *r, spm_error *err)
{
    if (m->size < 2)
        return spm_render_run(s->b, s->nb, npix, o, film, r, err);
    hub *h = the_hub;
    run_job j = {s, npix, o, film, r, err, 0};
    pthread_t th;
    if (pthread_create(&th, NULL, run_thread, &j)) {
        spm_errorf(err, "no thread for the render loop");
        return 1;
    }
    float *spare = spm_xmalloc(npix * 3 * sizeof(float));
    for (;;) {
        int busy = 0;
        pass_req out[SPM_MAX_BACKENDS];
        int to[SPM_MAX_BACKENDS], nout = 0;
        pthread_mutex_lock(&h->mu);
        int done = h->render_done;
        for (int i = 0; i < h->nproxies; i++)
            if (h->p[i]->state == 1) {
                h->p[i]->state = 2;
                out[nout] = h->p[i]->req;
                to[nout++] = h->p[i]->rank;
            }
        pthread_mutex_unlock(&h->mu);
        if (done)
            break;
        for (int i = 0; i < nout; i++)
            MPI_Send(&out[i], sizeof out[i], MPI_BYTE, to[i], TAG_PASS, MPI_COMM_WORLD);
        busy = nout > 0;
        while (take_message(h, spare))
            busy = 1;
        if (!busy)
            nap();
    }
    pthread_join(th, NULL);
    free(spare);
    if (!r->interrupted) {
        /* the answers of passes still in flight are not awaited: the others end */
        int zero = 0;
        for (int rk = 1; rk < m->size; rk++)
            MPI_Send(&zero, 1, MPI_INT, rk, TAG_DONE, MPI_COMM_WORLD);
    }
    return j.rc;
}

int spm_mpi_check_signalled(spm_mpi *m, spm_error *err)
{
    if (m->size < 2 || !the_hub)
        return 0;
    hub *h = the_hub;
    float *spare = spm_xmalloc(h->npix * 3 * sizeof(float));
    /* mpirun signals every rank at once; 0.3 s is ample for each to say so
     * and well within the second before it kills them */
    double t0 = spm_now();
    int missing;
    do {
        while (take_message(h, spare))
            ;
        missing = 0;
        for (int rk = 1; rk < m->size; rk++)
            missing += !h->signalled[rk];
        if (missing)
            nap();
    } while (missing && spm_now() - t0 < 0.3);
    free(spare);
    /* every silent rank is named: under load a live one may answer late */
    char list[256] = "";
    int nmissing = 0;
    for (int rk = 1; rk < m->size; rk++)
        if (!h->signalled[rk]) {
            size_t at = strlen(list);
            snprintf(list + at, sizeof list - at, "%srank %d stopped without a signal of its own",
                     nmissing++ ? "; " : "", rk);
        }
    if (!nmissing)
        return 0;
    spm_errorf(err, "%s: %s, and mpirun is ending the job", list,
               nmissing > 1 ? "one of them died" : "it died");
    return 1;
}
#endif
