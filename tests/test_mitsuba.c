/* Mitsuba 3 XML files read by value (host/scene/mitsuba_*.c): transforms in
 * Mitsuba's order, the camera's frame and fov_axis, default / $name / -D,
 * ref and id, include, the unit shapes' conventions, the BSDFs' mapping,
 * spectra (piecewise linear and zero outside, constants, rgb, blackbody),
 * emitter units, the constant background, files (spectrum, OBJ through
 * <path>, PLY); errors naming file:line:col.
 * Scenes written here. */
#include "colour.h"
#include "geometry.h"
#include "materials.h"
#include "scene.h"
#include "testutil.h"
#include "envmap_testlib.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[300];

static const char *write_file(const char *name, const char *text)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    return path;
}

/* body inside <scene>, with a light so that every scene is complete */
static int load(const char *name, const char *body, spm_scene *s, spm_error *err)
{
    char text[16384];
    snprintf(text, sizeof text,
             "<scene version=\"3.0.0\">\n%s\n<shape type=\"rectangle\">\n"
             "<transform name=\"to_world\"><translate z=\"-50\"/></transform>\n"
             "<emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter>\n"
             "</shape>\n</scene>\n", body);
    return spm_scene_load(write_file(name, text), s, err);
}

/* the first triangle not emitting whose material is of type `type` (-1 any) */
static const spm_scene_tri *first_of(const spm_scene *s, int type)
{
    for (int i = 0; i < s->ntris; i++) {
        const spm_scene_material *m = &s->materials[s->tris[i].material];
        if (m->emit < 0 && (type < 0 || m->type == type))
            return &s->tris[i];
    }
    return NULL;
}

static void normal_of(const spm_scene_tri *t, double n[3])
{
    double a[3], b[3];
    for (int i = 0; i < 3; i++) {
        a[i] = t->p[1][i] - t->p[0][i];
        b[i] = t->p[2][i] - t->p[0][i];
    }
    n[0] = a[1] * b[2] - a[2] * b[1];
    n[1] = a[2] * b[0] - a[0] * b[2];
    n[2] = a[0] * b[1] - a[1] * b[0];
}

static void test_transforms(void)
{
    spm_scene s;
    spm_error err;
    /* scale 2, then rotate 90 about z, then translate: (1,1,0) -> (2,2,0) -> (-2,2,0) -> (-1,4,3) */
    int rc = load("t.xml", "<shape type=\"rectangle\"><transform name=\"to_world\">"
                           "<scale value=\"2\"/><rotate z=\"1\" angle=\"90\"/>"
                           "<translate x=\"1\" y=\"2\" z=\"3\"/></transform></shape>", &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    const spm_scene_tri *t = rc ? NULL : first_of(&s, -1);
    CHECK(t != NULL, "a triangle");
    if (t) { /* the rectangle's third vertex is (1, 1, 0) */
        CHECK_NEAR(t->p[2][0], -1, 1e-6, "x");
        CHECK_NEAR(t->p[2][1], 4, 1e-6, "y");
        CHECK_NEAR(t->p[2][2], 3, 1e-6, "z");
        double n[3];
        normal_of(t, n);
        CHECK(n[2] > 0 && fabs(n[0]) < 1e-6, "the rectangle faces +z: (%g %g %g)", n[0], n[1], n[2]);
    }
    spm_scene_free(&s);
    /* matrix: row by row, its translation the last column */
    rc = load("m.xml", "<shape type=\"rectangle\"><transform name=\"to_world\">"
                       "<matrix value=\"2 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1\"/></transform></shape>",
              &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    t = rc ? NULL : first_of(&s, -1);
    if (t) {
        CHECK_NEAR(t->p[2][0], 7, 1e-6, "x = 2 * 1 + 5");
        CHECK_NEAR(t->p[2][1], 7, 1e-6, "y = 1 + 6");
    }
    spm_scene_free(&s);
}

/* Mitsuba's camera: x is the image's left; fov across x by default. */
static void test_camera(void)
{
    const char *axis[3] = {"", "<string name=\"fov_axis\" value=\"y\"/>",
                           "<string name=\"fov_axis\" value=\"diagonal\"/>"};
    double want[3] = {tan(15 * M_PI / 180), tan(15 * M_PI / 180) * 2,
                      tan(15 * M_PI / 180) / sqrt(1.25)};
    for (int k = 0; k < 3; k++) {
        char body[1024];
        snprintf(body, sizeof body,
                 "<sensor type=\"perspective\"><float name=\"fov\" value=\"30\"/>%s"
                 "<transform name=\"to_world\"><lookat origin=\"0,0,-5\" target=\"0,0,0\" "
                 "up=\"0,1,0\"/></transform><film type=\"hdrfilm\"><integer name=\"width\" "
                 "value=\"200\"/><integer name=\"height\" value=\"100\"/></film>"
                 "<sampler type=\"independent\"><integer name=\"sample_count\" value=\"7\"/>"
                 "</sampler></sensor>", axis[k]);
        spm_scene s;
        spm_error err;
        int rc = load("c.xml", body, &s, &err);
        CHECK(rc == 0, "%s", err.msg);
        if (rc)
            continue;
        spm_camera c = spm_camera_of_scene(&s);
        CHECK_NEAR(c.eye[2], -5, 1e-6, "eye z");
        CHECK_NEAR(c.dir[2], 1, 1e-6, "looks along +z");
        CHECK_NEAR(c.up[1], 1, 1e-6, "up y");
        /* Mitsuba: camera x = up x dir = +x is the image's left: right is -x */
        CHECK_NEAR(c.right[0], -1, 1e-6, "right x");
        CHECK_NEAR(c.tan_half, want[k], 1e-6, "tan_half for the fov_axis");
        CHECK(s.width == 200 && s.height == 100 && s.spp == 7, "film and sampler");
        spm_scene_free(&s);
    }
    /* thinlens: the aperture's radius and the distance in focus */
    spm_scene s;
    spm_error err;
    int rc = load("t.xml",
                  "<sensor type=\"thinlens\"><float name=\"fov\" value=\"30\"/>"
                  "<float name=\"aperture_radius\" value=\"0.25\"/>"
                  "<float name=\"focus_distance\" value=\"4\"/></sensor>",
                  &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    CHECK_NEAR(s.aperture, 0.5, 1e-7, "thinlens: aperture diameter 2 aperture_radius");
    CHECK_NEAR(s.focus, 4, 1e-7, "thinlens: focus_distance");
    spm_scene_free(&s);
    rc = load("p.xml",
              "<sensor type=\"perspective\"><float name=\"aperture_radius\" value=\"0.25\"/>"
              "<float name=\"focus_distance\" value=\"4\"/></sensor>",
              &s, &err);
    CHECK(rc == 0 && s.aperture == 0, "perspective: a pinhole whatever its aperture_radius");
    if (!rc)
        spm_scene_free(&s);
}

static double refl_at(const spm_scene *s, const spm_scene_tri *t, int nm)
{
    return s->colours[s->materials[t->material].refl].s.nm1[nm - SPM_LAMBDA_MIN];
}

/* default, $name and -D; ref and id shared; include of a fragment */
static void test_params_refs(void)
{
    write_file("frag.xml", "<scene version=\"3.0.0\"><bsdf type=\"diffuse\" id=\"grey\">"
                           "<spectrum name=\"reflectance\" value=\"$r\"/></bsdf></scene>");
    const char *body = "<default name=\"r\" value=\"0.25\"/><include filename=\"frag.xml\"/>"
                       "<shape type=\"rectangle\"><ref id=\"grey\"/></shape>"
                       "<shape type=\"cube\"><ref id=\"grey\"/></shape>";
    spm_scene s;
    spm_error err;
    int rc = load("p.xml", body, &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    const spm_scene_tri *t = rc ? NULL : first_of(&s, SPM_MAT_LAMBERT);
    if (t) {
        CHECK_NEAR(refl_at(&s, t, 550), 0.25, 1e-9, "the default's value");
        int n = 0;
        for (int i = 0; i < s.ntris; i++)
            n += s.tris[i].material == t->material;
        CHECK(n == 2 + 12, "rectangle and cube share the material: %d", n);
    }
    spm_scene_free(&s);
    CHECK(spm_scene_define("r=0.75", &err) == 0, "%s", err.msg);
    rc = load("p.xml", body, &s, &err);
    t = rc ? NULL : first_of(&s, SPM_MAT_LAMBERT);
    CHECK(t && fabs(refl_at(&s, t, 550) - 0.75) < 1e-9, "-D r=0.75 wins over the default");
    spm_scene_free(&s);
    CHECK(spm_scene_define("novalue", &err) == 1, "-D without '='");
}

static const spm_scene_material *mat_at_z(const spm_scene *s, double z)
{
    for (int i = 0; i < s->ntris; i++)
        if (fabs(s->tris[i].p[0][2] - z) < 1e-6 && s->materials[s->tris[i].material].emit < 0)
            return &s->materials[s->tris[i].material];
    return NULL;
}

static void test_bsdfs(void)
{
    spm_scene s;
    spm_error err;
#define AT(z, bsdf)                                                                        \
    "<shape type=\"rectangle\"><transform name=\"to_world\"><translate z=\"" #z "\"/>"      \
    "</transform>" bsdf "</shape>"
    int rc = load("b.xml",
                  AT(0, "<bsdf type=\"conductor\"><string name=\"material\" value=\"Au\"/></bsdf>")
                  AT(1, "<bsdf type=\"roughconductor\"><float name=\"alpha\" value=\"0.2\"/>"
                        "<string name=\"distribution\" value=\"ggx\"/></bsdf>")
                  AT(2, "<bsdf type=\"dielectric\"><string name=\"int_ior\" value=\"water\"/>"
                        "</bsdf>")
                  AT(3, "<bsdf type=\"roughdielectric\"><float name=\"int_ior\" value=\"1.6\"/>"
                        "<float name=\"ext_ior\" value=\"1.2\"/><string name=\"distribution\" "
                        "value=\"ggx\"/><float name=\"alpha\" value=\"0.3\"/></bsdf>")
                  AT(4, "<bsdf type=\"plastic\"><boolean name=\"nonlinear\" value=\"true\"/>"
                        "<rgb name=\"diffuse_reflectance\" value=\"0.5\"/></bsdf>")
                  AT(5, "<bsdf type=\"twosided\"><bsdf type=\"diffuse\"><float "
                        "name=\"reflectance\" value=\"0.3\"/></bsdf></bsdf>")
                  AT(6, "<bsdf type=\"conductor\"><spectrum name=\"eta\" value=\"2\"/>"
                        "<rgb name=\"k\" value=\"3, 2, 1\"/></bsdf>"),
                  &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    const spm_scene_material *m[7];
    for (int z = 0; z < 7; z++) {
        m[z] = mat_at_z(&s, z);
        CHECK(m[z] != NULL, "a material at z %d", z);
        if (!m[z])
            return;
    }
    CHECK(m[0]->type == SPM_MAT_CONDUCTOR && m[0]->p[SPM_COND_P_ALPHA] == 0, "smooth Au");
    /* gold's k at 600 nm is near 3 (metal_Au_k.csv); eta near 0.25 */
    CHECK(s.colours[m[0]->col2].s.nm1[220] > 2.5 && s.colours[m[0]->refl].s.nm1[220] < 0.5,
          "Au eta %g k %g", s.colours[m[0]->refl].s.nm1[220], s.colours[m[0]->col2].s.nm1[220]);
    /* the default material "none": eta 0, k 1 (a mirror) */
    CHECK(s.colours[m[1]->refl].s.nm1[100] == 0 && s.colours[m[1]->col2].s.nm1[100] == 1,
          "material none");
    CHECK_NEAR(m[1]->p[SPM_COND_P_ALPHA], 0.2, 1e-12, "alpha is GGX's width");
    CHECK(m[2]->type == SPM_MAT_DIELECTRIC, "dielectric");
    CHECK_NEAR(m[2]->p[SPM_DIEL_P_IOR], 1.3330 / 1.000277, 1e-9, "water over air");
    CHECK_NEAR(m[3]->p[SPM_DIEL_P_IOR], 1.6 / 1.2, 1e-12, "int_ior / ext_ior");
    CHECK_NEAR(m[3]->p[SPM_DIEL_P_ALPHA], 0.3, 1e-12, "rough dielectric alpha");
    CHECK(m[4]->type == SPM_MAT_COATED, "plastic -> coated");
    CHECK_NEAR(m[4]->p[SPM_COAT_P_ETA], 1.49 / 1.000277, 1e-9, "polypropylene over air");
    CHECK_NEAR(s.colours[m[4]->refl].s.nm1[100], 0.5, 1e-9, "grey rgb is its constant");
    CHECK(m[5]->type == SPM_MAT_LAMBERT, "twosided holds a diffuse");
    CHECK_NEAR(s.colours[m[5]->refl].s.nm1[300], 0.3, 1e-12, "float reflectance");
    /* unbounded lift: eta 2 stays 2, k (3 2 1) peaks above 1 */
    CHECK_NEAR(s.colours[m[6]->refl].s.nm1[200], 2.0, 1e-9, "eta 2");
    CHECK(spm_spectrum_max(&s.colours[m[6]->col2].s) > 2.5, "k unbounded");
    spm_scene_free(&s);
}

/* λ:v pairs are piecewise linear and zero outside; a radiance keeps its
 * values (luminance = Mitsuba's Y); rgb radiance 1 is luminance 1; a
 * blackbody is Planck's radiance per nm; constant is the background. */
static void test_spectra(void)
{
    spm_scene s;
    spm_error err;
    int rc = load("s.xml",
                  "<shape type=\"rectangle\"><bsdf type=\"diffuse\"><spectrum name=\"reflectance\" "
                  "value=\"420:0.2, 520:0.6\"/></bsdf></shape>"
                  "<shape type=\"rectangle\"><transform name=\"to_world\"><translate z=\"1\"/>"
                  "</transform><emitter type=\"area\"><spectrum name=\"radiance\" value=\"3\"/>"
                  "</emitter></shape>"
                  "<shape type=\"rectangle\"><transform name=\"to_world\"><translate z=\"2\"/>"
                  "</transform><emitter type=\"area\"><blackbody name=\"radiance\" "
                  "temperature=\"5000K\"/></emitter></shape>"
                  "<emitter type=\"constant\"><spectrum name=\"radiance\" value=\"0.5\"/></emitter>",
                  &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    const spm_scene_tri *t = first_of(&s, SPM_MAT_LAMBERT);
    CHECK(t != NULL, "the diffuse rectangle");
    if (t) { /* bin 470..471 nm: mean of the line 0.2 + 0.4 (λ - 420) / 100 */
        CHECK_NEAR(refl_at(&s, t, 470), 0.2 + 0.4 * 50.5 / 100, 1e-9, "linear between");
        CHECK_NEAR(refl_at(&s, t, 400), 0.0, 1e-12, "zero below the first sample");
        CHECK_NEAR(refl_at(&s, t, 600), 0.0, 1e-12, "zero above the last");
    }
    for (int i = 0; i < s.ntris; i++) {
        const spm_scene_material *m = &s.materials[s.tris[i].material];
        if (m->emit < 0)
            continue;
        double xyz[3];
        spm_xyz_emission(&s.colours[m->emit].s, xyz);
        double z = s.tris[i].p[0][2];
        if (fabs(z - 1) < 1e-6)
            CHECK_NEAR(xyz[1], 3.0, 1e-9, "a constant radiance 3 has luminance 3");
        if (fabs(z + 50) < 1e-6)
            CHECK_NEAR(xyz[1], 1.0, 1e-3, "rgb radiance 1: luminance 1");
        if (fabs(z - 2) < 1e-6) { /* Planck at 5000 K, 560.5 nm, per nm */
            double l = 560.5e-9, h = 6.62607015e-34, c = 2.99792458e8, k = 1.380649e-23;
            double b = 1e-9 * 2 * h * c * c / pow(l, 5) / (exp(h * c / (l * k * 5000)) - 1);
            CHECK_NEAR(s.colours[m->emit].s.nm1[180] / b, 1.0, 1e-6, "blackbody per nm");
        }
    }
    CHECK(s.bg_up >= 0 && s.bg_up == s.bg_down, "constant: both backgrounds");
    if (s.bg_up >= 0)
        CHECK_NEAR(s.colours[s.bg_up].s.nm1[123], 0.5, 1e-9, "background radiance");
    spm_scene_free(&s);
}

static void write_white_map(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/white.hdr", dir);
    CHECK(envmap_write_hdr(path, 8, 4, envmap_white) == 0, "write a map");
}

/* envmap: specmip's map, its file, scale and to_world's turn about +y; a
 * tilt is left out (warned) */
static void test_envmap(void)
{
    spm_scene s;
    spm_error err;
    write_white_map();
    int rc = load("envmap.xml", "<emitter type=\"envmap\"><string name=\"filename\" "
                  "value=\"white.hdr\"/><float name=\"scale\" value=\"2\"/>"
                  "<transform name=\"to_world\"><rotate y=\"1\" angle=\"30\"/></transform>"
                  "</emitter>", &s, &err);
    CHECK(rc == 0, "envmap: %s", err.msg);
    if (rc)
        return;
    CHECK(s.env && s.bg_up < 0 && s.bg_down < 0, "envmap: the map is the background");
    if (s.env) {
        CHECK_NEAR(s.env->scale, 2.0, 1e-12, "envmap: scale");
        CHECK_NEAR(s.env->rotate, 30.0, 1e-9, "envmap: to_world's turn about +y");
        CHECK(s.env->ncolours == 1 && fabs(s.env->lum[0] - 2.0f) < 1e-5f,
              "envmap: a white map of luminance 2 (%g)", (double)s.env->lum[0]);
    }
    spm_scene_free(&s);
    rc = load("envmap_tilt.xml", "<emitter type=\"envmap\"><string name=\"filename\" "
              "value=\"white.hdr\"/><transform name=\"to_world\"><rotate x=\"1\" "
              "angle=\"90\"/></transform></emitter>", &s, &err);
    CHECK(rc == 0 && s.env && fabs(s.env->rotate) < 1e-9, "envmap: a tilt left out: %s",
          rc ? err.msg : "");
    if (!rc)
        spm_scene_free(&s);
}

/* cube: 12 triangles facing out; disk faces +z; sphere at its center and radius */
static void test_shapes(void)
{
    spm_scene s;
    spm_error err;
    int rc = load("g.xml", "<shape type=\"cube\"><bsdf type=\"diffuse\"/></shape>"
                           "<shape type=\"disk\"><transform name=\"to_world\"><translate z=\"5\"/>"
                           "</transform><bsdf type=\"plastic\"><boolean name=\"nonlinear\" "
                           "value=\"true\"/></bsdf></shape>"
                           "<shape type=\"sphere\"><point name=\"center\" value=\"0, 10, 0\"/>"
                           "<float name=\"radius\" value=\"2\"/><bsdf type=\"conductor\"/></shape>",
                  &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    int cube = 0, disk = 0, sphere = 0, out = 0;
    double rmin = 1e9, rmax = 0;
    for (int i = 0; i < s.ntris; i++) {
        const spm_scene_tri *t = &s.tris[i];
        int type = s.materials[t->material].type;
        if (s.materials[t->material].emit >= 0)
            continue;
        double n[3], c[3];
        normal_of(t, n);
        for (int k = 0; k < 3; k++)
            c[k] = (t->p[0][k] + t->p[1][k] + t->p[2][k]) / 3;
        if (type == SPM_MAT_LAMBERT) {
            cube++;
            out += n[0] * c[0] + n[1] * c[1] + n[2] * c[2] > 0;
        } else if (type == SPM_MAT_COATED) {
            disk += n[2] > 0 && fabs(t->p[0][2] - 5) < 1e-6;
        } else {
            sphere++;
            for (int v = 0; v < 3; v++) {
                double r = sqrt(t->p[v][0] * t->p[v][0] + (t->p[v][1] - 10) * (t->p[v][1] - 10) +
                                t->p[v][2] * t->p[v][2]);
                rmin = fmin(rmin, r), rmax = fmax(rmax, r);
            }
            out += (n[0] * c[0] + n[1] * (c[1] - 10) + n[2] * c[2]) > 0;
        }
    }
    CHECK(cube == 12, "cube: %d triangles", cube);
    CHECK(disk == 128, "disk: %d triangles facing +z at z 5", disk);
    CHECK(sphere > 1000, "sphere tessellated: %d", sphere);
    CHECK(out == cube + sphere, "every cube and sphere face faces out: %d of %d", out,
          cube + sphere);
    CHECK_NEAR(rmin, 2, 1e-5, "sphere radius");
    CHECK_NEAR(rmax, 2, 1e-5, "sphere radius");
    spm_scene_free(&s);
}

/* Files: a spectrum file, an OBJ (through <path>), a PLY; flip_normals turns the front */
static void test_files(void)
{
    mkdir(strcat(strcpy((char[400]){0}, dir), "/sub"), 0700);
    write_file("sub/r.spd", "# lambda value\n420 0.2\n520 0.6\n");
    write_file("sub/tri.obj", "v 0 0 7\nv 1 0 7\nv 0 1 7\nf 1 2 3\n");
    write_file("quad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 1\n"
                           "property list uchar int vertex_indices\nend_header\n"
                           "0 0 8\n1 0 8\n0 1 8\n3 0 1 2\n");
    spm_scene s;
    spm_error err;
    int rc = load("f.xml", "<path value=\"sub\"/>"
                           "<shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/>"
                           "<bsdf type=\"diffuse\"><spectrum name=\"reflectance\" "
                           "filename=\"sub/r.spd\"/></bsdf></shape>"
                           "<shape type=\"ply\"><string name=\"filename\" value=\"quad.ply\"/>"
                           "<boolean name=\"flip_normals\" value=\"true\"/></shape>", &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    int obj = 0, ply = 0;
    for (int i = 0; i < s.ntris; i++) {
        const spm_scene_tri *t = &s.tris[i];
        double n[3];
        normal_of(t, n);
        if (fabs(t->p[0][2] - 7) < 1e-6) {
            obj++;
            CHECK(n[2] > 0, "the OBJ's winding is its front");
            CHECK_NEAR(refl_at(&s, t, 470), 0.2 + 0.4 * 50.5 / 100, 1e-9, "spectrum file");
            CHECK_NEAR(refl_at(&s, t, 600), 0.0, 1e-12, "zero past the file's last sample");
        } else if (fabs(t->p[0][2] - 8) < 1e-6) {
            ply++;
            CHECK(n[2] < 0, "flip_normals turns the PLY's front");
        }
    }
    CHECK(obj == 1 && ply == 1, "obj %d, ply %d", obj, ply);
    spm_scene_free(&s);
}

/* Errors: exit-2 messages name file:line:col and the problem. */
static void test_errors(void)
{
    static const struct {
        const char *body, *want;
    } cases[] = {
        {"<shape type=\"rectangle\">", "malformed XML"},
        {"<bsdf type=\"velvet\" id=\"v\"/><shape type=\"cube\"><ref id=\"v\"/></shape>",
         "unknown BSDF type \"velvet\""},
        {"<shape type=\"cube\"><ref id=\"nothing\"/></shape>", "no element has this id"},
        {"<shape type=\"cube\"><bsdf type=\"diffuse\"><float name=\"reflectance\" "
         "value=\"$undefined\"/></bsdf></shape>", "parameter '$undefined' is not defined"},
        {"<include filename=\"e.xml\"/>", "include cycle"},
        {"<include filename=\"../outside.xml\"/>", "leads outside"},
        {"<shape type=\"obj\"><string name=\"filename\" value=\"none.obj\"/></shape>",
         "not found"},
        {"<emitter type=\"laser\"/>", "unknown emitter type"},
        {"<shape type=\"cube\"><float name=\"flip_normals\" value=\"1\"/></shape>",
         "not one of boolean"},
        {"<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"1 2\"/>"
         "</transform></shape>", "one or three numbers"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        spm_scene s;
        spm_error err;
        err.msg[0] = 0;
        int rc = load("e.xml", cases[i].body, &s, &err);
        CHECK(rc == 1, "case %zu: loads", i);
        CHECK(strstr(err.msg, "e.xml:") && strstr(err.msg, cases[i].want),
              "case %zu: want 'e.xml:' and '%s', got '%s'", i, cases[i].want, err.msg);
        if (!rc)
            spm_scene_free(&s);
    }
    /* what is not rendered is a warning, and an error under --strict */
    const char *warned[] = {"<shape type=\"cube\"><bsdf type=\"thindielectric\"/></shape>",
                            "<emitter type=\"projector\"/>", "<shape type=\"serialized\"/>",
                            "<shape type=\"cube\"><bsdf type=\"mask\"><bsdf type=\"diffuse\"/>"
                            "</bsdf></shape>"};
    const char *named[] = {"<bsdf type=\"thindielectric\">", "<emitter type=\"projector\">",
                           "<shape type=\"serialized\">", "<bsdf type=\"mask\">"};
    for (int i = 0; i < 4; i++) {
        spm_scene s;
        spm_error err;
        int rc = load("w.xml", warned[i], &s, &err);
        CHECK(rc == 0, "warned %d loads: %s", i, err.msg);
        if (!rc)
            spm_scene_free(&s);
        spm_scene_strict = 1;
        rc = load("w.xml", warned[i], &s, &err);
        spm_scene_strict = 0;
        CHECK(rc == 1 && strstr(err.msg, named[i]) && strstr(err.msg, "--strict"),
              "strict %d: '%s'", i, rc ? err.msg : "loaded");
        if (!rc)
            spm_scene_free(&s);
    }
}

int main(void)
{
    spm_quiet_warnings = 1;
    char root[256];
    snprintf(root, sizeof root, "/tmp/spm_test_mitsuba_XXXXXX");
    if (!mkdtemp(root))
        return 1;
    snprintf(dir, sizeof dir, "%s/in", root);
    mkdir(dir, 0700);
    char out[512];
    snprintf(out, sizeof out, "%s/outside.xml", root);
    FILE *f = fopen(out, "w");
    fputs("<scene version=\"3.0.0\"/>", f);
    fclose(f);
    test_transforms();
    test_camera();
    test_params_refs();
    test_bsdfs();
    test_spectra();
    test_shapes();
    test_envmap();
    test_files();
    test_errors();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", root);
    if (system(cmd))
        return 1;
    TEST_END();
}
