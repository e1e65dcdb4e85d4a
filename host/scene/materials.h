/* Material and emitter types as descriptors, one per tag, both from the one
 * list of types (include/spm_types.h: an entry's name is its tag SPM_MAT_*,
 * SPM_EMIT_*, its fields the descriptor), the way host/spectral/modes.c
 * describes modes: the
 * scene parser reads a type's clauses from its descriptor, the tables fill the
 * device material with its `fill`, the render plan compiles in the kernel code
 * of the types a scene uses (`define`) and sizes the path record by their
 * `vertex_u32`. docs/ADDING_A_MATERIAL.md says how to add one. */
#ifndef SPM_MATERIALS_H
#define SPM_MATERIALS_H
#include <stddef.h>
#include "scene.h"

/* What a clause or positional parameter gives: a colour (a spectrum name and
 * an optional scale) into a colour slot, or a number into p[slot]. */
typedef enum {
    SPM_MP_REFLECTANCE, /* a reflectance colour: slot 0 refl, 2 col2 */
    SPM_MP_EMISSION,    /* an emission colour: slot 1 emit */
    SPM_MP_NUMBER,      /* a number in [lo, hi]: p[slot] */
    SPM_MP_EMIT_NUMBER, /* an emitter type's number in [lo, hi]: ep[slot] */
    SPM_MP_FLAG,        /* the clause's word alone: bit slot of flags */
    SPM_MP_FILE,        /* a re-radiation matrix file (fluor.h): its diagonal into refl, its
                           index in the scene's matrices into p[slot] */
    SPM_MP_SHAPE,       /* a spectrum name alone (no scale), kept as its shape: its peak
                           scaled to 1, a reflectance-kind colour into slot 2 col2 or 3 col3 */
    SPM_MP_OPTICAL,     /* an optical constant (eta, k): a colour not bounded by 1, slot 0 or 2 */
    SPM_MP_INDEX        /* an index of refraction as its clause gives it (dispersion.h): 'ior'
                           a number or a spectrum name, 'sellmeier' six numbers, 'cauchy' two,
                           'glass' a catalogue name; n_d into p[slot], a dispersive index's
                           table into the scene's (p[SPM_DIEL_P_DISP] 1 + its row) */
} spm_mparam_kind;

#define SPM_MSLOT_REFL 0
#define SPM_MSLOT_EMIT 1
#define SPM_MSLOT_COL2 2
#define SPM_MSLOT_COL3 3

/* the area light's flag: bit of the scene material's flags */
#define SPM_AREA_FLAG_TWOSIDED 0

typedef struct {
    const char *clause;   /* keyword before it, or NULL: positional (in order, after the type keyword) */
    spm_mparam_kind kind;
    int slot;
    double lo, hi;        /* SPM_MP_NUMBER: the range */
    const char *what;     /* for messages: "a probability" */
    int required;         /* a clause that must be given (the parser says so, file:line) */
    int group;            /* > 0: the clauses of one group are alternatives (one of them at
                             most; a required one is given when any of them is) */
} spm_mparam;

#define SPM_MTYPE_MAX_PARAMS 6

typedef struct {
    const char *keyword;  /* after the material name; NULL: the default type (no keyword) */
    unsigned tag;         /* its index in the table */
    const char *help;
    spm_mparam params[SPM_MTYPE_MAX_PARAMS];
    int nparams;
    int vertex_u32;       /* path-record fields per vertex beyond spm_vertex (32-bit words;
                             the types share one spm_vertex_ext) */
    int rng_dims;         /* dimensions it draws per vertex: SPM_DIM_TYPE(j, 0 .. rng_dims-1) for a
                             material type, SPM_DIM_EMIT_TYPE(j, ...) for an emitter type */
    const char *define;   /* the kernel -D that compiles its code in */
    /* 1 (conductors, glass, coatings): a mesh triangle of this type with
     * vertex normals shades smooth by default (kernels/shading.clh); 0 (the
     * diffuse types): only under the mesh statement's `smooth`; -1: never
     * (a type whose lobes read the geometric frame) */
    int smooth;
    /* 1: its reflectance may be textured per point (`reflect texture NAME`,
     * a mesh's base-colour image): where its vertex records the material's
     * colour refl, the trace stage records the texture's pick instead, from
     * the lifted grid or from a palette its derive makes (scene.h palette) */
    int textured;
    /* 1: its density is a function of the two directions alone (no term
     * picked per vertex by a random number), so MIS can weigh it alike from
     * both ends of a connected path (--integrator bdpt) */
    int connectable;
    /* The device material's type-specific part (mean, inv_mean, p[], ep[])
     * from the scene material; colour ids and tags are already set. NULL:
     * the generic fill (materials.c generic_fill: the numbers into their
     * slots, survival the largest mean of the reflectance colours). */
    void (*fill)(const spm_scene *sc, const spm_scene_material *s, spm_material *d);
    /* Optional: a colour derived from the material's own, appended to the
     * scene's colours (in material order) once the scene is complete, into
     * s->diag (the fluorescent types: the shade tables key on it) or a
     * colour slot the type leaves unused (coated: col3 and col2). Returns 0
     * or fills err. */
    int (*derive)(spm_scene *sc, spm_scene_material *s, spm_error *err);
} spm_mtype_desc;

extern const spm_mtype_desc spm_material_types[];
extern const int spm_nmaterial_types;
extern const spm_mtype_desc spm_emitter_types[];
extern const int spm_nemitter_types;

/* The material type named by keyword kw, or NULL. */
const spm_mtype_desc *spm_material_type_find(const char *kw);
/* The default (keyword-less) material type: Lambertian. */
const spm_mtype_desc *spm_material_type_default(void);

/* Why a texture on another type's reflectance is its mean colour. */
#define SPM_TEXTURED_TYPES_WHY \
    "only a Lambertian or coated reflectance is textured per point so far"
/* 1 if material type `tag` takes a textured reflectance (its descriptor's textured). */
#define spm_material_textured(tag) (spm_material_types[(tag)].textured)

/* The faces scene material s emits from: 1, or 2 for a 'twosided' area light. */
int spm_material_faces(const spm_scene_material *s);

/* The device material of scene material s (every type). */
void spm_material_fill(const spm_scene *sc, const spm_scene_material *s, spm_material *d);

/* The types the device materials use: used_m[tag], used_e[tag] set to 1. */
void spm_material_types_used(const spm_material *mats, int n, int used_m[SPM_MAT_TYPES],
                             int used_e[SPM_EMIT_TYPES]);
/* The kernel options that compile in exactly the types mats use ("-DX -DY "),
 * into buf; returns its length. */
int spm_material_defines(const spm_material *mats, int n, char *buf, size_t size);
/* The conductor's exact unpolarised Fresnel reflectance for the complex
 * index eta + i k at incidence cosine c in [0, 1] (double: the host's tables
 * and pretest; the kernels and the CPU reference have their own floats). */
double spm_conductor_fresnel(double eta, double k, double c);

/* Bytes of one path vertex's record for the types mats use. */
size_t spm_material_vertex_bytes(const spm_material *mats, int n);
#endif
