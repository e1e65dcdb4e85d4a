/* `render --stats` / `--json`: timings, throughput and the level decisions. */
#ifndef SPM_RENDER_STATS_H
#define SPM_RENDER_STATS_H
#include <stdio.h>
#include "render_setup.h"

void spm_render_stats_text(FILE *f, const spm_render_config *c, const spm_render_setup *s,
                           const spm_run_result *r);
void spm_render_stats_json(FILE *f, const spm_render_config *c, const spm_render_setup *s,
                           const spm_run_result *r);
#endif
