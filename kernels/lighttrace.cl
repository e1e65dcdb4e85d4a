/* The light integrator's kernels (--integrator light), compiled only into a
 * program built with -DSPM_LIGHT_TRACE, which has no camera-path kernels
 * (docs/ARCHITECTURE.md "Light subpaths"):
 *   spm_light_trace   one work-item per subpath: the record of a subpath from
 *                     a light, each vertex connected to the camera, and the
 *                     pixel each splat lands in (the CPU reference's
 *                     host/cpu/refcpu_lighttrace.c, operation for operation)
 *   <shade>_lt        the mode's shade body walking the record from the light
 *                     and appending its splats (kernels/shade_body.clh)
 *   spm_splat_add     the chunk's splats into 64-bit fixed-point sums per
 *                     pixel with integer atomics: the sums do not depend on
 *                     the order of the adds
 *   spm_splat_convert each pixel's sum into the pass image once, in double
 *                     as host/output/film_splat.c converts it
 * It follows kernels/trace.cl and kernels/shade.cl in one program and uses
 * trace.cl's helpers (feel, occurrences, hit_frame). */
#pragma OPENCL FP_CONTRACT OFF
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_fp64 : enable

/* Veach's correction of a shading normal for importance at a light
 * subpath's vertex (pbrt-v4's CorrectShadingNormal): light arrives from wo,
 * leaves along wi; f |wi . ns| times
 *   |wo . ns| |wi . ng| / (|wo . ng| |wi . ns|)
 * (host/cpu/refcpu_shading.c spm_ref_adjoint_ns); 1 at a flat hit. */
SPM_ALWAYS_INLINE float adjoint_ns(const spm_frame *fr, float3 wo, float3 wi)
{
    if (!fr->smooth)
        return 1.0f;
    float num = fabs(dot3(wo, fr->n)) * fabs(dot3(wi, fr->gn));
    float den = fabs(dot3(wo, fr->gn)) * fabs(dot3(wi, fr->n));
    return den > 0.0f ? num / den : 0.0f;
}

/* The pixel film point f in [-1, 1]^2 falls in (f.y = 1 the top row), the
 * inverse of the camera ray's cx = 2 (x + u) / w - 1, cy = 1 - 2 (y + v) / h. */
SPM_ALWAYS_INLINE uint film_pixel(const spm_camera *cam, float2 f)
{
    int x = (int)floor((f.x + 1.0f) * 0.5f * (float)cam->width);
    int y = (int)floor((1.0f - f.y) * 0.5f * (float)cam->height);
    x = x < 0 ? 0 : x >= cam->width ? cam->width - 1 : x;
    y = y < 0 ? 0 : y >= cam->height ? cam->height - 1 : y;
    return (uint)y * (uint)cam->width + (uint)x;
}

/* The camera seen from p (leaving triangle skip), the lens sample from
 * dimensions dim, dim + 1: We / pdf_Wi, 0 when the camera does not see p or
 * something is between (a closest hit nearer than the lens, as the
 * reference's test); *px the pixel. */
SPM_ALWAYS_INLINE float camera_link(const spm_camera *cam, __global const spm_bvh4_node *nodes,
                                    __global const spm_tri *tris, __global uint *counters,
                                    spm_key k, uint dim, float3 p, uint skip, float3 *wi,
                                    uint *px SPM_ALPHA_PARAMS)
{
    float dist, pdf, t;
    float2 film;
    float we = camera_sample_Wi(cam, p, key_rng(k, dim), key_rng(k, dim + 1u), wi, &dist, &pdf,
                                &film);
    if (!(we > 0.0f) || !(pdf > 0.0f))
        return 0.0f;
    if (intersect(nodes, tris, p, *wi, skip, &t, counters SPM_ALPHA_ARGS) >= 0 && t < dist)
        return 0.0f;
    *px = film_pixel(cam, film);
    return we / pdf;
}

/* Light e's emission along d: its colour (SPM_NONE: none), *scale (Le of an
 * area light, I of a point light) and *cos_o to its face (1 without one). */
SPM_ALWAYS_INLINE uint lt_emission(__global const spm_tri *tris, __global const spm_material *mats,
                                   __global const spm_emitter *e, float3 d, float *scale,
                                   float *cos_o)
{
    *cos_o = 1.0f;
    if (e->kind != SPM_LIGHT_AREA) { /* I, times a spot's falloff (it samples its whole cone) */
        *scale = e->p[SPM_LIGHT_P_SCALE];
#ifdef SPM_WITH_LIGHT_SPOT
        if (e->kind == SPM_LIGHT_SPOT)
            *scale *= light_spot_falloff(e, dot3(d, light_spot_vec(e, SPM_LIGHT_P_DIR)));
#endif
        return e->colour;
    }
    __global const spm_tri *tr = &tris[e->tri];
    spm_material m = mats[tr->material];
    float c = dot3(d, ld3(tr->n));
    if (m.type & SPM_EMIT_TWOSIDED)
        c = fabs(c);
    *cos_o = c;
    if (!(c > 0.0f)) {
        *scale = 0.0f;
        return SPM_NONE;
    }
    return light_eval(m, c, scale);
}

/* Starts the subpath: the light by the selection, its ray o + t d,
 * beta = Le |cos_o| / (pmf pdf_pos pdf_dir), the emission's colour into the
 * head; an area light's own point connected to the camera (its splat
 * Le |cos| We / (pdf_Wi pmf pdf_pos), pixel px0). 0: the light gives none. */
SPM_ALWAYS_INLINE int lt_start(SPM_TRACE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA), spm_key k,
                               spm_path_head *hd, float3 *o, float3 *d, float *beta, uint *colour,
                               uint *skip, uint *px0)
{
    uint ei = light_pick(&p, emitters, k, SPM_DIM_VERTEX(0));
    __global const spm_emitter *e = &emitters[ei];
    float pp, pd, scale, cos_o;
    light_sample_emission(tris, emitters, ei, key_rng(k, SPM_DIM_LT_EMIT),
                          key_rng(k, SPM_DIM_LT_EMIT + 1u), key_rng(k, SPM_DIM_LT_EMIT + 2u),
                          key_rng(k, SPM_DIM_LT_EMIT + 3u), o, d, &pp, &pd);
    if (!(pp > 0.0f && pd > 0.0f))
        return 0;
    float ts = 1.0f; /* a textured emission's factor at o, looked up once */
    *colour = lt_emission(tris, mats, e, *d, &scale, &cos_o);
    if (e->kind == SPM_LIGHT_AREA)
        *colour = emit_texture(tex, uvs, e->tri, &tris[e->tri], *o, k, SPM_MAX_DEPTH, 0u, *colour,
                               &ts);
    if (*colour == SPM_NONE)
        return 0;
    *beta = scale * ts * cos_o / (e->pdf * pp * pd);
    *skip = e->kind == SPM_LIGHT_AREA ? e->tri : 0xFFFFFFFFu;
    hd->first_emit = *colour;
    if (e->kind != SPM_LIGHT_AREA) /* a delta in position: no camera ray meets it */
        return 1;
    spm_camera cam = p.cam;
    float3 wi;
    float w = camera_link(&cam, nodes, tris, counters, k, SPM_DIM_LT_LENS, *o, e->tri, &wi,
                          px0 SPM_ALPHA_ARGS);
    if (!(w > 0.0f) || lt_emission(tris, mats, e, wi, &scale, &cos_o) == SPM_NONE) {
        *px0 = SPM_NO_PIXEL;
        return 1;
    }
    hd->first_emit_c = scale * ts * cos_o * w / (e->pdf * pp);
    return 1;
}

/* Vertex j's connection to the camera: the splat weight
 *   beta f |cos_i| We / pdf_Wi
 * (f |cos_i| the type's in importance mode; its colour is the shade stage's,
 * which reads x->light); 0: none (a delta lobe has none). */
SPM_ALWAYS_INLINE float lt_link(SPM_TRACE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA), spm_material m,
                                const spm_bsdf *b, const spm_frame *fr, spm_key k, uint j,
                                float3 x, uint hit, float beta, spm_vertex_ext *xe, uint *px)
{
    float3 wi;
    if (!b->nee)
        return 0.0f;
    spm_camera cam = p.cam;
    float w = camera_link(&cam, nodes, tris, counters, k, SPM_DIM_VERTEX(j) + SPM_DIM_EPOINT_A,
                          x, hit, &wi, px SPM_ALPHA_ARGS);
    if (!(w > 0.0f))
        return 0.0f;
    spm_eval e = bsdf_eval(m, b, fr, wi, SPM_IMPORTANCE | SPM_JOIN);
    xe->light = e.cos_light;
    float c = beta * (e.k * e.f / e.div) / e.post * w;
    c *= adjoint_ns(fr, fr->back, wi);
    return c > 0.0f ? c : 0.0f;
}

/* One chunk's subpaths: subpath first_path + gid of the pass, keyed as that
 * camera path (pixel i / spp, sample first_sample + i % spp). The record is a
 * camera path's device layout (spm_shared.h) read from the light, with the
 * pixel words in lpx: slab 0 the light's own splat, slab j + 1 vertex j's
 * (SPM_NO_PIXEL: no splat). Parameters: SPM_TRACE_ARGS, SPM_LIGHT_TRACE_ARGS. */
__kernel void spm_light_trace(SPM_TRACE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA),
                              SPM_LIGHT_TRACE_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint gid = get_global_id(0);
    if (gid >= npaths)
        return;
    uint i = first_path + gid;
    spm_key key = {p.seed, i / p.spp_per_pass, p.first_sample + i % p.spp_per_pass};
    spm_walk walk = {disp, p.disperse, SPM_NONE};
    __global spm_vertex *vrec = &verts[gid];
    __global uint *pxrec = &lpx[gid]; /* slab s at pxrec[s * npaths] */
#ifdef SPM_WITH_VEXT
    __global spm_vertex_ext *xrec = (__global spm_vertex_ext *)SPM_VERTEX_EXT(verts, npaths) + gid;
#endif
    spm_path_head hd = {0u, SPM_END_ABSORBED, SPM_NONE, 0.0f, SPM_NONE, 0.0f, 0u, 0u};
    uint level = init_level, setby = SPM_SETBY_NONE, px0 = SPM_NO_PIXEL, colour, skip;
    ushort seen[SPM_MAX_DEPTH];
    float3 o, d;
    float beta;
    int started = p.nemitters > 0u &&
                  lt_start(SPM_TRACE_ARGS(SPM_KERNEL_ARG, SPM_COMMA), key, &hd, &o, &d, &beta,
                           &colour, &skip, &px0);
    pxrec[0] = px0;
    if (started)
        feel(lvlk, colour, 1u, SPM_SETBY_EMITTER, &level, &setby);
    int seg = 0;
    for (uint j = 0; started; j++) {
        float t;
        int hit = intersect(nodes, tris, o, d, skip, &t, counters SPM_ALPHA_ARGS);
        if (hit < 0) {
            hd.end = SPM_END_ESCAPED;
            break;
        }
        __global const spm_tri *tr = &tris[hit];
        float3 x = o + d * t;
        SPM_MATERIAL_AT(m, mi, mats, tex, uvs, tr, (uint)hit, x, key, j); /* metalrough.clh */
        spm_frame fr;
        hit_frame(tr, vnormals, tex, uvs, (uint)hit, o, d, &fr);
#ifdef SPM_WITH_VEXT
        if (seg && j > 0u) /* the segment's length inside: its absorption, in the shade stage */
            xrec[(size_t)(j - 1u) * npaths].lobe = t;
#endif
        spm_bsdf b;
        bsdf_begin(m, &fr, key, j, &walk, &b);
        float mmean, minv;
        uint refl = bsdf_lobe(m, &b, &mmean, &minv);
        spm_camera cam = p.cam;
        refl = texture_seen(tex, uvs, mi, (uint)hit, tr, x, &cam, key, j, refl, m.refl, &mmean,
                            &minv);
        spm_vertex_ext xe = {0u, 0.0f, 0.0f, 0.0f};
        uint px = SPM_NO_PIXEL;
        float c = lt_link(SPM_TRACE_ARGS(SPM_KERNEL_ARG, SPM_COMMA), m, &b, &fr, key, j, x,
                          (uint)hit, beta, &xe, &px);
        pxrec[(size_t)(j + 1u) * npaths] = c > 0.0f ? px : SPM_NO_PIXEL;
        __global spm_vertex *vx = &vrec[(size_t)j * npaths];
        vx->ids = (refl & 0xFFFFu) | (colour << 16);
        vx->c = c;
        uint col2 = bsdf_record(m, &b, &walk, &xe);
#ifdef SPM_WITH_VEXT
        xrec[(size_t)j * npaths] = xe;
#endif
        seg = 0;
        hd.nvert = j + 1u;
        seen[j] = (ushort)refl;
        if (refl != SPM_NONE)
            feel(lvlk, refl, occurrences(seen, j, refl), SPM_SETBY_REFLECTOR, &level, &setby);
        if (col2 != SPM_NONE)
            feel(lvlk, col2, 1u, SPM_SETBY_REFLECTOR, &level, &setby);
        if (refl == SPM_NONE || !(key_rng(key, SPM_DIM_VERTEX(j) + SPM_DIM_RR) < mmean))
            break;
        if (j + 1u == SPM_MAX_DEPTH) {
            hd.end = SPM_END_TRUNCATED;
            atomic_inc(&counters[SPM_COUNTER_TRUNCATED]);
            break;
        }
        beta *= minv;
        spm_bsample s;
        if (!bsdf_sample(m, &b, &fr, key, j, SPM_IMPORTANCE, &s) ||
            (fr.smooth && (s.refract ? !(dot3(s.wi, fr.gn) < 0.0f) : !(dot3(s.wi, fr.gn) > 0.0f))))
            break;
        beta *= s.wt;
        beta *= s.w;
        beta *= adjoint_ns(&fr, -d, s.wi);
        seg = s.inside;
#ifdef SPM_WITH_VEXT
        if (s.cos_lobe != 0.0f)
            xrec[(size_t)j * npaths].lobe = s.cos_lobe;
#endif
        o = x;
        d = s.wi;
        skip = (uint)hit;
    }
    heads[gid] = spm_dev_head_pack(&hd);
    levels[gid] = (uchar)(level | (setby << SPM_SETBY_SHIFT));
}

/* A splat counts unless a component is NaN or infinite (on the bits, as
 * spm_accumulate's test). */
SPM_ALWAYS_INLINE int splat_finite(__global const float *v)
{
    for (uint c = 0; c < SPM_PATH_CH; c++)
        if ((as_uint(v[c]) & 0x7f800000u) == 0x7f800000u)
            return 0;
    return 1;
}

/* Splats [0, n) into the fixed-point sums: acc[ch px + c] += round(v 2^shift)
 * (ldexp is exact in float short of underflow, and convert_long_rte rounds
 * as llrint); a non-finite splat is left out and counted. Parameters:
 * SPM_SPLAT_ADD_ARGS. */
__kernel void spm_splat_add(SPM_SPLAT_ADD_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint i = get_global_id(0);
    if (i >= n)
        return;
    __global const float *v = &sval[(size_t)SPM_PATH_CH * i];
    if (!splat_finite(v)) {
        atomic_inc(&counters[SPM_COUNTER_NONFINITE]);
        return;
    }
    __global long *a = &acc[(size_t)SPM_PATH_CH * spx[i]];
    for (uint c = 0; c < SPM_PATH_CH; c++) {
        long q = convert_long_rte(ldexp(v[c], shift));
        if (q != 0)
            atom_add(&a[c], q);
    }
}

/* Each pixel's sum into the pass image, (float)(sum 2^-shift) through double
 * as the host's conversion, and the sum back to zero for the next chunk. A
 * zero sum adds nothing. Parameters: SPM_SPLAT_CONVERT_ARGS. */
__kernel void spm_splat_convert(SPM_SPLAT_CONVERT_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint i = get_global_id(0);
    if (i >= npix)
        return;
    for (uint c = 0; c < SPM_PATH_CH; c++) {
        size_t k = (size_t)SPM_PATH_CH * i + c;
        long s = acc[k];
        if (s != 0) {
            pass[k] += (float)ldexp((double)s, -shift);
            acc[k] = 0;
        }
    }
}
