/* The CPU reference's camera (kernels/camera.clh: the formulas and their
 * measure). */
#include "refcpu_camera.h"
#include <math.h>
#include "geometry_vec3.h"

/* Concentric map of the unit square onto the unit disk (Shirley and Chiu 1997). */
static void camera_disk(float u, float v, float l[2])
{
    float a = 2.0f * u - 1.0f, b = 2.0f * v - 1.0f, r, phi;
    if (a == 0.0f && b == 0.0f) {
        l[0] = l[1] = 0.0f;
        return;
    }
    if (fabsf(a) > fabsf(b))
        r = a, phi = (SPM_PI_F / 4.0f) * (b / a);
    else
        r = b, phi = SPM_PI_F / 2.0f - (SPM_PI_F / 4.0f) * (a / b);
    l[0] = r * cosf(phi);
    l[1] = r * sinf(phi);
}

/* the lens point of lens sample (lu, lv): eye + r (right l0 + up l1) */
static void lens_point(const spm_camera *cam, float lu, float lv, float o[3])
{
    float l[2];
    camera_disk(lu, lv, l);
    l[0] *= cam->lens_radius;
    l[1] *= cam->lens_radius;
    for (int i = 0; i < 3; i++)
        o[i] = cam->eye[i] + (cam->right[i] * l[0] + cam->up[i] * l[1]);
}

void spm_ref_camera_ray(const spm_camera *cam, float cx, float cy, float lu, float lv, float o[3],
                        float d[3])
{
    float sy = cy * (float)cam->height / (float)cam->width;
    float s[3], t[3];
    for (int i = 0; i < 3; i++)
        s[i] = cam->tan_half * (cam->right[i] * cx + cam->up[i] * sy);
    if (cam->ortho) {
        for (int i = 0; i < 3; i++)
            o[i] = cam->eye[i] + s[i], d[i] = cam->dir[i];
        return;
    }
    for (int i = 0; i < 3; i++)
        o[i] = cam->eye[i], t[i] = cam->dir[i] + s[i];
    v3_normalise(d, t);
    if (cam->lens_radius > 0.0f) {
        float focus[3];
        for (int i = 0; i < 3; i++)
            focus[i] = cam->eye[i] + cam->focus * t[i];
        lens_point(cam, lu, lv, o);
        v3_sub(t, focus, o);
        v3_normalise(d, t);
    }
}

/* the film point the ray images to and its cos theta; 0: none */
static int camera_film(const spm_camera *cam, const float o[3], const float d[3], float film[2],
                       float *cos_t)
{
    *cos_t = v3_dot(d, cam->dir);
    if (cam->ortho || !(*cos_t > 0.0f))
        return 0;
    float q[3];
    for (int i = 0; i < 3; i++) {
        q[i] = d[i] / *cos_t;
        if (cam->lens_radius > 0.0f)
            q[i] = (o[i] - cam->eye[i] + q[i] * cam->focus) / cam->focus;
    }
    float aspect = (float)cam->height / (float)cam->width;
    film[0] = v3_dot(q, cam->right) / cam->tan_half;
    film[1] = v3_dot(q, cam->up) / (cam->tan_half * aspect);
    return fabsf(film[0]) <= 1.0f && fabsf(film[1]) <= 1.0f;
}

static float film_area(const spm_camera *cam)
{
    return 4.0f * cam->tan_half * cam->tan_half * (float)cam->height / (float)cam->width;
}

static float lens_area(const spm_camera *cam)
{
    return cam->lens_radius > 0.0f ? SPM_PI_F * cam->lens_radius * cam->lens_radius : 1.0f;
}

float spm_ref_camera_We(const spm_camera *cam, const float o[3], const float d[3], float film[2])
{
    float c;
    if (!camera_film(cam, o, d, film, &c))
        return 0.0f;
    float c2 = c * c;
    return 1.0f / (film_area(cam) * lens_area(cam) * (c2 * c2));
}

void spm_ref_camera_pdf_We(const spm_camera *cam, const float o[3], const float d[3],
                           float *pdf_pos, float *pdf_dir)
{
    float film[2], c;
    *pdf_pos = *pdf_dir = 0.0f;
    if (!camera_film(cam, o, d, film, &c))
        return;
    *pdf_pos = 1.0f / lens_area(cam);
    *pdf_dir = 1.0f / (film_area(cam) * c * c * c);
}

float spm_ref_camera_sample_Wi(const spm_camera *cam, const float p[3], float lu, float lv,
                               float wi[3], float *dist, float *pdf, float film[2])
{
    float lens[3] = {cam->eye[0], cam->eye[1], cam->eye[2]}, v[3], back[3];
    *pdf = 0.0f;
    if (cam->ortho)
        return 0.0f;
    if (cam->lens_radius > 0.0f)
        lens_point(cam, lu, lv, lens);
    v3_sub(v, lens, p);
    *dist = sqrtf(v3_dot(v, v));
    if (!(*dist > 0.0f))
        return 0.0f;
    for (int i = 0; i < 3; i++)
        wi[i] = v[i] / *dist, back[i] = -wi[i];
    float c = fabsf(v3_dot(wi, cam->dir));
    *pdf = *dist * *dist / (c * lens_area(cam));
    return spm_ref_camera_We(cam, lens, back, film);
}
