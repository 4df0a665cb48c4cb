#line 2 "kernels/shared/types.h"
/* Device data layout shared by the C++ host and OpenCL C kernels.
 *
 * Rules: plain C only; every struct is a multiple of 16 bytes with explicit
 * padding; vectors are 16-byte float4 (xyz used, w documented per field);
 * the host static_asserts every sizeof/offsetof (host/cl/layout_check.cpp)
 * and RecordLayout (tests/test_render_core.cpp) compares them with what the
 * device reports. shared/compat.h makes the vector types and builtins of
 * kernels/lib/ the same names on the host.
 * Nothing here may depend on the scene: scene-dependent choices are -D flags
 * (see host/scene/features.h), kept coarse so programs stay cacheable. */
#ifndef CAUSTICA_SHARED_TYPES_H
#define CAUSTICA_SHARED_TYPES_H

#ifdef __OPENCL_C_VERSION__
#include "shared/compat.h"
typedef float4 cs_float4;
typedef uint cs_uint;
typedef int cs_int;
typedef ushort cs_ushort;
#define CS_ALIGN16
#else
#include <cstdint>

#include "kernels/shared/compat.h"
typedef float4 cs_float4; /* the host's float4 (compat.h): .xyz and .w read as on the device */
typedef uint32_t cs_uint;
typedef int32_t cs_int;
typedef uint16_t cs_ushort;
#endif

/* Primitive references in BVH leaf order: type in the top 2 bits, index into
 * that type's array in the low 30 bits. */
#define PRIM_SPHERE 0u
#define PRIM_CYLINDER 1u
#define PRIM_TRIANGLE 2u
#define PRIM_TYPE_SHIFT 30u
#define PRIM_INDEX_MASK 0x3FFFFFFFu
#define PRIM_NONE 0xFFFFFFFFu

/* Entries of the per-ray traversal stack (kernels/lib/bvh_traverse.h), and so
 * the deepest tree the builders may produce (host/accel/bvh.h, bvh_wide.h)
 * and the host trace's stack. Tests shrink the kernels' copy with
 * -DBVH_STACK_SIZE=N to exercise the group entries. */
#define CS_BVH_STACK_SIZE 64

/* Ray-query constants shared by the kernels (lib/geometry.h,
 * lib/bvh_traverse.h) and the host trace (host/bench/host_trace.cpp), which
 * must give the kernels' answers:
 *   RAY_T_FAR: finite stand-in for "infinitely far" (fast-relaxed-math may
 *     fold inf);
 *   BVH_INV_DIR_MAX: reciprocal directions are clamped to +-this;
 *   BVH_EXIT_SLACK: relative widening of each box's exit distance, so that
 *     rounding in the slab test never culls a hit on a primitive touching
 *     its box (rays through triangle vertices sit exactly on box corners);
 *   BVH_ORIGIN_MAX: the largest origin coordinate a traced ray may have
 *     (the traversal's domain, lib/bvh_traverse.h: ray_traceable);
 *   CYL_PART_*: Hit.u of a cylinder hit, the part it is on. */
#define RAY_T_FAR 1e30f
#define BVH_INV_DIR_MAX 1e18f
#define BVH_EXIT_SLACK 2e-6f
#define BVH_ORIGIN_MAX 1e20f
#define CYL_PART_SIDE 0.0f
#define CYL_PART_TOP 1.0f    /* the cap at centre + half * axis */
#define CYL_PART_BOTTOM 2.0f /* the cap at centre - half * axis */

/* A closest-hit answer. u, v by primitive type:
 *   triangle: barycentrics, position = (1-u-v) v0 + u v1 + v v2;
 *   cylinder: u = part (CYL_PART_*), v = signed axial coordinate of the hit;
 *   sphere:   unused (0).
 * "No hit" exactly when prim == PRIM_NONE. One per ray-queue slot on the
 * device (intersect_closest writes them); the host trace returns the same. */
typedef struct {
  float t;
  float u;
  float v;
  cs_uint prim;
} Hit; /* 16 bytes */

typedef struct {
  cs_float4 center_radius; /* xyz centre, w radius */
  cs_uint material;
  cs_uint pad0, pad1, pad2;
} Sphere; /* 32 bytes */

typedef struct {
  cs_float4 center_radius; /* xyz centre, w radius */
  cs_float4 axis_half;     /* xyz unit axis, w half length (the JSON "height") */
  cs_uint material;
  cs_uint pad0, pad1, pad2;
} Cylinder; /* 48 bytes */

typedef struct {
  cs_float4 v0, v1, v2; /* xyz positions, w unused (0) */
  cs_uint material;
  cs_uint pad0, pad1, pad2;
} Triangle; /* 64 bytes */

/* Per-triangle shading data, parallel to the Triangle array; present only
 * when some triangle has vertex normals or texture coordinates (meshes,
 * JSON uv0..uv2). Triangles without them carry the geometric normal in
 * n0..n2 and the default UVs (0,0), (1,0), (0,1). */
typedef struct {
  cs_float4 n0, n1, n2; /* unit shading normals at v0, v1, v2; w unused */
  float u0, v0, u1, v1;
  float u2, v2;
  cs_uint pad0, pad1;
} TriangleShading; /* 80 bytes */

/* Per-triangle vertex tangents for normal maps (HAS_NORMAL_MAPS), parallel
 * to the Triangle array, present only when some material has a normal map:
 * xyz the tangent at v0, v1, v2 (glTF's TANGENT, or computed as MikkTSpace
 * does: host/scene/mesh_tangents.cpp), w its bitangent sign, so that the
 * bitangent is w cross(N, T) (lib/normal_map.h). Zero where a triangle's
 * material has no normal map. */
typedef struct {
  cs_float4 t0, t1, t2;
} TriangleTangents; /* 48 bytes */

/* Per-triangle vertex colours (glTF COLOR_0; HAS_VERTEX_COLOURS), parallel
 * to the Triangle array, present only when some triangle has them: linear
 * rgba at v0, v1, v2 as IEEE half floats (4 a vertex; alpha unused), white
 * for triangles without. They multiply the base colour (lib/material.h). */
typedef struct {
  cs_ushort rgba[12];
} TriangleColours; /* 24 bytes */

#define TEXTURE_IMAGE 0u
#define TEXTURE_CHECKER 1u

/* Texture.sampling: how uv become texels (lib/texture.h; zero is what the
 * coursework format means: repeat both ways, bilinear, uv as they are).
 * Wrap modes per axis (glTF sampler's wrapS / wrapT): repeat (no bit),
 * clamp to edge, mirrored repeat. */
#define TEXTURE_CLAMP_U 1u
#define TEXTURE_MIRROR_U 2u
#define TEXTURE_CLAMP_V 4u
#define TEXTURE_MIRROR_V 8u
#define TEXTURE_NEAREST 16u     /* the nearest texel (glTF magFilter NEAREST) instead of bilinear */
#define TEXTURE_TRANSFORMED 32u /* uv pass through the affine map uv_u, uv_v first (KHR_texture_transform) */

/* One texture of the scene. Image texels of every texture live in one buffer
 * of linear-RGB half floats (4 halves a texel: r, g, b and the image's alpha,
 * 1 where it has none; only alpha cut-outs read it), row-major from
 * the top row, texture i starting at texel `offset`. Several Texture records
 * may share texels (one image under different samplers or transforms). */
typedef struct {
  cs_float4 color1; /* checker: colour of even squares (linear rgb) */
  cs_float4 color2; /* checker: colour of odd squares */
  cs_float4 uv_u;   /* TEXTURE_TRANSFORMED: u' = uv_u.x u + uv_u.y v + uv_u.z (in this format's uv: v up); w unused */
  cs_float4 uv_v;   /* TEXTURE_TRANSFORMED: v' = uv_v.x u + uv_v.y v + uv_v.z; w unused */
  cs_uint kind;     /* TEXTURE_IMAGE or TEXTURE_CHECKER */
  cs_uint offset;   /* image: first texel */
  cs_uint width, height;
  float scale;      /* checker: squares per unit of u and v */
  cs_uint sampling; /* TEXTURE_* bits above */
  cs_uint pad0, pad1;
} Texture; /* 96 bytes */

/* 8-wide BVH, the layout the kernels traverse (host/accel/bvh_wide.cpp
 * collapses the BVH2 above into it; kernels/lib/bvh_traverse.h). Child
 * bounds are stored plane by plane, one lane per child, so that one float8
 * load per plane tests all eight children at once; an axis's lo and hi rows
 * are adjacent so the traversal picks the near/far row from the ray's sign
 * by offset alone. An empty slot has lo = +1e18, hi = -1e18 (missed by the
 * sign-picked slab test) and child WIDE_CHILD_EMPTY.
 *
 * child: an inner node index (< 2^22, see WIDE_GROUP_FLAG), or a leaf:
 * WIDE_LEAF_FLAG | kind | (count - 1) << 27 | first, where kind 0 names
 * `count` TriangleBlock4s from tri_blocks[first] and WIDE_LEAF_PRIMS names
 * `count` encoded refs (spheres, cylinders) from the wide prim_refs[first]. */
#define WIDE_WIDTH 8
#define WIDE_LEAF_FLAG 0x80000000u
#define WIDE_LEAF_PRIMS 0x40000000u
#define WIDE_LEAF_COUNT_SHIFT 27u
#define WIDE_LEAF_MAX_COUNT 8u
#define WIDE_LEAF_INDEX_MASK 0x07FFFFFFu
/* Traversal-stack only: "node, restricted to these child lanes" (lane mask
 * in bits 22..29). Inner node indices must stay below 2^22 for it. */
#define WIDE_GROUP_FLAG 0x40000000u
#define WIDE_GROUP_MASK_SHIFT 22u
#define WIDE_NODE_INDEX_MASK 0x003FFFFFu
#define WIDE_CHILD_EMPTY 0xFFFFFFFFu

typedef struct {
  float lo_x[8], hi_x[8], lo_y[8], hi_y[8], lo_z[8], hi_z[8];
  cs_uint child[8];
  /* Inner levels from this node to its deepest leaf, itself included: the
   * traversal's bound on the stack entries the subtree can still need. */
  cs_uint height;
  cs_uint pad[7];
} BvhNode8; /* 256 bytes */

/* Four triangles stored plane by plane (row r = vertex (r / 3), axis (r % 3),
 * one lane per triangle), tested together. Vertices, not edges: the
 * watertight test shears vertices, and v0 + (v1 - v0) would not give back
 * v1 exactly, so neighbours would no longer agree on a shared edge. Unused
 * lanes repeat lane 0 (same triangle, same answer: inert). */
typedef struct {
  float v[9][4];
  cs_uint ref[4]; /* encoded PRIM_TRIANGLE refs */
} TriangleBlock4; /* 160 bytes */

#define MATERIAL_REFLECTIVE 1u
#define MATERIAL_REFRACTIVE 2u
#define MATERIAL_TWO_SIDED 4u /* path mode: emission leaves both sides ("twosided") */
/* the texture's texel scales the diffuse colour (glTF: baseColorFactor x
 * baseColorTexture) instead of replacing it (the coursework format's textures) */
#define MATERIAL_TEXTURE_SCALES 8u
/* glTF alphaMode MASK: cut out where alpha_factor x the base colour
 * texture's alpha < alpha_cutoff; BLEND: passed through with probability
 * 1 - alpha (lib/alpha_cutout.h) */
#define MATERIAL_ALPHA_MASK 16u
#define MATERIAL_ALPHA_BLEND 32u
/* glTF KHR_materials_transmission: the glass's transmission is tinted by
 * the diffuse (base) colour, as the specification's BTDF is */
#define MATERIAL_TINTED_TRANSMISSION 64u
/* KHR_materials_volume: light inside the refractive material is absorbed
 * by volume.xyz per unit length (applied where a path leaves it) */
#define MATERIAL_ATTENUATES 128u

typedef struct {
  cs_float4 diffuse;  /* rgb diffuse colour, w = kd */
  cs_float4 specular; /* rgb specular colour, w = ks */
  cs_float4 emission; /* rgb emitted radiance (emissive materials, area lights), w unused */
  float specular_exponent;
  float reflectivity; /* weight of the mirror ray when MATERIAL_REFLECTIVE */
  float ior;          /* refractive index when MATERIAL_REFRACTIVE */
  float ka;           /* ambient coefficient (times the diffuse colour) */
  cs_uint flags;
  cs_int texture; /* index into the Texture table modulating the diffuse colour; -1: none */
  float roughness; /* path mode: GGX alpha as written ("roughness"); < 0: not given */
  float metallic;  /* path mode: 0 dielectric-coated ... 1 conductor ("metallic") */
  /* path mode: a glTF metallicRoughnessTexture (linear texels, not sRGB):
   * at a hit, roughness is scaled by G^2 (alpha = roughness x G^2, as glTF's
   * perceptual roughness is G x factor and alpha its square) and metallic by
   * B (lib/material.h); -1: none */
  cs_int roughness_texture;
  /* a glTF emissiveTexture (rgb, sRGB-decoded like base colour): the
   * radiance emitted at a point is emission.xyz x its texel there
   * (lib/material.h: material_emission_texel; a triangle light's sampled
   * point reads it too, lib/lights/triangle_light.h); -1: none */
  cs_int emission_texture;
  /* a glTF normalTexture (linear texels, tangent space: rgb = (n + 1) / 2)
   * perturbing the shading normal of triangles with tangents
   * (TriangleTangents; lib/normal_map.h); -1: none. normal_scale scales the
   * map's x and y (glTF's normalTexture.scale). */
  cs_int normal_texture;
  float normal_scale;
  /* MATERIAL_ALPHA_MASK / _BLEND: the base colour's alpha factor and the
   * MASK cut-off; the alpha texels are those of `texture` */
  float alpha_factor;
  float alpha_cutoff;
  /* path mode (HAS_CLEARCOAT): glTF's KHR_materials_clearcoat over a
   * plastic or conductor: its weight (0: none) and GGX alpha (lib/bsdf.h) */
  float clearcoat;
  float clearcoat_alpha;
  /* xyz: the absorption coefficient inside a refractive material per unit
   * length (MATERIAL_ATTENUATES); w: the share of a refractive material
   * that is its opaque base instead of glass (glTF's 1 - transmission x
   * (1 - metallic); 0: all glass, the coursework format's) */
  cs_float4 volume;
  /* glTF's clearcoatTexture (R scales the coat's weight) and
   * clearcoatRoughnessTexture (G scales its roughness, so alpha by G^2):
   * linear texels (lib/material.h); -1: none */
  cs_int clearcoat_texture;
  cs_int clearcoat_roughness_texture;
  /* glTF's clearcoatNormalTexture and its scale: the coat's own normal map
   * (lib/normal_map.h); -1: the coat lies on the vertex normal */
  cs_int clearcoat_normal_texture;
  float clearcoat_normal_scale;
} Material; /* 144 bytes */

/* A triangle's alpha cut-out (HAS_ALPHA_CUTOUTS; parallel to the Triangle
 * array, present only when some material has alpha MASK or BLEND; built
 * from the materials by host/scene/alpha_cutouts.cpp, read by the
 * traversal, lib/alpha_cutout.h). `mode` 0 is opaque: the traversal's hit
 * stands. Otherwise alpha = factor x the fourth channel of the texture
 * image (offset, width, height, sampling as its Texture record) at the
 * triangle's texture coordinates, whose corners already carry the
 * texture's transform (an affine map commutes with interpolation). */
#define ALPHA_OPAQUE 0u
#define ALPHA_MASK 1u  /* cut where alpha < cutoff */
#define ALPHA_BLEND 2u /* passed with probability 1 - alpha */
#define ALPHA_NO_IMAGE 0xFFFFFFFFu /* offset: the factor alone */
typedef struct {
  float u0, v0, u1, v1, u2, v2;
  float factor;
  float cutoff;
  cs_uint mode;
  cs_uint offset; /* first texel, or ALPHA_NO_IMAGE */
  cs_uint width, height;
  cs_uint sampling; /* TEXTURE_CLAMP_U ... TEXTURE_NEAREST (TEXTURE_TRANSFORMED is already applied) */
  cs_uint pad0, pad1, pad2;
} TriangleAlpha; /* 64 bytes */

/* A light, in the one form every integrator and the photon pass read, from
 * the scene loader to the device. What p0, p1, p2 and emitted hold is
 * each type's own (kernels/lib/lights/<type>_light.h says it; `kind` is a
 * row of the registry, kernels/lib/lights.h); emitted.w is the area of an
 * area light (0 for a delta light). Area lights are also scene geometry in
 * path mode (so BSDF-sampled rays hit them); a hit primitive's light is
 * found through the per-primitive light indices (light_of_sphere,
 * light_of_cylinder, light_of_triangle; LIGHT_NONE for none). Lights are
 * picked in proportion to power: select_cdf is the inclusive prefix sum of
 * select_probability (host/lights/light_table.cpp). */
#define LIGHT_NONE 0xFFFFFFFFu
#define LIGHT_TWO_SIDED 1u /* Light.flags */
/* Light.flags: a triangle light whose material has an emission texture; its
 * p0.w and p1.w hold the triangle's and the texture's indices
 * (lib/lights/triangle_light.h) */
#define LIGHT_EMISSION_TEXTURE 2u
/* Light.flags: a triangle light whose material has alpha MASK or BLEND; its
 * p0.w holds the triangle's index, whose TriangleAlpha record scales the
 * emission at a sampled point (lib/lights.h: light_emission_texel) */
#define LIGHT_ALPHA 4u

typedef struct {
  cs_float4 p0, p1, p2;
  cs_float4 emitted; /* rgb radiance (area lights) or intensity (delta lights); w: area */
  cs_uint kind;
  float select_probability;
  float select_cdf;
  cs_uint flags; /* LIGHT_TWO_SIDED, LIGHT_EMISSION_TEXTURE */
} Light; /* 80 bytes */

/* A node of the light tree (issue 42; host/lights/light_tree.h builds it,
 * lib/light_tree.h traverses it): the bounds of the lights below it, their
 * power and the cone of their emission (Conty Estevez and Kulla 2018;
 * pbrt-v4's LightBounds): axis, cos theta_o (the spread of the normals
 * about it) and cos theta_e (how far past the normals they emit). Nodes
 * are in depth-first order: an interior node's first child follows it,
 * `index` is its second; a leaf holds one light, `index` its index in
 * the light table. */
#define LIGHT_TREE_LEAF 1u      /* LightTreeNode.flags */
#define LIGHT_TREE_TWO_SIDED 2u /* every light below emits on both sides of its normal */
#define LIGHT_TREE_BY_POWER 4u  /* an interior node whose children are picked by power alone (lights at
                                 * infinity, the choice between them and the rest, --light-sampler uniform) */
typedef struct {
  cs_float4 bounds_min; /* xyz; w: power (the lights' summed flux, as the power CDF weighs them) */
  cs_float4 bounds_max; /* xyz; w: cos theta_o */
  cs_float4 axis;       /* xyz unit; w: cos theta_e */
  cs_uint index;        /* interior: the second child's node; leaf: the light */
  cs_uint flags;        /* LIGHT_TREE_* */
  float sin_o;          /* sin theta_o (from the host in double: the walk takes no square root for it) */
  cs_uint pad0;
} LightTreeNode; /* 64 bytes */

/* Where a light sits in the tree: its path from the root, one bit a level
 * (1: the second child), the root's first, in `bits` (lo word, then hi),
 * and the number of levels. The pmf of a light follows it (lib/light_tree.h). */
typedef struct {
  cs_uint bits_lo, bits_hi;
  cs_uint depth;
  cs_uint pad0;
} LightTreeTrail; /* 16 bytes */
#define LIGHT_TREE_MAX_DEPTH 64u

/* Pinhole camera (host: camera_for_image; the ray: shared/camera.h). */
typedef struct {
  cs_float4 position;
  cs_float4 forward; /* unit */
  cs_float4 right;   /* scaled */
  cs_float4 up;      /* scaled */
  cs_float4 lens;    /* x: aperture radius (0: pinhole), y: focus distance along forward; zw unused */
  cs_uint width, height;
  cs_uint pixel_offset; /* first pixel of this chunk (row-major) */
  cs_uint pixel_count;  /* pixels in this chunk */
} CameraGPU; /* 96 bytes */

/* Per-launch constants of the Whitted (phong) shading stage. */
typedef struct {
  cs_float4 background;    /* rgb, w unused */
  cs_float4 ambient_light; /* rgb scale of the ambient term ka * diffuse (1 unless the scene sets it) */
  cs_uint light_count;
  cs_uint max_depth; /* nbounces: secondary rays are spawned while depth < max_depth */
  cs_uint ray_capacity; /* of the next-wave queue */
  float min_weight;     /* rays whose weight falls below this are not spawned */
  cs_uint pad0, pad1, pad2, pad3;
} ShadeParams; /* 64 bytes */

/* Per-launch constants of the path tracer's stages. */
#define PATH_STRATEGY_MIS 0u  /* light sampling and BSDF sampling, power-heuristic weights */
#define PATH_STRATEGY_NEE 1u  /* light sampling only (emission found by BSDF rays ignored where sampleable) */
#define PATH_STRATEGY_BSDF 2u /* BSDF sampling only (no shadow rays; point lights unreachable) */
typedef struct {
  cs_float4 background; /* rgb radiance of rays that leave the scene */
  cs_uint light_count;
  cs_uint max_depth;    /* nbounces: most scattering events of a path */
  cs_uint ray_capacity; /* path slots: of each path queue */
  cs_uint first_pass;   /* the wave's first pass: index into each pixel's sample sequence */
  cs_uint seed;
  cs_uint strategy;     /* PATH_STRATEGY_* */
  cs_uint rr_depth;     /* Russian roulette from this many scattering events on */
  cs_uint sampler;      /* SAMPLER_* */
  /* The wave's samples (kernels/lib/camera_sample.h). With wave_entries 0
   * every pixel has the same count: sample s is pixel camera.pixel_offset +
   * s % wave_pixels in pass first_pass + s / wave_pixels. Otherwise the film
   * lists the wave's pixels (WAVE_ALLOCATION_PARAMS: wave_entries of them,
   * each with its own count; adaptive sampling). */
  cs_uint wave_pixels;
  cs_uint wave_samples;
  cs_uint wave_entries;
  cs_uint environment_light; /* the environment's index in the light table, or LIGHT_NONE */
} PathParams; /* 64 bytes */

/* The path tracer's wave counters (host/render/integrator_path.cpp), each in
 * its own sub-buffer of one buffer so that the host reads them all at once:
 * three path-queue counts that rotate (iteration j traces count j % 3, its
 * shade stage pushes into (j + 1) % 3 and clears (j + 2) % 3 for the next),
 * the shadow rays traced, and the wave's progress (WAVE_*: one uint each).
 * Ray counts run over the whole render (the host takes differences, modulo
 * 2^32); the samples started restart with each wave. */
#define WAVE_SAMPLES_STARTED 0u /* samples handed to a path slot so far (runs past the wave's samples) */
#define WAVE_CLOSEST_RAYS 1u    /* rays intersect_closest traced (the shade stages sum their queues) */
#define WAVE_PROGRESS_VALUES 2u

#define SAMPLER_SOBOL_BURLEY 0u /* low discrepancy, the default */
#define SAMPLER_INDEPENDENT 1u  /* independent uniforms: what the default is measured against */

/* The film's fixed point, one for every render: a contribution is added to
 * the pass in progress as a 128-bit integer, value * 2^FILM_FRACTION_BITS
 * rounded to nearest (even), with integer atomics, so that the sum does not
 * depend on the order in which work-items add (the same bits on any device,
 * thread count or work-group size), and passes add to 128-bit sums the same
 * way (accumulate_film_pass.cl). No scale is chosen from the scene: values
 * from 2^-20 (1e-6) to FILM_MAX_CONTRIBUTION keep every bit of their float,
 * values down to 2^-44 keep fewer, and the rest are counted as underflow
 * (issue 24: one very bright value no longer rounds the ordinary ones to
 * zero). A contribution above FILM_MAX_CONTRIBUTION is clamped to it and
 * counted, NaN/Inf and negative ones are dropped and counted: nothing is
 * changed silently. 2^56 in fixed point is 2^100, so a pixel takes 2^27
 * clamped contributions in one wave before its 128 bits could overflow. */
#define FILM_FRACTION_BITS 44
#define FILM_MAX_CONTRIBUTION 0x1p56f /* 7.2e16 */

/* Counters of film_add (one uint each, in this order). */
#define FILM_COUNT_NONFINITE 0u /* NaN or Inf components dropped */
#define FILM_COUNT_NEGATIVE 1u  /* negative components dropped */
#define FILM_COUNT_CLAMPED 2u   /* components above FILM_MAX_CONTRIBUTION clamped */
#define FILM_COUNT_UNDERFLOW 3u /* positive components below 2^-45 that rounded to 0 */
#define FILM_COUNTERS 4u

/* --check-numerics (path mode, -DHAS_NUMERIC_CHECKS=1): per scattering
 * event d < NUMERICS_DEPTHS (deeper ones count as the last), three 64-bit
 * counters at 3 d: BSDF samples taken, the sum of their weights' largest
 * channel (fixed point, NUMERICS_WEIGHT_SCALE), and samples whose weight
 * exceeded 1 (a single sample may; a mean above 1 is energy gain); then one
 * counter of non-finite BSDF weights. */
#define NUMERICS_DEPTHS 16u
#define NUMERICS_NONFINITE (3u * NUMERICS_DEPTHS)
#define NUMERICS_COUNTERS (3u * NUMERICS_DEPTHS + 1u)
#define NUMERICS_WEIGHT_SCALE 16777216.0f

/* Parameters of accumulate_film_pass: the accumulated sums are 128-bit
 * integers (two ulongs, low first) laid out in one buffer at offsets
 * (host/render/film.h). */
#define FILM_PASS_ABSENT 0xFFFFFFFFu
typedef struct {
  cs_uint value_count; /* pixels * 3, or with the aux passes pixels * (3 + FILM_AUX_CHANNELS) */
  cs_uint half_offset; /* value offset of the sum of passes [P, N), or FILM_PASS_ABSENT */
  cs_uint pass_index;  /* 0-based index of the first pass being added */
  cs_uint pass_count;  /* passes the pass in progress holds (a wave's) */
  /* 1: pixels have counts of their own (adaptive sampling): pixel p had
   * pixel_spp[p] samples and the wave adds wave_spp[p] (pass_index and
   * pass_count unused); 0: every pixel has pass_index and adds pass_count. */
  cs_uint per_pixel;
  cs_uint colour_values; /* pixels * 3: the aux passes' values follow */
  cs_uint pad1, pad2;
} FilmAccumulate; /* 32 bytes */

#endif /* CAUSTICA_SHARED_TYPES_H */
