/* The material and emitter types: one entry each, its tag its position in
 * its list. A type is named here once, and everything else is derived:
 *  - spm_shared.h expands the entries' names into the tags SPM_MAT_NAME and
 *    SPM_EMIT_NAME (host, CPU reference and kernels alike);
 *  - host/scene/materials.c expands the same entries into the descriptors
 *    (materials.h spm_mtype_desc: the fields after the name), so the scene
 *    parser, the tables, the render plan and the kernel options read them.
 *  - kernels/materials.clh includes each type's kernel file, which its entry
 *    names under SPM_KERNEL_FILES (a line above the entry);
 *  - a type's host code, the functions its fields name (fill, derive), is
 *    written above its entry under SPM_TYPE_HOST_CODE, which materials.c
 *    alone defines (a type without a fill takes the generic one, materials.c
 *    spm_material_fill; the older types' functions are materials.c's).
 * The fields are host-only C initialisers; the kernels' expansion drops them.
 * docs/ADDING_A_MATERIAL.md says how to add a type.
 *
 * No include guard: the includer defines SPM_MATERIAL_TYPE(NAME, ...) and
 * SPM_EMITTER_TYPE(NAME, ...) first, and undefines them after. */

/* ---- material types -------------------------------------------------------- */

/* MiniLight's diffuse reflector: its colour, survival its mean reflectance */
#ifdef SPM_KERNEL_FILES
#include "lambert.clh"
#endif
SPM_MATERIAL_TYPE(LAMBERT,
    .keyword = NULL, /* the default type */
    .help = "diffuse: 'reflect SPECTRUM [SCALE]' (default black)",
    .params = {{.clause = "reflect", .kind = SPM_MP_REFLECTANCE, .slot = SPM_MSLOT_REFL,
                .what = "a reflectance"}},
    .nparams = 1,
    .vertex_u32 = 0,
    .rng_dims = 0, /* the vertex's own cosine-lobe dimensions */
    .connectable = 1,
    .define = "SPM_WITH_LAMBERT",
    .textured = 1)

/* a metal: Fresnel of eta + i k, smooth or GGX-rough */
#ifdef SPM_KERNEL_FILES
#include "conductor.clh"
#endif
SPM_MATERIAL_TYPE(CONDUCTOR,
    .keyword = "conductor",
    .help = "metal: 'conductor ETA_SPECTRUM K_SPECTRUM [alpha A]' (complex index eta + i k; "
            "alpha: GGX width, 0 smooth)",
    .params = {{.kind = SPM_MP_OPTICAL, .slot = SPM_MSLOT_REFL,
                .what = "the real part eta of the index of refraction"},
               {.kind = SPM_MP_OPTICAL, .slot = SPM_MSLOT_COL2,
                .what = "the extinction coefficient k"},
               {.clause = "alpha", .kind = SPM_MP_NUMBER, .slot = SPM_COND_P_ALPHA, .lo = 0.0,
                .hi = 1.0, .what = "a GGX width"}},
    .nparams = 3,
    .vertex_u32 = (int)(sizeof(spm_vertex_ext) / 4),
    .rng_dims = 2, /* SPM_DIM_COND_M_A, SPM_DIM_COND_M_B */
    .connectable = 1,
    .define = "SPM_WITH_CONDUCTOR",
    .smooth = 1, /* a faceted metal sphere shows its facets in every reflection */
    .fill = conductor_fill)

/* a diffuse fluorescent surface (re-radiation matrix, fluor.h) */
#ifdef SPM_KERNEL_FILES
#include "fluor.clh"
#endif
SPM_MATERIAL_TYPE(FLUOR,
    .keyword = "fluoresce",
    .help = "fluorescent, diffuse: 'fluoresce ABSORB EMIT YIELD [reflect SPECTRUM [SCALE]]' "
            "(Wilkie et al. 2006)",
    .params = {{.kind = SPM_MP_REFLECTANCE, .slot = SPM_MSLOT_COL2,
                .what = "an absorption spectrum"},
               {.kind = SPM_MP_SHAPE, .slot = SPM_MSLOT_COL3, .what = "an emission shape"},
               {.kind = SPM_MP_NUMBER, .slot = SPM_FLUOR_P_YIELD, .lo = 0.0, .hi = 1.0,
                .what = "an energy yield"},
               {.clause = "reflect", .kind = SPM_MP_REFLECTANCE, .slot = SPM_MSLOT_REFL,
                .what = "a reflectance"}},
    .nparams = 4,
    .vertex_u32 = 0,
    .rng_dims = 0,
    .connectable = 1, /* the Lambertian's lobe; the matrix is the shade stage's */
    .define = "SPM_WITH_FLUOR",
    .fill = fluor_fill,
    .derive = fluor_derive)

/* the same from a measured re-radiation (Donaldson) matrix */
SPM_MATERIAL_TYPE(DONALDSON,
    .keyword = "donaldson",
    .help = "fluorescent, diffuse, measured: 'donaldson FILE' (a re-radiation matrix, its "
            "diagonal the reflectance; docs/SCENE_FORMAT.md)",
    .params = {{.kind = SPM_MP_FILE, .slot = SPM_FLUOR_P_MATRIX, .what = "a matrix file"}},
    .nparams = 1,
    .vertex_u32 = 0,
    .rng_dims = 0,
    .connectable = 1,
    .define = "SPM_WITH_FLUOR", /* the fluorescent type's code, shared */
    .fill = fluor_fill,
    .derive = fluor_derive)

/* glass: one index, smooth or GGX-rough, Beer-Lambert inside */
#ifdef SPM_KERNEL_FILES
#include "dielectric.clh"
#endif
SPM_MATERIAL_TYPE(DIELECTRIC,
    .keyword = "dielectric",
    .help = "glass: 'dielectric IOR [absorb SPECTRUM DENSITY] [alpha A]', IOR one of 'ior N', "
            "'ior SPECTRUM' (n per wavelength), 'sellmeier B1 B2 B3 C1 C2 C3' (um, um^2), "
            "'cauchy A B' (B in um^2), 'glass NAME' (N-BK7, N-SF11: Schott's catalogue) "
            "(index inside the front face's side; Beer-Lambert exp(-DENSITY SPECTRUM d), d in "
            "scene units; alpha: GGX width, 0 smooth)",
    .params = {{.clause = "ior", .kind = SPM_MP_INDEX, .slot = SPM_DIEL_P_IOR, .lo = 1.0,
                .hi = 4.0, .what = "an index of refraction", .required = 1, .group = 1},
               {.clause = "sellmeier", .kind = SPM_MP_INDEX, .slot = SPM_DIEL_P_IOR, .lo = 1.0,
                .hi = 4.0, .what = "an index of refraction", .required = 1, .group = 1},
               {.clause = "cauchy", .kind = SPM_MP_INDEX, .slot = SPM_DIEL_P_IOR, .lo = 1.0,
                .hi = 4.0, .what = "an index of refraction", .required = 1, .group = 1},
               {.clause = "glass", .kind = SPM_MP_INDEX, .slot = SPM_DIEL_P_IOR, .lo = 1.0,
                .hi = 4.0, .what = "an index of refraction", .required = 1, .group = 1},
               {.clause = "absorb", .kind = SPM_MP_OPTICAL, .slot = SPM_MSLOT_COL2,
                .what = "an absorption coefficient (spectrum and density per scene unit)"},
               {.clause = "alpha", .kind = SPM_MP_NUMBER, .slot = SPM_DIEL_P_ALPHA, .lo = 0.0,
                .hi = 1.0, .what = "a GGX width"}},
    .nparams = 6,
    .vertex_u32 = (int)(sizeof(spm_vertex_ext) / 4),
    .rng_dims = 4, /* SPM_DIM_DIEL_M_A, SPM_DIM_DIEL_M_B, SPM_DIM_DIEL_CHOICE, SPM_DIM_DIEL_LAMBDA */
    .connectable = 1,
    .define = "SPM_WITH_DIELECTRIC",
    .smooth = 1, /* a faceted glass sphere shows its facets in every refraction */
    .fill = dielectric_fill,
    .derive = dielectric_derive)

/* a Lambertian base under a smooth or GGX-rough dielectric coating */
#ifdef SPM_KERNEL_FILES
#include "coated.clh"
#endif
SPM_MATERIAL_TYPE(COATED,
    .keyword = "coated",
    .help = "paint, plastic: 'coated reflect SPECTRUM [SCALE] ior N [alpha A]' (a diffuse "
            "base under a dielectric coating of index N, default 1.5; alpha: GGX width, 0 "
            "smooth)",
    .params = {{.clause = "reflect", .kind = SPM_MP_REFLECTANCE, .slot = SPM_MSLOT_REFL,
                .what = "a reflectance"},
               {.clause = "ior", .kind = SPM_MP_NUMBER, .slot = SPM_COAT_P_ETA, .lo = 1.0,
                .hi = 4.0, .what = "an index of refraction"},
               {.clause = "alpha", .kind = SPM_MP_NUMBER, .slot = SPM_COAT_P_ALPHA, .lo = 0.0,
                .hi = 1.0, .what = "a GGX width"}},
    .nparams = 3,
    .vertex_u32 = (int)(sizeof(spm_vertex_ext) / 4),
    .rng_dims = 3, /* SPM_DIM_COAT_LOBE, SPM_DIM_COAT_M_A, SPM_DIM_COAT_M_B */
    .define = "SPM_WITH_COATED",
    .smooth = 1, /* a faceted glossy sphere shows its facets in its highlight */
    .textured = 1, /* its base: a palette of D (coated_derive) */
    .fill = coated_fill,
    .derive = coated_derive)

/* a rough diffuse reflector: the energy-preserving Oren-Nayar model (EON,
 * Portsmouth, Kutz and Hill 2025, OpenPBR's rough diffuse), its roughness in
 * p[SPM_ROUGH_P_R]; its multiple-scattering colour rho_ms(rho), derived into
 * col2 (roughdiffuse_derive, below), is what a vertex records when it
 * picks that term (kernels/roughdiffuse.clh) */
#ifndef SPM_ROUGH_P_R
#define SPM_ROUGH_P_R 0
#endif
#ifdef SPM_KERNEL_FILES
#include "roughdiffuse.clh"
#elif defined(SPM_TYPE_HOST_CODE)
/* Rough diffuse (EON, kernels/roughdiffuse.clh): its multiple-scattering
 * colour rho_ms = rho^2 E_avg / (1 - rho (1 - E_avg)) per 1 nm bin into col2,
 * E_avg = A (1 + c2 r) the average albedo of its single-scattering term,
 * A = 1 / (1 + c1 r), c1 = 1/2 - 2 / (3 pi), c2 = 2/3 - 28 / (15 pi). At
 * roughness 0 the term is 0 (the Lambertian): no colour. */
static int roughdiffuse_derive(spm_scene *sc, spm_scene_material *s, spm_error *err)
{
    double r = s->p[SPM_ROUGH_P_R];
    if (!(r > 0.0))
        return 0;
    if (refuse_fluor(sc, s, "rough diffuse", err))
        return 1;
    double c1 = 0.5 - 2.0 / (3.0 * M_PI), c2 = 2.0 / 3.0 - 28.0 / (15.0 * M_PI);
    double eavg = (1.0 + c2 * r) / (1.0 + c1 * r);
    sc->colours = spm_xrealloc(sc->colours, ((size_t)sc->ncolours + 1) * sizeof *sc->colours);
    spm_colour *c = &sc->colours[sc->ncolours];
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "%.50s:multiple", s->name);
    c->s.kind = SPM_KIND_REFLECTANCE;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double rho = s->refl >= 0 ? sc->colours[s->refl].s.nm1[i] : 0.0;
        c->s.nm1[i] = rho * rho * eavg / (1.0 - rho * (1.0 - eavg));
    }
    s->col2 = sc->ncolours++;
    return 0;
}
#endif
SPM_MATERIAL_TYPE(ROUGHDIFFUSE,
    .keyword = "roughdiffuse",
    .help = "rough diffuse: 'roughdiffuse reflect SPECTRUM [SCALE] roughness R' (energy-"
            "preserving Oren-Nayar, R in [0, 1]; 0 is the Lambertian)",
    .params = {{.clause = "reflect", .kind = SPM_MP_REFLECTANCE, .slot = SPM_MSLOT_REFL,
                .what = "a reflectance"},
               {.clause = "roughness", .kind = SPM_MP_NUMBER, .slot = SPM_ROUGH_P_R, .lo = 0.0,
                .hi = 1.0, .what = "a roughness", .required = 1}},
    .nparams = 2,
    .vertex_u32 = 0,
    .rng_dims = 2, /* the term's choice, the sampler's lobe (kernels/roughdiffuse.clh) */
    .define = "SPM_WITH_ROUGHDIFFUSE",
    .derive = roughdiffuse_derive)

/* ---- emitter types --------------------------------------------------------- */

/* a triangle emitting from its front face (or both), uniformly */
SPM_EMITTER_TYPE(AREA,
    .keyword = "area",
    .help = "'emit SPECTRUM [SCALE] [twosided]': an area light, front face (or both)",
    .params = {{.clause = "emit", .kind = SPM_MP_EMISSION, .slot = SPM_MSLOT_EMIT,
                .what = "an emission"},
               {.clause = "twosided", .kind = SPM_MP_FLAG, .slot = SPM_AREA_FLAG_TWOSIDED,
                .what = "both faces emit"}},
    .nparams = 2,
    .vertex_u32 = 0,
    .rng_dims = 0,
    .define = "SPM_WITH_AREA",
    .fill = area_fill)
