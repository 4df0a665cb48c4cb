#line 2 "kernels/shared/records.h"
/* The work records that flow between wavefront stages, declared once.
 *
 * Rules: a record is an X-macro field list F(q, type, name); a queue of
 * records is structure-of-arrays, one buffer per field plus one atomic
 * counter (kernels/lib/queue.h). Everything else is generated from these
 * lists: the kernels' parameter lists and load/store/push helpers
 * (kernels/lib/queue.h), the host's buffer allocation and the named argument
 * binding (DeviceQueue and KernelArgs::queue, host/render/kernel_args.h),
 * and the record structs both sides check the layout of
 * (host/cl/layout_check.cpp, and RecordLayout in tests/test_render_core.cpp).
 * Adding a field is one line here. Types are the shared ones of types.h
 * (cs_float4, cs_uint, float): 16-byte vectors first keeps the record
 * structs free of hidden padding. `q` is the queue's name, the prefix of its
 * kernel parameters (q_origin, q_dir, ..., q_count). Every field has one
 * meaning in every stage that reads or writes it: a record that carries
 * something else gets its own list (photon paths are PhotonRecords, not
 * PathRecords), and nothing rides in a vector's spare lane (a float4's w is
 * "unused" or a declared part of the field). Each record's flag bits are
 * one list next to it, F(name, bit), and layout_check.cpp asserts that no
 * two of them share a bit. */
#ifndef CAUSTICA_SHARED_RECORDS_H
#define CAUSTICA_SHARED_RECORDS_H

#ifdef __OPENCL_C_VERSION__
#include "shared/types.h"
#else
#include "kernels/shared/types.h"
#endif

/* A ray on its way: camera rays and every ray a shade stage spawns (path
 * tracer, Whitted and binary modes alike), with its ray cone (Amanatides
 * 1984: shade_surface_path), which only the path tracer's photon pass reads,
 * and the normal the light tree weighed lights with where the ray left,
 * which only programs with the tree read: programs without them neither
 * store nor load those fields (queue.h). */
#define PATH_RECORD_FIELDS(F, q) PATH_RAY_FIELDS(F, q) PATH_CONE_FIELDS(F, q) PATH_LIGHT_TREE_FIELDS(F, q)
#define PATH_RAY_FIELDS(F, q)                                                \
  F(q, cs_float4, origin)     /* xyz; w unused */                            \
  F(q, cs_float4, dir)        /* xyz unit direction; w unused */             \
  F(q, cs_float4, throughput) /* rgb share of the pixel; w unused */         \
  F(q, cs_uint, pixel)        /* film pixel it contributes to */             \
  F(q, cs_uint, depth)        /* scattering events so far */                 \
  F(q, float, bsdf_pdf)       /* density of the sampled direction (MIS); 0 after a delta lobe or from the camera */ \
  F(q, cs_uint, flags)        /* PATH_* bits (PATH_FLAGS) */                 \
  F(q, cs_uint, sample)       /* index into the pixel's sample sequence (its pass) */
#define PATH_CONE_FIELDS(F, q)                                               \
  F(q, float, cone_width)     /* the ray cone's footprint width at origin */ \
  F(q, float, cone_spread)    /* the ray cone's spread angle (radians) */
#define PATH_LIGHT_TREE_FIELDS(F, q)                                         \
  F(q, cs_uint, light_normal) /* the normal next-event estimation gave the light tree at origin, packed (lib/light_pick.h) */

/* PathRecord.flags: F(name, bit), each a distinct bit (layout_check.cpp). */
#define PATH_FLAGS(F)                                                                                \
  F(PATH_SPECULAR, 0)              /* arrived by a delta lobe or from the camera: emission hit counts fully */ \
  F(PATH_PAST_RECEIVER, 1)         /* caustics: D1 is behind, its visible point recorded (lib/caustics.h) */ \
  F(PATH_AFTER_RECEIVER, 2)        /* caustics: left a receiver, and met only casters since */ \
  F(PATH_CASTER_SINCE_RECEIVER, 3) /* caustics: ... at least one of them */ \
  F(PATH_AUX_PENDING, 4)           /* aux passes: no rough surface met yet (its albedo and normal are still to add) */

/* A photon path on its way from a light (the photon pass, kernels/photon/):
 * the same queue machinery as paths, its own fields. */
#define PHOTON_RECORD_FIELDS(F, q)                                          \
  F(q, cs_float4, origin)   /* xyz; w unused */                              \
  F(q, cs_float4, dir)      /* xyz unit direction; w unused */               \
  F(q, cs_float4, power)    /* rgb flux; w unused */                         \
  F(q, cs_uint, index)      /* the photon path's index in its pass: its random numbers and its candidate slot */ \
  F(q, cs_uint, depth)      /* scattering events so far */                   \
  F(q, float, path_length)  /* length travelled from the light to origin */  \
  F(q, cs_uint, flags)      /* PHOTON_* bits (PHOTON_FLAGS) */

/* PhotonRecord.flags: F(name, bit), each a distinct bit (layout_check.cpp). */
#define PHOTON_FLAGS(F)                                                                      \
  F(PHOTON_AFTER_CASTER, 0)      /* scattered at a caster at least once: stored at the next receiver */ \
  F(PHOTON_FROM_ENVIRONMENT, 1)  /* left the environment: no distance falloff (phong's gather, lib/caustics.h) */ \
  F(PHOTON_FROM_DISTANT_LIGHT, 2) /* left a directional light: phong's gather takes its irradiance as it is */

/* A segment toward a light, with what it adds to the film when unoccluded. */
#define SHADOW_RECORD_FIELDS(F, q)                                         \
  F(q, cs_float4, origin)       /* xyz; w unused */                        \
  F(q, cs_float4, dir)          /* xyz unit direction; w unused */         \
  F(q, cs_float4, contribution) /* rgb; w unused */                        \
  F(q, cs_uint, pixel)          /* film pixel, or SHADOW_SLOT_EMPTY (lib/queue.h) */ \
  F(q, float, tmax)             /* where the segment ends (short of the light) */

/* PathRecord.light_normal when the light tree weighed no normal (camera
 * rays, rays that left glass): no packed normal has this value. */
#define LIGHT_NORMAL_NONE 0xFFFFFFFFu

/* The flag constants, from the lists above. */
#define RECORD_FLAG_CONSTANT(name, bit) name = 1u << (bit),
enum { PATH_FLAGS(RECORD_FLAG_CONSTANT) };
enum { PHOTON_FLAGS(RECORD_FLAG_CONSTANT) };

/* The record structs: what one slot holds, and what the layout test checks. */
#define RECORD_STRUCT_MEMBER(q, type, name) type name;
typedef struct {
  PATH_RECORD_FIELDS(RECORD_STRUCT_MEMBER, _)
} PathRecord; /* 80 bytes of fields (what a queue slot holds: queues are SoA; 68 moved without the photon pass and the light tree) */

typedef struct {
  PHOTON_RECORD_FIELDS(RECORD_STRUCT_MEMBER, _)
} PhotonRecord; /* 64 bytes */

typedef struct {
  SHADOW_RECORD_FIELDS(RECORD_STRUCT_MEMBER, _)
  cs_uint pad0, pad1;
} ShadowRecord; /* 56 bytes of fields, 64 with the padding */

#endif /* CAUSTICA_SHARED_RECORDS_H */
