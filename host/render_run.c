#include "render_run.h"
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

spm_u32 spm_spp_per_pass(size_t npix, int spp)
{
    size_t want = (65536 + npix - 1) / (npix ? npix : 1);
    if (want < 1)
        want = 1;
    if (want > (size_t)spp)
        want = (size_t)spp;
    return (spm_u32)want;
}

typedef struct {
    /* shared state, guarded by mu */
    pthread_mutex_t mu;
    pthread_cond_t changed;         /* a pass finished or was given back */
    int in_flight;                  /* passes being rendered now */
    int npasses, next_pass, next_to_add;
    int *retry, nretry;             /* passes a failed device left behind */
    float **done;                   /* finished pass images waiting for their turn */
    /* fixed */
    spm_backend **b;
    size_t npix;
    const spm_run_opts *o;
    spm_film *film;
    spm_run_result *r;
    double t0;
} run_state;

typedef struct {
    run_state *s;
    int idx;
} worker_arg;

static spm_u32 pass_spp(const run_state *s, int pass)
{
    int first = pass * (int)s->o->spp_per_pass;
    int left = s->o->spp - first;
    return (spm_u32)(left < (int)s->o->spp_per_pass ? left : (int)s->o->spp_per_pass);
}

/* Caller holds mu. The next pass to render, or -1. */
static int take_pass(run_state *s)
{
    if (s->o->stop && *s->o->stop)
        return -1;
    if (s->nretry > 0)
        return s->retry[--s->nretry];
    if (s->next_pass < s->npasses)
        return s->next_pass++;
    return -1;
}

static void progress_line(run_state *s)
{
    double dt = spm_now() - s->t0;
    double paths = (double)s->r->total.paths;
    int left = s->npasses - s->next_to_add;
    double eta = s->next_to_add > 0 ? dt / s->next_to_add * left : 0.0;
    fprintf(stderr, "\rspecmip: pass %d/%d  %.2f Mpaths/s  ETA %.0f s   ", s->next_to_add,
            s->npasses, dt > 0 ? paths / dt * 1e-6 : 0.0, eta);
    if (left == 0)
        fputc('\n', stderr);
}

/* Caller holds mu: add every finished pass that is next in order. */
static void flush_in_order(run_state *s)
{
    while (s->next_to_add < s->npasses && s->done[s->next_to_add]) {
        int p = s->next_to_add;
        spm_film_add_pass(s->film, s->done[p], (int)pass_spp(s, p));
        s->r->spp_done += (int)pass_spp(s, p);
        free(s->done[p]);
        s->done[p] = NULL;
        s->next_to_add++;
        if (s->o->progress)
            progress_line(s);
    }
}

static void *worker(void *argp)
{
    worker_arg *a = argp;
    run_state *s = a->s;
    spm_backend *b = s->b[a->idx];
    for (;;) {
        pthread_mutex_lock(&s->mu);
        int pass = take_pass(s);
        /* nothing left to take, but a pass in flight may yet fail and come back */
        while (pass < 0 && s->in_flight > 0 && !(s->o->stop && *s->o->stop)) {
            pthread_cond_wait(&s->changed, &s->mu);
            pass = take_pass(s);
        }
        if (pass >= 0)
            s->in_flight++;
        pthread_mutex_unlock(&s->mu);
        if (pass < 0)
            break;
        float *img = spm_xcalloc(s->npix * 3, sizeof(float));
        spm_pass_stats st;
        memset(&st, 0, sizeof st);
        spm_error err;
        err.msg[0] = 0;
        int rc = b->pass(b, (spm_u32)pass * s->o->spp_per_pass, pass_spp(s, pass), img, &st, &err);
        pthread_mutex_lock(&s->mu);
        s->in_flight--;
        pthread_cond_broadcast(&s->changed);
        if (rc) {
            /* the device is lost for this render: its pass goes back to the queue */
            fprintf(stderr, "specmip: device '%s' failed: %s; its work goes to the other devices\n",
                    b->name, err.msg);
            s->retry[s->nretry++] = pass;
            s->r->failed[a->idx] = 1;
            free(img);
            pthread_mutex_unlock(&s->mu);
            break;
        }
        spm_pass_stats_add(&s->r->total, &st);
        spm_pass_stats_add(&s->r->per_backend[a->idx], &st);
        s->r->passes_by_backend[a->idx]++;
        s->done[pass] = img;
        flush_in_order(s);
        pthread_mutex_unlock(&s->mu);
    }
    return NULL;
}

int spm_render_run(spm_backend **b, int nb, size_t npix, const spm_run_opts *o, spm_film *film,
                   spm_run_result *r, spm_error *err)
{
    if (nb < 1 || nb > SPM_MAX_BACKENDS) {
        spm_errorf(err, "between 1 and %d devices can render together (got %d)", SPM_MAX_BACKENDS,
                   nb);
        return 1;
    }
    memset(r, 0, sizeof *r);
    run_state s;
    memset(&s, 0, sizeof s);
    pthread_mutex_init(&s.mu, NULL);
    pthread_cond_init(&s.changed, NULL);
    s.npasses = (o->spp + (int)o->spp_per_pass - 1) / (int)o->spp_per_pass;
    s.retry = spm_xcalloc((size_t)s.npasses + 1, sizeof *s.retry);
    s.done = spm_xcalloc((size_t)s.npasses + 1, sizeof *s.done);
    s.b = b;
    s.npix = npix;
    s.o = o;
    s.film = film;
    s.r = r;
    s.t0 = spm_now();
    pthread_t th[SPM_MAX_BACKENDS];
    worker_arg args[SPM_MAX_BACKENDS];
    for (int i = 0; i < nb; i++) {
        args[i].s = &s;
        args[i].idx = i;
        pthread_create(&th[i], NULL, worker, &args[i]);
    }
    for (int i = 0; i < nb; i++)
        pthread_join(th[i], NULL);
    r->wall_s = spm_now() - s.t0;
    r->interrupted = s.next_to_add < s.npasses && o->stop && *o->stop;
    int incomplete = s.next_to_add < s.npasses && !r->interrupted;
    for (int p = 0; p < s.npasses; p++)
        free(s.done[p]);
    free(s.done);
    free(s.retry);
    pthread_mutex_destroy(&s.mu);
    pthread_cond_destroy(&s.changed);
    if (incomplete) {
        spm_errorf(err, "every device failed; %d of %d passes rendered", s.next_to_add, s.npasses);
        return 1;
    }
    return 0;
}
