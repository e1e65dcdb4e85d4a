/* Whether PoCL compiled anything during a timed stretch. PoCL compiles a
 * kernel's work-group functions for the shape of a launch at its first launch
 * of that shape (cl_render_program.c, spm_clr_warm_up) and writes each compiled
 * version into its kernel cache, so the cache gaining files or bytes across a
 * timed render means the time includes a compile. Other OpenCL platforms
 * compile in clBuildProgram and are not watched. */
#ifndef SPM_POCL_CACHE_H
#define SPM_POCL_CACHE_H

typedef struct {
    long long files, bytes; /* files -1: no cache directory found */
} spm_pocl_cache;

/* The cache now: POCL_CACHE_DIR, else PoCL's default $XDG_CACHE_HOME/pocl/kcache
 * or ~/.cache/pocl/kcache (its temporary files left out). */
spm_pocl_cache spm_pocl_cache_now(void);
/* 1: the cache grew from a to b, 0: it did not, -1: no cache to watch. */
int spm_pocl_cache_grew(const spm_pocl_cache *a, const spm_pocl_cache *b);
/* The directory spm_pocl_cache_now reads (for messages). */
const char *spm_pocl_cache_dir(char *buf, unsigned long size);
#endif
