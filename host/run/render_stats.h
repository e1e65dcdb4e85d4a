/* `render --stats` / `--json`: timings, throughput and the level decisions. */
#ifndef SPM_RENDER_STATS_H
#define SPM_RENDER_STATS_H
#include <stdio.h>
#include "render_setup.h"

void spm_render_stats_text(FILE *f, const spm_render_config *c, const spm_render_setup *s,
                           const spm_run_result *r);
void spm_render_stats_json(FILE *f, const spm_render_config *c, const spm_render_setup *s,
                           const spm_run_result *r);
/* Warns (stderr) when more than SPM_DROPPED_WARN of the samples, or of the
 * pixels' pass sums added to `film`, were NaN/Inf and left out: the light they
 * carried is missing and the image is darker than the scene. Returns 1 if it
 * warned. */
#define SPM_DROPPED_WARN 1e-3
int spm_render_warn_dropped(const spm_run_result *r, const spm_film *film);
#endif
