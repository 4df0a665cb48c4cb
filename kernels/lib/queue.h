#line 2 "kernels/lib/queue.h"
/* Work queues: structure-of-arrays buffers plus one atomic counter, for the
 * records of shared/records.h. A push reserves a slot with atomic_inc and
 * then writes it (shadow queues are addressed instead, see below). The
 * counter may run past the capacity: the slot is then dropped and the host,
 * which reads the counter back, sees the overflow and re-traces the chunk in
 * halves, so no ray is ever lost silently (the path tracer's queues cannot
 * overflow: a path pushes one record at most). Stage kernels are launched
 * over at least the count (the path tracer: its queues' capacity until the
 * host knows a smaller bound) and return early past the count.
 *
 * Everything below is generated from the field lists; a stage names a queue
 * by its prefix: PATH_QUEUE_PARAMS(next) declares next_count, next_origin,
 * ..., and path_push(PATH_QUEUE_ARGS(next), capacity, record) pushes
 * (PHOTON_QUEUE_PARAMS / photon_push and SHADOW_QUEUE_PARAMS likewise). */
#ifndef CAUSTICA_LIB_QUEUE_H
#define CAUSTICA_LIB_QUEUE_H

#include "shared/records.h"

#define QUEUE_FIELD_PARAM(q, type, name) , __global type* restrict q##_##name
#define QUEUE_FIELD_ARG(q, type, name) , q##_##name
#define QUEUE_FIELD_LOAD(q, type, name) record.name = q##_##name[slot];
#define QUEUE_FIELD_STORE(q, type, name) q##_##name[slot] = record.name;

#define PATH_QUEUE_PARAMS(q) volatile __global uint* q##_count PATH_RECORD_FIELDS(QUEUE_FIELD_PARAM, q)
#define PATH_QUEUE_ARGS(q) q##_count PATH_RECORD_FIELDS(QUEUE_FIELD_ARG, q)
#define PHOTON_QUEUE_PARAMS(q) volatile __global uint* q##_count PHOTON_RECORD_FIELDS(QUEUE_FIELD_PARAM, q)
#define PHOTON_QUEUE_ARGS(q) q##_count PHOTON_RECORD_FIELDS(QUEUE_FIELD_ARG, q)
#define SHADOW_QUEUE_PARAMS(q) volatile __global uint* q##_count SHADOW_RECORD_FIELDS(QUEUE_FIELD_PARAM, q)
#define SHADOW_QUEUE_ARGS(q) q##_count SHADOW_RECORD_FIELDS(QUEUE_FIELD_ARG, q)

/* What the intersection stages read of any ray queue: its count, origins and
 * directions (the host binds those three fields of a queue by name). */
#define RAY_VIEW_PARAMS(q)                                                           \
  __global const uint* restrict q##_count, __global const float4* restrict q##_origin, \
      __global const float4* restrict q##_dir

inline uint queue_reserve(volatile __global uint* counter, uint capacity) {
  uint slot = atomic_inc(counter);
  return slot < capacity ? slot : 0xFFFFFFFFu;
}

/* A path as the camera starts it: full throughput, no scattering yet,
 * counted as arriving by a delta lobe (emission seen directly is not
 * MIS-weighted), a cone of width 0 and no spread (the path tracer's camera
 * sets the spread, lib/camera_sample.h), no normal for the light tree. */
inline PathRecord camera_path(float3 origin, float3 dir, uint pixel, uint sample) {
  PathRecord ray;
  ray.origin = (float4)(origin, 0.0f);
  ray.dir = (float4)(dir, 0.0f);
  ray.throughput = (float4)(1.0f, 1.0f, 1.0f, 0.0f);
  ray.pixel = pixel;
  ray.depth = 0u;
  ray.bsdf_pdf = 0.0f;
  ray.flags = PATH_SPECULAR;
  ray.sample = sample;
  ray.cone_width = 0.0f;
  ray.cone_spread = 0.0f;
  ray.light_normal = LIGHT_NORMAL_NONE;
  return ray;
}

/* The ray cone is read only with the photon pass (HAS_CAUSTICS, a
 * -D of the whole program), the light tree's normal only with the tree
 * (HAS_LIGHT_TREE): every other program (path tracing without them,
 * Whitted, binary) moves only the ray's own fields, so those cost it no
 * memory traffic, and their loads read 0. */
#define QUEUE_FIELD_ZERO(q, type, name) record.name = 0;
#define QUEUE_FIELDS_NONE(F, q)
#if HAS_CAUSTICS
#define PATH_MOVED_CONE_FIELDS PATH_CONE_FIELDS
#define PATH_UNMOVED_CONE_FIELDS QUEUE_FIELDS_NONE
#else
#define PATH_MOVED_CONE_FIELDS QUEUE_FIELDS_NONE
#define PATH_UNMOVED_CONE_FIELDS PATH_CONE_FIELDS
#endif
#if HAS_LIGHT_TREE
#define PATH_MOVED_LIGHT_TREE_FIELDS PATH_LIGHT_TREE_FIELDS
#define PATH_UNMOVED_LIGHT_TREE_FIELDS QUEUE_FIELDS_NONE
#else
#define PATH_MOVED_LIGHT_TREE_FIELDS QUEUE_FIELDS_NONE
#define PATH_UNMOVED_LIGHT_TREE_FIELDS PATH_LIGHT_TREE_FIELDS
#endif
#define PATH_MOVED_FIELDS(F, q) PATH_RAY_FIELDS(F, q) PATH_MOVED_CONE_FIELDS(F, q) PATH_MOVED_LIGHT_TREE_FIELDS(F, q)
#define PATH_UNMOVED_ZERO(record) \
  PATH_UNMOVED_CONE_FIELDS(QUEUE_FIELD_ZERO, _) PATH_UNMOVED_LIGHT_TREE_FIELDS(QUEUE_FIELD_ZERO, _)

#define QUEUE_NOTHING_TO_ZERO(record)

/* A record type's load, store and push over the fields its queue moves;
 * push is false when the queue is full (the host sees the overflow in the
 * count). */
#define QUEUE_ACCESS(prefix, Record, QUEUE_PARAMS, MOVED_FIELDS, ZERO_UNMOVED) \
  inline Record prefix##_load(QUEUE_PARAMS(q), uint slot) {                   \
    Record record;                                                            \
    MOVED_FIELDS(QUEUE_FIELD_LOAD, q)                                         \
    ZERO_UNMOVED(record)                                                      \
    return record;                                                            \
  }                                                                           \
  inline void prefix##_store(QUEUE_PARAMS(q), uint slot, Record record) {     \
    MOVED_FIELDS(QUEUE_FIELD_STORE, q)                                        \
  }                                                                           \
  inline bool prefix##_push(QUEUE_PARAMS(q), uint capacity, Record record) {  \
    const uint slot = queue_reserve(q_count, capacity);                       \
    if (slot == 0xFFFFFFFFu) return false;                                    \
    MOVED_FIELDS(QUEUE_FIELD_STORE, q)                                        \
    return true;                                                              \
  }

QUEUE_ACCESS(path, PathRecord, PATH_QUEUE_PARAMS, PATH_MOVED_FIELDS, PATH_UNMOVED_ZERO)
QUEUE_ACCESS(photon, PhotonRecord, PHOTON_QUEUE_PARAMS, PHOTON_RECORD_FIELDS, QUEUE_NOTHING_TO_ZERO)
QUEUE_ACCESS(shadow, ShadowRecord, SHADOW_QUEUE_PARAMS, SHADOW_RECORD_FIELDS, QUEUE_NOTHING_TO_ZERO)

/* Shadow queues are addressed rather than pushed: the shade stage owns the
 * slots of its ray (for Whitted, slot = ray * light_count + light) and
 * writes a record or marks the slot empty, so no counter is contended and
 * the host knows the count without reading it back (shadow_push, generated
 * above with the others, goes unused). */
#define SHADOW_SLOT_EMPTY 0xFFFFFFFFu

inline void shadow_mark_empty(SHADOW_QUEUE_PARAMS(q), uint slot) { q_pixel[slot] = SHADOW_SLOT_EMPTY; }

#endif
