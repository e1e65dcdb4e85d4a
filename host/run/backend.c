/* Helpers of the backend interface (backend.h). */
#include "backend.h"
#include "interrupt.h"

int spm_pass_batch_end(const spm_pass_ctl *c, uint64_t paths_so_far)
{
    spm_test_pause("pass"); /* before batch_done, which turns a signal into c->stop */
    if (c && c->batch_done)
        c->batch_done(c->ctx, paths_so_far);
    return c && c->stop && *c->stop;
}
