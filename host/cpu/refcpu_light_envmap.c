/* The CPU reference's environment map kind (kernels/light_envmap.clh): an
 * equirectangular image, its texels a luminance and a palette node each,
 * interpolated bilinearly by drawing one of four texels, met by escaping
 * rays and sampled by the 2-D distribution of the interpolated luminance's
 * texel means x sin(theta) in g->env (spm_shared.h SPM_ENV_*); the
 * selection's last entry. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "geometry_vec3.h"
#include "refcpu.h"
#include "refcpu_lights.h"

/* SPECMIP_BENCH_ENV_UNIFORM=1 (bench/envmap_nee.sh): the map sampled
 * uniformly over the sphere instead of by its distribution, light samples
 * and MIS alike, the baseline its importance sampling is measured against. */
static int uniform(void)
{
    static _Thread_local int u = -1;
    if (u < 0) {
        const char *s = getenv("SPECMIP_BENCH_ENV_UNIFORM");
        u = s && !strcmp(s, "1");
    }
    return u;
}

static spm_u32 env_w(const spm_emitter *e) { return (spm_u32)e->p[SPM_LIGHT_P_A]; }
static spm_u32 env_h(const spm_emitter *e) { return (spm_u32)e->p[SPM_LIGHT_P_B]; }

/* the colour standing for texel t's, one node of its palette cell's four
 * corners drawn by vertex j's SPM_DIM_ENV_NODE with the weights bilinear in
 * the texel's fractions times each node's luminance
 * (kernels/light_envmap.clh env_node) */
static spm_u32 env_id(const spm_geometry *g, const spm_emitter *e, spm_u32 t, const spm_ref_key *key,
                      spm_u32 j)
{
    spm_u32 w = env_w(e), h = env_h(e), n, f, s;
    memcpy(&n, &g->env[SPM_ENV_NODE(w, h) + t], sizeof n);
    memcpy(&f, &g->env[SPM_ENV_FRAC(w, h) + t], sizeof f);
    if (n == SPM_NONE)
        return SPM_NONE;
    const float *nd = g->env + SPM_ENV_NODES(w, h);
    memcpy(&s, &nd[0], sizeof s);
    spm_u32 k[4] = {n, n + 1u, n + s, n + s + 1u}, pick = n, id;
    float fa = (float)(f & 0xFFFFu) * (1.0f / 65535.0f), fb = (float)(f >> 16) * (1.0f / 65535.0f);
    float wt[4] = {(1.0f - fa) * (1.0f - fb), (1.0f - fa) * fb, fa * (1.0f - fb), fa * fb}, sum = 0.0f;
    for (int c = 0; c < 4; c++) {
        wt[c] *= nd[2u + 2u * k[c]];
        sum += wt[c];
    }
    float x = spm_ref_rnd(key, SPM_DIM_ENV(j, SPM_DIM_ENV_NODE)) * sum;
    for (int c = 0; c < 4; c++)
        if (wt[c] > 0.0f) {
            pick = k[c];
            if (x < wt[c])
                break;
            x -= wt[c];
        }
    memcpy(&id, &nd[1u + 2u * pick], sizeof id);
    return id;
}

/* the last k with cdf[k] <= u < cdf[k+1] among cdf[0, n] */
static spm_u32 env_search(const float *cdf, spm_u32 n, float u)
{
    spm_u32 lo = 0, hi = n - 1u;
    while (lo < hi) {
        spm_u32 mid = (lo + hi + 1u) >> 1;
        if (cdf[mid] <= u)
            lo = mid;
        else
            hi = mid - 1u;
    }
    return lo;
}

/* a direction of the distribution from u1 (row) and u2 (column): its map
 * coordinates uv, its texel of the distribution *c, sin(theta) *st; returns
 * its density in (u, v) */
static float env_sample_dir(const spm_geometry *g, const spm_emitter *e, float u1, float u2,
                            float d[3], float uv[2], spm_u32 *c, float *st)
{
    spm_u32 w = env_w(e), h = env_h(e);
    const float *env = g->env;
    spm_u32 j = env_search(env, h, u1);
    float dv = (u1 - env[j]) / (env[j + 1u] - env[j]);
    const float *cond = env + SPM_ENV_COND(w, h) + j * (w + 1u);
    spm_u32 i = env_search(cond, w, u2);
    float du = (u2 - cond[i]) / (cond[i + 1u] - cond[i]);
    float u = ((float)i + du) / (float)w, v = ((float)j + dv) / (float)h;
    float theta = SPM_PI_F * v, phi = 2.0f * SPM_PI_F * u;
    float s = sinf(theta), cs = cosf(theta);
    float lx = s * sinf(phi), lz = -s * cosf(phi);
    float cr = e->p[SPM_LIGHT_P_DIR], sr = e->p[SPM_LIGHT_P_DIR + 1];
    d[0] = cr * lx + sr * lz;
    d[1] = cs;
    d[2] = cr * lz - sr * lx;
    uv[0] = u;
    uv[1] = v;
    *c = j * w + i;
    *st = s;
    return env[SPM_ENV_PDF(w, h) + *c];
}

/* the map coordinates uv of direction d; *c the texel it falls in, *st its
 * sin(theta) */
static void env_uv(const spm_emitter *e, const float d[3], float uv[2], spm_u32 *c, float *st)
{
    spm_u32 w = env_w(e), h = env_h(e);
    float cr = e->p[SPM_LIGHT_P_DIR], sr = e->p[SPM_LIGHT_P_DIR + 1];
    float lx = cr * d[0] - sr * d[2], lz = sr * d[0] + cr * d[2];
    float y = fminf(fmaxf(d[1], -1.0f), 1.0f);
    float u = atan2f(lx, -lz) * (0.5f / SPM_PI_F);
    if (u < 0.0f)
        u += 1.0f;
    float v = acosf(y) / SPM_PI_F;
    spm_u32 i = (spm_u32)(u * (float)w), j = (spm_u32)(v * (float)h);
    i = i < w - 1u ? i : w - 1u;
    j = j < h - 1u ? j : h - 1u;
    *st = sqrtf(fmaxf(0.0f, 1.0f - y * y));
    *c = j * w + i;
    uv[0] = u;
    uv[1] = v;
}

/* the texel standing for the bilinear interpolation at uv: along each
 * axis, centres at k + 1/2, the one below u w (v h) or the next with
 * probability the fraction, drawn by vertex j's SPM_DIM_ENV; columns wrap,
 * rows clamp */
static spm_u32 env_tap(const spm_emitter *e, const float uv[2], const spm_ref_key *k, spm_u32 j)
{
    int w = (int)env_w(e), h = (int)env_h(e);
    float x = uv[0] * (float)w - 0.5f, y = uv[1] * (float)h - 0.5f;
    float fx = floorf(x), fy = floorf(y);
    int i = (int)fx + (spm_ref_rnd(k, SPM_DIM_ENV(j, 0)) < x - fx ? 1 : 0);
    int r = (int)fy + (spm_ref_rnd(k, SPM_DIM_ENV(j, 1)) < y - fy ? 1 : 0);
    i = i < 0 ? i + w : i >= w ? i - w : i;
    r = r < 0 ? 0 : r > h - 1 ? h - 1 : r;
    return (spm_u32)(r * w + i);
}

spm_u32 spm_ref_light_escape_ENVMAP(const spm_geometry *g, const spm_emitter *e, float pmf,
                                    const float d[3], const spm_ref_key *k, spm_u32 j, float *scale,
                                    float *pdf)
{
    spm_u32 w = env_w(e), h = env_h(e), c;
    float st, uv[2];
    env_uv(e, d, uv, &c, &st);
    spm_u32 t = env_tap(e, uv, k, j);
    *scale = g->env[SPM_ENV_LUM(w, h) + t];
    *pdf = st > 0.0f ? pmf * g->env[SPM_ENV_PDF(w, h) + c] / (2.0f * SPM_PI_F * SPM_PI_F * st)
                     : 0.0f;
    if (uniform())
        *pdf = pmf / (4.0f * SPM_PI_F);
    return env_id(g, e, t, k, j);
}

/* the uniform baseline's direction: z = 1 - 2 u1, phi = 2 pi u2; its map
 * coordinates uv; returns its density 1 / (4 pi) */
static float uniform_dir(const spm_emitter *e, float u1, float u2, float d[3], float uv[2])
{
    float z = 1.0f - 2.0f * u1, r = sqrtf(fmaxf(0.0f, 1.0f - z * z)), st;
    spm_u32 c;
    d[0] = r * cosf(2.0f * SPM_PI_F * u2);
    d[1] = z;
    d[2] = r * sinf(2.0f * SPM_PI_F * u2);
    env_uv(e, d, uv, &c, &st);
    return 1.0f / (4.0f * SPM_PI_F);
}

int spm_ref_light_sample_ENVMAP(const spm_geometry *g, const spm_material *mats,
                                const spm_emitter *e, const spm_ref_key *k, spm_u32 dim,
                                const float x[3], spm_u32 hit, const spm_ref_hit *h,
                                spm_ref_lsample *ls)
{
    (void)mats;
    spm_u32 c;
    float st, uv[2];
    float u1 = spm_ref_rnd(k, dim + SPM_DIM_EPOINT_A), u2 = spm_ref_rnd(k, dim + SPM_DIM_EPOINT_B);
    float puv = env_sample_dir(g, e, u1, u2, ls->wi, uv, &c, &st);
    float pdf_sa = puv > 0.0f && st > 0.0f ? puv / (2.0f * SPM_PI_F * SPM_PI_F * st) : 0.0f;
    if (uniform())
        pdf_sa = uniform_dir(e, u1, u2, ls->wi, uv);
    /* vertex j of the path whose light sample this is (dim = SPM_DIM_VERTEX(j)) */
    spm_u32 j = (dim - SPM_DIM_VERTEX(0)) / SPM_DIMS_PER_VERTEX;
    spm_u32 t = env_tap(e, uv, k, j);
    spm_u32 colour = env_id(g, e, t, k, j);
    float cos_i = v3_dot(ls->wi, h->ng), cos_o = -v3_dot(h->d, h->ng);
    if (!(pdf_sa > 0.0f) || colour == SPM_NONE || (cos_i < 0.0f) != (cos_o < 0.0f))
        return 0;
    if (!spm_ref_light_unblocked(g, x, ls->wi, hit, INFINITY))
        return 0;
    ls->pdf = ls->pmf * pdf_sa;
    ls->g = ls->inv_pmf / pdf_sa;
    ls->scale = g->env[SPM_ENV_LUM(env_w(e), env_h(e)) + t];
    ls->colour = colour;
    ls->delta = 0;
    return 1;
}

/* pbrt-v4's SampleLe: a direction -w of the distribution (u[0], u[1]) from a
 * point of the disk of the scene's radius r facing it, r beyond the centre
 * along w (u[2], u[3]: density 1 / (pi r^2)) */
void spm_ref_light_sample_emission_ENVMAP(const spm_geometry *g, const spm_emitter *e,
                                          const float u[4], float o[3], float d[3], float *pdf_pos,
                                          float *pdf_dir)
{
    float w[3], a[3] = {1.0f, 0.0f, 0.0f}, b1[3], b2[3], c[3], st, uv[2];
    spm_u32 t;
    float puv = env_sample_dir(g, e, u[0], u[1], w, uv, &t, &st);
    if (fabsf(w[0]) > 0.9f)
        a[0] = 0.0f, a[1] = 1.0f;
    v3_cross(c, a, w);
    v3_normalise(b1, c);
    v3_cross(b2, w, b1);
    float r = e->p[SPM_LIGHT_P_DIR + 2], rr = r * sqrtf(u[2]), ph = 2.0f * SPM_PI_F * u[3];
    for (int i = 0; i < 3; i++) {
        o[i] = e->p[SPM_LIGHT_P_POS + i] + w[i] * r + b1[i] * (rr * cosf(ph)) +
               b2[i] * (rr * sinf(ph));
        d[i] = -w[i];
    }
    *pdf_pos = 1.0f / (SPM_PI_F * r * r);
    *pdf_dir = puv > 0.0f && st > 0.0f ? puv / (2.0f * SPM_PI_F * SPM_PI_F * st) : 0.0f;
}

void spm_ref_light_pdf_emission_ENVMAP(const spm_geometry *g, const spm_emitter *e, const float o[3],
                                       const float d[3], float *pdf_pos, float *pdf_dir)
{
    (void)o;
    float st, uv[2], back[3] = {-d[0], -d[1], -d[2]}, r = e->p[SPM_LIGHT_P_DIR + 2];
    spm_u32 t;
    env_uv(e, back, uv, &t, &st);
    *pdf_pos = 1.0f / (SPM_PI_F * r * r);
    *pdf_dir = st > 0.0f ? g->env[SPM_ENV_PDF(env_w(e), env_h(e)) + t] /
                               (2.0f * SPM_PI_F * SPM_PI_F * st)
                         : 0.0f;
}
