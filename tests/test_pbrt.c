/* pbrt-v4 files read by value (host/scene/pbrt_*.c): transforms and the
 * camera's handedness, named materials, instancing, parameter types, the
 * three rgb lifts, light normalisation, orientation; scenes written here. */
#include "colour.h"
#include "csv.h"
#include "geometry.h"
#include "materials.h"
#include "scene.h"
#include "testutil.h"
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[256];

/* A light so that every scene is complete; `body` after WorldBegin. */
static const char *write_scene(const char *name, const char *head, const char *body)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    fprintf(f, "%s\nWorldBegin\n%s\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
               "Shape \"trianglemesh\" \"point3 P\" [-1 9 -1 1 9 -1 0 9 1] \"integer indices\" [0 2 1]\n"
               "AttributeEnd\n", head, body);
    fclose(f);
    return path;
}

static int load(const char *name, const char *head, const char *body, spm_scene *s, spm_error *err)
{
    return spm_scene_load(write_scene(name, head, body), s, err);
}

static const spm_scene_tri *first_plain(const spm_scene *s)
{
    for (int i = 0; i < s->ntris; i++)
        if (s->materials[s->tris[i].material].emit < 0)
            return &s->tris[i];
    return NULL;
}

static void test_transforms(void)
{
    spm_scene s;
    spm_error err;
    /* Translate then Scale then Rotate 90 about z: p -> T S R p */
    int rc = load("t.pbrt", "", "Translate 1 2 3 Scale 2 2 2 Rotate 90 0 0 1\n"
                  "Shape \"trianglemesh\" \"point3 P\" [1 0 0 0 1 0 0 0 1] \"integer indices\" [0 1 2]",
                  &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    const spm_scene_tri *t = rc ? NULL : first_plain(&s);
    CHECK(t != NULL, "a triangle");
    if (t) { /* (1,0,0) -> R (0,1,0) -> S (0,2,0) -> T (1,4,3) */
        CHECK_NEAR(t->p[0][0], 1, 1e-6, "x");
        CHECK_NEAR(t->p[0][1], 4, 1e-6, "y");
        CHECK_NEAR(t->p[0][2], 3, 1e-6, "z");
    }
    spm_scene_free(&s);
    /* Transform is given column by column: its translation is numbers 13..15 */
    rc = load("m.pbrt", "", "Transform [1 0 0 0 0 1 0 0 0 0 1 0 5 6 7 1]\n"
              "ConcatTransform [2 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]\n"
              "Shape \"trianglemesh\" \"point3 P\" [1 0 0 0 1 0 0 0 1] \"integer indices\" [0 1 2]",
              &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    t = rc ? NULL : first_plain(&s);
    if (t) {
        CHECK_NEAR(t->p[0][0], 7, 1e-6, "x = 5 + 2 * 1");
        CHECK_NEAR(t->p[0][1], 6, 1e-6, "y");
    }
    spm_scene_free(&s);
}

/* pbrt's camera: LookAt's frame, fov across the shorter side; a Scale -1 1 1
 * before it mirrors the image (right-handed tools' exports). */
static void test_camera(void)
{
    const char *cam[2] = {"Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\n"
                          "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30",
                          "Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\n"
                          "Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\n"
                          "Camera \"perspective\" \"float fov\" 30"};
    for (int k = 0; k < 2; k++) {
        spm_scene s;
        spm_error err;
        int rc = load("c.pbrt", cam[k], "", &s, &err);
        CHECK(rc == 0, "%s", err.msg);
        if (rc)
            continue;
        spm_camera c = spm_camera_of_scene(&s);
        CHECK_NEAR(c.eye[2], -5, 1e-6, "eye z");
        CHECK_NEAR(c.dir[2], 1, 1e-6, "looks along +z");
        CHECK_NEAR(c.up[1], 1, 1e-6, "up y");
        /* pbrt: camera x is up x dir = +x, so image right is world +x; mirrored: -x */
        CHECK_NEAR(c.right[0], k ? -1 : 1, 1e-6, "right x");
        CHECK(s.mirror == k, "mirror %d", s.mirror);
        /* 30 degrees across the 100-pixel side: horizontal tan = tan(15) * 2 */
        CHECK_NEAR(c.tan_half, tan(15 * M_PI / 180) * 2, 1e-6, "tan_half");
        spm_scene_free(&s);
    }
}

static void test_materials(void)
{
    spm_scene s;
    spm_error err;
    int rc = load("n.pbrt", "",
                  "MakeNamedMaterial \"grey\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n"
                  "MakeNamedMaterial \"silver\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Ag-eta\"\n"
                  "  \"spectrum k\" \"metal-Ag-k\" \"float roughness\" 0.25\n"
                  "MakeNamedMaterial \"bk7\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-BK7\"\n"
                  "MakeNamedMaterial \"water\" \"string type\" \"dielectric\" \"float eta\" 1.33\n"
                  "MakeNamedMaterial \"metal\" \"string type\" \"conductor\" \"rgb eta\" [2 2 2] \"rgb k\" [3 2 1]\n"
                  "NamedMaterial \"grey\"\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
                  "NamedMaterial \"silver\"\nShape \"trianglemesh\" \"point3 P\" [0 0 1 1 0 1 0 1 1]\n"
                  "NamedMaterial \"bk7\"\nShape \"trianglemesh\" \"point3 P\" [0 0 2 1 0 2 0 1 2]\n"
                  "NamedMaterial \"water\"\nShape \"trianglemesh\" \"point3 P\" [0 0 3 1 0 3 0 1 3]\n"
                  "NamedMaterial \"metal\"\nShape \"trianglemesh\" \"point3 P\" [0 0 4 1 0 4 0 1 4]\n",
                  &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    const spm_scene_material *m[5];
    for (int z = 0; z < 5; z++)
        for (int i = 0; i < s.ntris; i++)
            if (s.tris[i].p[0][2] == z && s.materials[s.tris[i].material].emit < 0)
                m[z] = &s.materials[s.tris[i].material];
    /* the bounded lift: a grey is its constant */
    CHECK(m[0]->type == SPM_MAT_LAMBERT, "diffuse");
    CHECK_NEAR(s.colours[m[0]->refl].s.nm1[100], 0.5, 1e-9, "grey 0.5");
    CHECK(m[1]->type == SPM_MAT_CONDUCTOR && m[1]->col2 >= 0, "conductor with k");
    CHECK_NEAR(m[1]->p[SPM_COND_P_ALPHA], 0.5, 1e-12, "alpha = sqrt(roughness 0.25)");
    /* silver's eta at 550 nm is near 0.06 (metal_Ag_eta.csv): a named spectrum, not a grey */
    CHECK(s.colours[m[1]->refl].s.nm1[170] < 0.2, "Ag eta %g", s.colours[m[1]->refl].s.nm1[170]);
    CHECK(m[2]->type == SPM_MAT_DIELECTRIC && m[2]->p[SPM_DIEL_P_DISP] >= 1, "BK7 disperses");
    CHECK_NEAR(m[2]->p[SPM_DIEL_P_IOR], 1.5168, 2e-4, "BK7 n_d (Schott: 1.51680)");
    CHECK(s.ndisp == 1, "one index table, %d", s.ndisp);
    CHECK_NEAR(m[3]->p[SPM_DIEL_P_IOR], 1.33, 1e-12, "water");
    CHECK(m[3]->p[SPM_DIEL_P_DISP] == 0, "a constant eta does not disperse");
    /* the unbounded lift: eta 2 stays 2 (a bounded lift would clip it to 1), k 3..1 peaks near 3 */
    CHECK_NEAR(s.colours[m[4]->refl].s.nm1[200], 2.0, 1e-9, "rgb eta 2");
    CHECK(spm_spectrum_max(&s.colours[m[4]->col2].s) > 2.5, "rgb k (3 2 1) unbounded: max %g",
          spm_spectrum_max(&s.colours[m[4]->col2].s));
    spm_scene_free(&s);
}

/* The illuminant lift and the light normalisation: rgb L (1 1 1) is D65 at
 * luminance 1; a blackbody L is normalised to luminance 1 before scale. */
static void test_lights(void)
{
    spm_scene s;
    spm_error err;
    int rc = load("l.pbrt", "",
                  "AttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 3000 \"float scale\" 2.5\n"
                  "  \"bool twosided\" true\n"
                  "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\nAttributeEnd\n", &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    spm_spectrum d65;
    char path[4096];
    CHECK(spm_spectrum_load(spm_data_path("spectra/illuminant_D65.csv", path, sizeof path), NULL,
                            SPM_KIND_EMISSION, &d65, &err) == 0, "%s", err.msg);
    int seen = 0;
    for (int i = 0; i < s.nmaterials; i++) {
        const spm_scene_material *m = &s.materials[i];
        if (m->emit < 0)
            continue;
        double xyz[3];
        spm_xyz_emission(&s.colours[m->emit].s, xyz);
        if (m->flags) { /* the blackbody: luminance 2.5, both faces */
            CHECK_NEAR(xyz[1], 2.5, 1e-6, "blackbody L, luminance = scale");
            seen |= 1;
        } else { /* rgb (1 1 1): Y 1, the shape of D65 */
            CHECK_NEAR(xyz[1], 1.0, 1e-3, "rgb L (1 1 1), luminance 1");
            double r0 = s.colours[m->emit].s.nm1[60] / d65.nm1[60];
            double r1 = s.colours[m->emit].s.nm1[300] / d65.nm1[300];
            CHECK_NEAR(r1 / r0, 1.0, 1e-3, "rgb white L is D65's shape");
            seen |= 2;
        }
    }
    CHECK(seen == 3, "both lights, %d", seen);
    spm_scene_free(&s);
}

/* Instances: each ObjectInstance adds the object's shapes under its transform. */
static void test_instances(void)
{
    spm_scene s;
    spm_error err;
    int rc = load("i.pbrt", "",
                  "ObjectBegin \"tri\"\nTranslate 0 0 1\n"
                  "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\nObjectEnd\n"
                  "AttributeBegin\nTranslate 10 0 0\nObjectInstance \"tri\"\nAttributeEnd\n"
                  "AttributeBegin\nTranslate 20 0 0\nObjectInstance \"tri\"\nAttributeEnd\n",
                  &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    int found[2] = {0, 0}, plain = 0;
    for (int i = 0; i < s.ntris; i++) {
        if (s.materials[s.tris[i].material].emit >= 0)
            continue;
        plain++;
        for (int k = 0; k < 2; k++)
            found[k] |= s.tris[i].p[0][0] == 10 * (k + 1) && s.tris[i].p[0][2] == 1;
    }
    CHECK(plain == 2 && found[0] && found[1], "%d instanced triangles at x 10 and 20, z 1", plain);
    spm_scene_free(&s);
}

/* Orientation: the winding's normal; vertex normals decide when given;
 * ReverseOrientation turns either. */
static void test_orientation(void)
{
    const char *body[3] = {
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]",
        "ReverseOrientation\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]",
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 -1 0 0 -1 0 0 -1]"};
    for (int k = 0; k < 3; k++) {
        spm_scene s;
        spm_error err;
        int rc = load("o.pbrt", "", body[k], &s, &err);
        CHECK(rc == 0, "%s", err.msg);
        const spm_scene_tri *t = rc ? NULL : first_plain(&s);
        if (!t)
            continue;
        double e1[2] = {t->p[1][0] - t->p[0][0], t->p[1][1] - t->p[0][1]};
        double e2[2] = {t->p[2][0] - t->p[0][0], t->p[2][1] - t->p[0][1]};
        double nz = e1[0] * e2[1] - e1[1] * e2[0];
        CHECK(k == 0 ? nz > 0 : nz < 0, "case %d: front face z %g", k, nz);
        spm_scene_free(&s);
    }
}

/* Wrong parameter types and counts are errors naming file:line:col. */
static void test_param_errors(void)
{
    static const struct {
        const char *body, *expect;
    } cases[] = {
        {"Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1]", "multiple of 3"},
        {"Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1.5 2]",
         "whole number"},
        {"Material \"diffuse\" \"rgb reflectance\" [0.5 0.5]", "exactly 3"},
        {"Material \"diffuse\" \"float reflectance\" \"x\"", "a number"},
        {"Shape \"sphere\" \"string radius\" \"1\"", "cannot be of type 'string'"},
        {"Shape \"trianglemesh\" \"point9 P\" [0]", "unknown parameter type 'point9'"},
        {"Material \"plastic\"", "unknown material type"},
        {"Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]",
         "outside the 3 points"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        spm_scene s;
        spm_error err = {{0}};
        int rc = load("e.pbrt", "", cases[i].body, &s, &err);
        CHECK(rc != 0 && strstr(err.msg, cases[i].expect) && strstr(err.msg, "e.pbrt:"),
              "case %zu: '%s'", i, err.msg);
        spm_scene_free(&s);
    }
}

/* Include and Import read a file in place, relative to the including file;
 * named materials and coordinate systems carry across. */
static void test_include(void)
{
    char sub[600], path[700];
    snprintf(sub, sizeof sub, "%s/sub", dir);
    CHECK(mkdir(sub, 0755) == 0, "mkdir %s", sub);
    snprintf(path, sizeof path, "%s/mats.pbrt", sub);
    FILE *f = fopen(path, "w");
    fprintf(f, "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.5 0 0]\n"
               "Include \"geom.pbrt\"\n");
    fclose(f);
    snprintf(path, sizeof path, "%s/geom.pbrt", sub);
    f = fopen(path, "w");
    fprintf(f, "Translate 0 0 7\nCoordinateSystem \"seven\"\n");
    fclose(f);
    spm_scene s;
    spm_error err;
    int rc = load("inc.pbrt", "", "AttributeBegin\nInclude \"sub/mats.pbrt\"\nAttributeEnd\n"
                  "CoordSysTransform \"seven\"\nImport \"sub/geom.pbrt\"\nNamedMaterial \"red\"\n"
                  "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]", &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    const spm_scene_tri *t = rc ? NULL : first_plain(&s);
    if (t) { /* 7 from the named system, 7 more from the second include's Translate */
        CHECK_NEAR(t->p[0][2], 14, 1e-6, "z");
        const spm_spectrum *r = &s.colours[s.materials[t->material].refl].s;
        CHECK(r->nm1[300] > 3 * r->nm1[80], "the included red: %g at 680 nm, %g at 460 nm",
              r->nm1[300], r->nm1[80]);
    }
    spm_scene_free(&s);
}

/* A sphere is tessellated: 48 rings of 96, less the poles' degenerate halves. */
static void test_sphere(void)
{
    spm_scene s;
    spm_error err;
    int rc = load("s.pbrt", "", "Shape \"sphere\" \"float radius\" 2", &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    int n = 0;
    double rmin = 1e9, rmax = 0;
    for (int i = 0; i < s.ntris; i++)
        if (s.materials[s.tris[i].material].emit < 0) {
            n++;
            for (int v = 0; v < 3; v++) {
                const float *p = s.tris[i].p[v];
                double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                rmin = fmin(rmin, r);
                rmax = fmax(rmax, r);
            }
        }
    CHECK(n == 48 * 96 * 2 - 2 * 96, "%d triangles", n);
    CHECK_NEAR(rmin, 2, 1e-5, "vertices on the sphere");
    CHECK_NEAR(rmax, 2, 1e-5, "vertices on the sphere");
    spm_scene_free(&s);
}

/* LightSource by value: a point light at the CTM's image of `from`, its
 * power over 4 pi the intensity, its blackbody at luminance `scale`; a
 * distant light travelling from `from` to `to` through the CTM, its
 * illuminance the irradiance; a constant infinite light the background at
 * illuminance / pi; a spot at `from` aimed at `to`, its smoothstep between
 * coneangle - conedelta and coneangle, its power over pbrt-v4's k_e = 2 pi
 * ((1 - cos start) + (cos start - cos end) / 2) the intensity; an infinite
 * map's file warned, not made. */
static void test_light_sources(void)
{
    spm_scene s;
    spm_error err;
    int rc = load("ls.pbrt", "",
                  "AttributeBegin\nTranslate 1 2 3\n"
                  "LightSource \"point\" \"blackbody I\" 3000 \"float scale\" 2 \"float power\" 20\n"
                  "  \"point3 from\" [0 1 0]\n"
                  "Rotate 90 0 0 1\n"
                  "LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [2 0 0]\n"
                  "  \"float illuminance\" 3\nAttributeEnd\n"
                  "LightSource \"spot\" \"rgb I\" [1 1 1] \"float power\" 7 \"float coneangle\" 40\n"
                  "  \"float conedelta\" 10 \"point3 from\" [0 2 0] \"point3 to\" [0 2 3]\n"
                  "LightSource \"infinite\" \"string filename\" \"sky.exr\"\n"
                  "LightSource \"infinite\" \"rgb L\" [1 1 1] \"float illuminance\" 6.2831853\n",
                  &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    CHECK(s.nlights == 3, "three lights made (point, distant, spot): %d", s.nlights);
    for (int i = 0; i < s.nlights && s.nlights == 3; i++) {
        const spm_scene_light *l = &s.lights[i];
        double xyz[3];
        spm_xyz_emission(&s.colours[l->colour].s, xyz);
        if (l->kind == SPM_LIGHT_POINT) { /* (0 1 0) -> (1 3 3); I = 20 / (4 pi) x 2 */
            CHECK_NEAR(l->p[SPM_LIGHT_P_POS + 0], 1, 1e-6, "point x");
            CHECK_NEAR(l->p[SPM_LIGHT_P_POS + 1], 3, 1e-6, "point y");
            CHECK_NEAR(l->p[SPM_LIGHT_P_POS + 2], 3, 1e-6, "point z");
            CHECK_NEAR(xyz[1] * l->p[SPM_LIGHT_P_SCALE], 2.0 * 20 / (4 * M_PI), 1e-5,
                       "point intensity's luminance");
        } else if (l->kind == SPM_LIGHT_SPOT) { /* aimed along +z; I = 7 / k_e (D65 at luminance 1) */
            double cs = cos(30 * M_PI / 180), ce = cos(40 * M_PI / 180);
            double k_e = 2 * M_PI * ((1 - cs) + (cs - ce) / 2);
            CHECK_NEAR(l->p[SPM_LIGHT_P_POS + 1], 2, 1e-6, "spot y");
            CHECK_NEAR(l->p[SPM_LIGHT_P_DIR + 2], 1, 1e-6, "spot aimed along +z");
            CHECK_NEAR(l->p[SPM_LIGHT_P_A], 40 * M_PI / 180, 1e-6, "spot cone angle");
            CHECK_NEAR(l->p[SPM_LIGHT_P_B], 30 * M_PI / 180, 1e-6, "spot falloff start");
            CHECK(l->p[SPM_LIGHT_P_D] == SPM_SPOT_SMOOTHSTEP, "spot shape smoothstep: %g",
                  l->p[SPM_LIGHT_P_D]);
            CHECK_NEAR(xyz[1] * l->p[SPM_LIGHT_P_SCALE], 7 / k_e, 1e-4, "spot intensity's Y");
        } else { /* +x turned 90 degrees about z: +y; E = 3 (D65 at luminance 1) */
            CHECK(l->kind == SPM_LIGHT_DISTANT, "the second a distant light: %d", l->kind);
            CHECK_NEAR(l->p[SPM_LIGHT_P_DIR + 0], 0, 1e-6, "distant x");
            CHECK_NEAR(l->p[SPM_LIGHT_P_DIR + 1], 1, 1e-6, "distant y");
            CHECK_NEAR(l->p[SPM_LIGHT_P_DIR + 2], 0, 1e-6, "distant z");
            CHECK_NEAR(xyz[1] * l->p[SPM_LIGHT_P_SCALE], 3.0, 1e-3, "distant irradiance's Y");
        }
    }
    CHECK(s.bg_up >= 0 && s.bg_up == s.bg_down, "a uniform background: %d %d", s.bg_up,
          s.bg_down);
    if (s.bg_up >= 0) {
        double xyz[3];
        spm_xyz_emission(&s.colours[s.bg_up].s, xyz);
        CHECK_NEAR(xyz[1], 2.0, 1e-3, "infinite L = illuminance / pi");
    }
    spm_scene_free(&s);
}

int main(void)
{
    spm_quiet_warnings = 1;
    snprintf(dir, sizeof dir, "/tmp/spm_test_pbrt_XXXXXX");
    if (!mkdtemp(dir))
        return 1;
    test_transforms();
    test_camera();
    test_materials();
    test_lights();
    test_light_sources();
    test_instances();
    test_orientation();
    test_param_errors();
    test_sphere();
    test_include();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd))
        return 1;
    TEST_END();
}
