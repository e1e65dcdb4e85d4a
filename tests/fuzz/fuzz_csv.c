/* libFuzzer harness: the spectrum CSV loader (host/colour/csv.c): the table, then
 * every column as a reflectance and as an emission spectrum. */
#include "spectrum.h"
#include "fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = spm_fuzz_write("input.csv", data, size);
    if (!path)
        return 0;
    spm_csv c;
    spm_error err;
    spm_spectrum sp;
    if (spm_csv_load(path, &c, &err) == 0) {
        for (int col = 1; col < c.ncols; col++) {
            spm_spectrum_from_csv(&c, col, path, SPM_KIND_REFLECTANCE, &sp, &err);
            spm_spectrum_from_csv(&c, col, path, SPM_KIND_EMISSION, &sp, &err);
        }
        spm_csv_free(&c);
    }
    spm_spectrum_load(path, NULL, SPM_KIND_REFLECTANCE, &sp, &err);
    return 0;
}
