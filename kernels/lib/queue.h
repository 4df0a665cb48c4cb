#line 2 "kernels/lib/queue.h"
/* Work queues: structure-of-arrays buffers plus one atomic counter. A push
 * reserves a slot with atomic_inc and then writes it. The counter may run
 * past the capacity: the slot is then dropped and the host, which reads the
 * counter back, sees the overflow and re-renders the chunk in halves, so no
 * ray is ever lost silently. Stage kernels are launched over the count
 * padded to the work-group size and return early past the count. */
#ifndef CAUSTICA_LIB_QUEUE_H
#define CAUSTICA_LIB_QUEUE_H

#include "shared/types.h"

/* A ray queue: origin.xyz, direction.xyz, weight.rgb with the depth in the
 * weight's w (as bits), and the film pixel the ray contributes to. */
#define RAY_QUEUE_PARAMS(q)                                                 \
  __global float4* restrict q##_origin, __global float4* restrict q##_dir, \
      __global float4* restrict q##_weight, __global uint* restrict q##_pixel
#define RAY_QUEUE_ARGS(q) q##_origin, q##_dir, q##_weight, q##_pixel

/* A shadow queue: origin.xyz with tmax in w, direction, the unoccluded
 * contribution, and the film pixel. */
#define SHADOW_QUEUE_PARAMS(q)                                              \
  __global float4* restrict q##_origin, __global float4* restrict q##_dir, \
      __global float4* restrict q##_contribution, __global uint* restrict q##_pixel

inline uint queue_reserve(volatile __global uint* counter, uint capacity) {
  uint slot = atomic_inc(counter);
  return slot < capacity ? slot : 0xFFFFFFFFu;
}

#endif
