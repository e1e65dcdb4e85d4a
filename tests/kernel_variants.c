/* Lists every OpenCL program the host builds, one per line: its source files
 * (relative to the data root, space-separated), a tab, its build options
 * beyond the ones every build adds (cl_core.c). The render's programs come from
 * the backend's own spm_cl_program_files / spm_cl_program_defines for every
 * mode with every slot used, without and with each spectral output bin width
 * the mode writes, and the light and bidirectional integrators' where they
 * render the scene, on
 * the default scene and each scene given (the shade kernels' vector counts
 * follow a scene's tables); then the ray replay's and
 * the operator benchmark's. Duplicates are left to the caller (sort -u).
 * Not a test itself: cli_kernel_warnings.sh compiles what it lists.
 * Usage: kernel_variants [SCENE...] */
#include "bench_ops.h"
#include "bench_rays.h"
#include "cl_testlib.h"

static void print_files(const char *const *files, int n)
{
    for (int i = 0; i < n; i++)
        printf("%s%s", i ? " " : "", files[i]);
}

/* The plan of mode m with every slot used, and spectral output of nm nm (0: none). */
static int print_plan(const cl_test_scene *s, int m, int nm)
{
    spm_render_plan plan;
    spm_error err;
    if (spm_render_plan_init(&plan, &s->geom, &s->tables, m, 1, &err) ||
        (nm && spm_render_plan_spectral(&plan, nm, &err))) {
        fprintf(stderr, "kernel_variants: %s mode: %s\n", spm_mode_name(m), err.msg);
        return 1;
    }
    for (int sl = 0; sl < plan.nslots; sl++)
        plan.used[sl] = 1;
    char defs[1024];
    spm_cl_program_defines(&plan, 0, defs, sizeof defs, NULL);
    print_files(spm_cl_program_files, SPM_CL_PROGRAM_NFILES);
    printf("\t%s\n", defs);
    spm_error why;
    if (!spm_render_plan_integrator(&plan, SPM_INTEGRATOR_LIGHT, &why)) { /* its own program */
        spm_cl_program_defines(&plan, 0, defs, sizeof defs, NULL);
        print_files(spm_cl_light_program_files, SPM_CL_LIGHT_PROGRAM_NFILES);
        printf("\t%s\n", defs);
    }
    if (!spm_render_plan_integrator(&plan, SPM_INTEGRATOR_BDPT, &why)) {
        spm_cl_program_defines(&plan, 0, defs, sizeof defs, NULL);
        print_files(spm_cl_bdpt_program_files, SPM_CL_BDPT_PROGRAM_NFILES);
        printf("\t%s\n", defs);
    }
    spm_render_plan_free(&plan);
    return 0;
}

int main(int argc, char **argv)
{
    for (int a = 0; a < argc; a++) {
        cl_test_scene s;
        if (cl_test_scene_load(&s, a ? argv[a] : NULL, 8, 8))
            return 1;
        int rc = 0;
        for (int m = 0; m < SPM_MODE_COUNT && !rc; m++) {
            const spm_mode_desc *d = spm_mode(m);
            spm_error why;
            if (spm_mode_check(d, &s.tables, &why))
                continue; /* a mode that refuses the scene (hero, fluorescence) builds nothing */
            rc = print_plan(&s, m, 0);
            for (int k = 0; k < 2 && !rc; k++)
                if (d->spec_nm[k])
                    rc = print_plan(&s, m, d->spec_nm[k]);
        }
        cl_test_scene_close(&s);
        if (rc)
            return 1;
    }
    for (size_t k = 0; k < sizeof spm_rays_program_defines / sizeof *spm_rays_program_defines; k++)
        printf("%s\t%s\n", spm_rays_program_file, spm_rays_program_defines[k]);
    printf("%s\t\n", spm_ops_program_file);
    return 0;
}
