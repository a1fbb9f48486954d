/* sss/scene.h: scene files (JSON, schema in docs/scenes.md): the objects,
 * lights and camera a bake is for. The planner (sss/planner.h) turns a scene
 * into the effects to bake (docs/scenes.md).
 *
 * Errors are one line naming the file and the JSON path (RFC 6901) of the
 * element at fault: `scene.json: /lights/2/direction: expected 3 numbers`.
 * Paths inside the scene (meshes, probes) are relative to the scene file's
 * directory; the parser resolves them but does not open them.
 */
#ifndef SSS_SCENE_H
#define SSS_SCENE_H

#include <stdint.h>
#include <stdio.h>
#include "sss/deform.h"
#include "sss/dipole.h"
#include "sss/single.h"
#include "sss/field.h"
#include "sss/layer_depth.h"
#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/vec3.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSS_SCENE_PATH_MAX 1024
#define SSS_SCENE_NAME_MAX 64
/* The most objects and lights a scene may hold: each costs about 1 KiB
 * parsed, and the planner keeps a row of every light per object; a 64 MiB
 * file of minimal lights would otherwise take gigabytes before anything is
 * planned (docs/robustness.md, item 7). */
#define SSS_SCENE_MAX_OBJECTS 4096
#define SSS_SCENE_MAX_LIGHTS 65536

typedef enum sss_light_kind {
    SSS_LIGHT_DIRECTIONAL = 0, /* parallel light of irradiance `intensity` from `direction` */
    SSS_LIGHT_POINT = 1,       /* isotropic point light of intensity `intensity` (per sr) at `position` */
    SSS_LIGHT_ENVIRONMENT = 2  /* distant radiance from an OpenEXR lat-long probe, scaled by `intensity` */
} sss_light_kind;

typedef struct sss_scene_light {
    sss_light_kind kind;
    int moving;              /* 0: static for the whole animation; 1: may move (or rotate) at run time */
    double direction[3];     /* directional: unit, towards the light (world) */
    double position[3];      /* point: world units */
    double intensity;        /* ≥ 0 */
    double colour[3];        /* linear RGB, ≥ 0 (default 1,1,1) */
    double rotation_deg;     /* environment: rotation about world +z (degrees) */
    char probe[SSS_SCENE_PATH_MAX]; /* environment: resolved path of the .exr */
} sss_scene_light;

typedef struct sss_scene_object {
    char name[SSS_SCENE_NAME_MAX];  /* default "object<i>" */
    char mesh[SSS_SCENE_PATH_MAX];  /* resolved path */
    sss_material material;
    double mm_per_unit;             /* millimetres per unit of the mesh file (default 1) */
    /* object → world: x_world = scale · R(rotate_deg) · x + translate;
     * rotation about x, then y, then z (degrees). Uniform scale keeps the
     * dipole distances isotropic. */
    double translate[3], rotate_deg[3], scale;
    int moving;                     /* 1: moves relative to the others (cannot cast baked shadows) */
    /* "deform": the procedural deformer applied in mesh units before the
     * transform (sss/deform.h; kind SSS_DEFORM_NONE: rigid) */
    sss_deform deform;
    /* Not a key of the file: set by a tool from the import
     * (sss_import_report.animated) when the mesh is a glTF whose skin its
     * first clip moves; such an object deforms as one with "deform" does
     * (docs/deformable.md §5) */
    int animated;
    int editable;                   /* "editable": the material is edited live (docs/heterogeneous.md §9) */
    int single_scattering;          /* "single_scattering": 1 true, -1 false, 0 absent (the planner decides) */
    /* The material's "layers" (seed 002; docs/layers.md §3): flat layers of
     * the given lower-boundary depths below the surface, over the material
     * itself; n = 0: none. Single scattering only: the dipole sees the
     * material. */
    sss_layer_stack layers;
    /* How each layer's depth is given (docs/layers.md §3): kind
     * SSS_DEPTH_CONSTANT for a number (layers.layer[k].depth), else a map or
     * a procedural pattern the bake evaluates per vertex (section LDEP);
     * layers.layer[k].depth is then the largest depth it can give (so the
     * stack may decrease until the bake, sss_layer_depths_eval, replaces
     * it by each layer's deepest over the vertices) */
    sss_depth_spec layer_depth[SSS_MAX_LAYERS];
    /* "material": {"field": ..., "inside": ...} (docs/heterogeneous.md §1):
     * kind SSS_FIELD_NONE for a homogeneous object; xf is filled by the
     * parser from mm_per_unit and the transform (world → rest-frame mm).
     * A grid field's samples are owned (sss_scene_free). */
    sss_hetero hetero;
    char field_path[SSS_SCENE_PATH_MAX]; /* a "vdb" field: the resolved file, read by the bake (else "") */
    /* the field's "strength" s (f → min(1, s f)), which only the run-time
     * path of an editable object draws (docs/heterogeneous.md §9.6); 1
     * when absent (0 in an object built in code: read as 1) */
    double field_strength;
    char field_grid[SSS_SCENE_NAME_MAX]; /* its grid's name */
} sss_scene_object;

typedef struct sss_scene_camera {
    int present;
    double position[3], target[3], up[3];
    double fov_deg;                 /* vertical field of view (default 40) */
} sss_scene_camera;

/* Bake settings a scene may override (0 = the bake's default). */
typedef struct sss_scene_bake {
    uint32_t dirs;       /* direction set size for moving directional lights / point shells */
    double eps;
    uint32_t sh_order;   /* environment transfer order (default 4) */
    uint32_t shells;     /* point-light distance shells (default 4) */
    double near_factor;  /* a point light is "near" below near_factor × object size (default 5) */
    /* How every object is baked (docs/scenes.md, "Schema"; 0 = the plain
     * bake's default, which the planner states with its reason): */
    uint32_t weights;    /* SSS_SCENE_WEIGHTS_*: the hat-function weights (physics.md §9) or the paper's */
    uint32_t compress;   /* SSS_SCENE_COMPRESS_*: the direction set's rows compact (compression.md) or float */
    uint32_t near_terms; /* SSS_SCENE_NEAR_*: the direction set's near terms at run time where they pay, or baked */
    uint32_t gather;     /* SSS_SCENE_GATHER_*: every neighbour's row, or the hierarchical gather (the values of
                          * SSS_GATHER_*, sss/bake.h; docs/heterogeneous.md §4.5) */
} sss_scene_bake;

enum { SSS_SCENE_WEIGHTS_DEFAULT = 0, SSS_SCENE_WEIGHTS_HAT = 1, SSS_SCENE_WEIGHTS_POINT = 2 };
enum { SSS_SCENE_COMPRESS_DEFAULT = 0, SSS_SCENE_COMPRESS_COMPACT = 1, SSS_SCENE_COMPRESS_NONE = 2 };
enum { SSS_SCENE_NEAR_DEFAULT = 0, SSS_SCENE_NEAR_RUNTIME = 1, SSS_SCENE_NEAR_BAKED = 2 };
enum { SSS_SCENE_GATHER_DEFAULT = 0, SSS_SCENE_GATHER_DIRECT = 1, SSS_SCENE_GATHER_TREE = 2 };

typedef struct sss_scene {
    char path[SSS_SCENE_PATH_MAX];  /* the file as given (used in messages) */
    uint32_t nobjects, nlights;
    sss_scene_object *objects;      /* owned */
    sss_scene_light *lights;        /* owned */
    sss_scene_camera camera;
    sss_scene_bake bake;
} sss_scene;

/* Parses the JSON text `text` as if read from `path` (for messages and
 * relative paths). On failure *out is zeroed and err holds
 * "PATH: /json/path: problem". */
sss_result sss_scene_parse(const char *text, const char *path, sss_scene *out, sss_error *err);

/* Reads and parses the file at path. */
sss_result sss_scene_load(const char *path, sss_scene *out, sss_error *err);

/* NULL-safe. */
void sss_scene_free(sss_scene *s);

/* Object i's mesh in world units: positions transformed, normals and areas
 * recomputed. mesh is the imported object-space mesh. */
sss_result sss_scene_object_world(const sss_scene_object *o, const sss_mesh *mesh, sss_mesh *out, sss_error *err);

/* Whether object o changes its shape at run time: a "deform", or a mesh
 * animated by its own rig (o->animated). */
static inline int sss_scene_object_deforms(const sss_scene_object *o)
{
    return o->deform.kind != SSS_DEFORM_NONE || o->animated;
}

/* What moves object o at time t, for messages: "bend, theta 40 deg", or
 * "the glTF's clip" for an animated rig (both when it has both). */
static inline void sss_scene_object_motion(const sss_scene_object *o, double t, char *buf, size_t n)
{
    if (o->deform.kind != SSS_DEFORM_NONE)
        snprintf(buf, n, "%s, theta %.4g deg%s", sss_deform_kind_name(o->deform.kind),
                 sss_deform_angle(&o->deform, t) * (180.0 / SSS_PI),
                 o->animated ? ", and the glTF's clip" : "");
    else
        snprintf(buf, n, "%s", o->animated ? "the glTF's clip" : "rigid");
}

/* Object i's pose at time t in world units: its "deform" applied to the
 * rest mesh (sss_deform_pose, docs/deformable.md §2), then its transform
 * (sss_scene_object_world). A rigid object gives its world mesh. */
sss_result sss_scene_object_posed(const sss_scene_object *o, const sss_mesh *rest, double t, sss_mesh *out,
                                  sss_error *err);

/* millimetres per world unit for object o: mm_per_unit / scale. */
double sss_scene_object_mm_per_world_unit(const sss_scene_object *o);

const char *sss_light_kind_name(sss_light_kind k);

#ifdef __cplusplus
}
#endif
#endif
