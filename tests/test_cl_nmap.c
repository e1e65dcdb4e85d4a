/* Normal maps: the kernel's trace against the reference's, path by path
 * (records and level bytes), on a scene where every material type the map
 * may sit on wears one (a checkerboard of two tilted normals): a diffuse
 * floor and wall, a rough and a smooth conductor, a smooth and a rough
 * coating and a glass pane, on flat quads and on a faceted sphere (the
 * rough coating), under an area light and a distant light. (A bumped glass
 * sphere traps paths for 20 and more reflections, over which the kernel's
 * cos/sin ulps grow until 2e-3 of the paths part: chaos, not a difference
 * of formulas; test_cl_smooth sees its start on smooth glass.) The kernel bends the normal by the map and
 * rejects directions on the wrong geometric side as the reference does. How
 * many camera rays meet a bent normal is counted on the host, so a map that
 * changed nothing would fail. The image against real geometry: cli_nmap.sh. */
#include "cl_testlib.h"
#include "refcpu_shading.h"
#include "testutil.h"
#include <unistd.h>

#define SEED 5u
#define W 32
#define H 24
#define SPP 16
/* as test_cl_smooth: a path may diverge only where a few ulps of cos/sin
 * move a ray across an edge */
#define MAX_DIVERGENT_FRACTION 1e-3

static const char *scene_text =
    "image 32 24\n"
    "camera position 0 1.4 -3.2 lookat 0 0.5 0 fov 55\n"
    "spectrum white equal\n"
    "spectrum e inline 380 1 780 1 end\n"
    "spectrum red inline 380 0.1 580 0.1 620 0.8 780 0.8 end\n"
    "texture bumps checker 6 0.75 0.5 0.93 0.32 0.62 0.9\n"
    "material floor reflect white 0.6 normal texture bumps\n"
    "material wall reflect red normal texture bumps scale 0.5\n"
    "material rough conductor e e alpha 0.2 normal texture bumps\n"
    "material mirror conductor e e normal texture bumps\n"
    "material paint coated reflect red ior 1.5 normal texture bumps\n"
    "material satin coated reflect white ior 1.5 alpha 0.3 normal texture bumps\n"
    "material glass dielectric ior 1.5 normal texture bumps\n"
    "material light emit e 20\n"
    "quad floor -2 0 -2  -2 0 2  2 0 2  2 0 -2 uv 0 0 0 1 1 1 1 0\n"
    "quad wall -2 0 2  -2 2 2  2 2 2  2 0 2\n"
    "quad rough -1.6 0 1  -1.6 1 1.2  -0.8 1 1.6  -0.8 0 1.4\n"
    "quad mirror 0.8 0 1.4  0.8 1 1.6  1.6 1 1.2  1.6 0 1\n"
    "quad paint -1.5 0.01 -0.5  -1.5 0.01 0.3  -0.7 0.6 0.3  -0.7 0.6 -0.5\n"
    "quad satin 0.7 0.6 -0.5  0.7 0.6 0.3  1.5 0.01 0.3  1.5 0.01 -0.5\n"
    "quad light -0.5 2.5 -0.5  0.5 2.5 -0.5  0.5 2.5 0.5  -0.5 2.5 0.5\n"
    "quad glass -0.4 0.2 -1.2  0.4 0.2 -1.2  0.4 0.9 -1.1  -0.4 0.9 -1.1\n"
    "light distant 0.4 -1 0.3 white 0.5\n";

/* camera rays of the reference that meet a triangle whose map bends the normal */
static size_t bent_hits(const cl_test_scene *s)
{
    spm_trace_params p = cl_test_params(s, SEED, 0, 1);
    size_t n = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        double dd[3];
        cl_test_camera_dir(&p, i, dd);
        float d[3] = {(float)dd[0], (float)dd[1], (float)dd[2]}, t, gn[3], sn[3], st[3];
        int hit = spm_bvh_intersect(&s->geom, p.cam.eye, d, 0xFFFFFFFFu, &t);
        if (hit < 0)
            continue;
        memcpy(gn, s->geom.tris[hit].n, sizeof gn);
        n += spm_ref_nmap_frame(&s->geom, (spm_u32)hit, p.cam.eye, d, gn, sn, st);
    }
    return n;
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    char dir[] = "/tmp/spm_nmap_XXXXXX", path[256];
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    snprintf(path, sizeof path, "%s/nmap.scene", dir);
    FILE *f = fopen(path, "w");
    CHECK(f != NULL, "cannot write %s", path);
    if (!f)
        return 1;
    fputs(scene_text, f);
    cl_test_write_sphere(f, "satin");
    fclose(f);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "cannot load %s", path);
        TEST_END();
    }
    CHECK(s.geom.ntex && s.geom.tex[SPM_TEXD_NMAP], "the scene has no normal map on the device");
    size_t bent = bent_hits(&s), n = (size_t)W * H * SPP, diverged, level_diff;
    spm_path *cp = spm_xcalloc(n, sizeof *cp);
    int rc = cl_test_trace_diff(&s, SEED, SPP, cp, &diverged, &level_diff);
    CHECK(rc == 0, "the kernel's trace failed");
    printf("%zu paths, %zu of %d camera rays meet a bent normal; %zu diverged, %zu level bytes "
           "differ\n", n, bent, W * H, diverged, level_diff);
    CHECK(bent > (size_t)W * H / 4, "too few camera rays meet a bent normal (%zu)", bent);
    CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu paths diverged", diverged);
    CHECK(level_diff == 0, "%zu level bytes differ", level_diff);
    free(cp);
    cl_test_scene_close(&s);
    unlink(path);
    rmdir(dir);
    TEST_END();
}
