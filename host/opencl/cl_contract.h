/* The host/kernel contract (include/) as this binary was built with it: the
 * kernels are compiled at run time from the source tree (SPECMIP_DATA or the
 * build's own), and headers that differ from the host's would give structs of
 * another layout, argument lists in another order: a crash, not an error. */
#ifndef SPM_CL_CONTRACT_H
#define SPM_CL_CONTRACT_H
#include "util.h"
#include <stddef.h>

typedef struct {
    const char *path; /* relative to the source tree, e.g. "include/spm_shared.h" */
    const unsigned char *bytes;
    size_t size;
} spm_contract_file;

/* Every header of include/, sorted by path, ended by {0}; generated at build
 * time (cmake/embed_contract.cmake). */
extern const spm_contract_file spm_contract[];

/* 0 when the kernel tree's include/ holds exactly the headers the host was
 * built with; else 1 and err names the first header that differs. */
int spm_cl_contract_check(spm_error *err);
#endif
