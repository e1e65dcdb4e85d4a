/* Shared by the harnesses: the loaders read files, so each input is written
 * to one file in a private directory and the loader is given its path. */
#ifndef SPM_FUZZ_INPUT_H
#define SPM_FUZZ_INPUT_H
#include <stddef.h>
#include <stdint.h>

/* Writes data to a file named `name` in this process's temporary directory
 * and returns its path (valid until the next call), or NULL on failure. */
const char *spm_fuzz_write(const char *name, const uint8_t *data, size_t size);
#endif
