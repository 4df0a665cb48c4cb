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
 * kernel parameters (q_origin, q_dir, ..., q_count). */
#ifndef CAUSTICA_SHARED_RECORDS_H
#define CAUSTICA_SHARED_RECORDS_H

#ifdef __OPENCL_C_VERSION__
#include "shared/types.h"
#else
#include "kernels/shared/types.h"
#endif

/* A ray on its way: camera rays and every ray a shade stage spawns. */
#define PATH_RECORD_FIELDS(F, q)                                   \
  F(q, cs_float4, origin)     /* xyz; w unused */                  \
  F(q, cs_float4, dir)        /* xyz unit direction; w unused */   \
  F(q, cs_float4, throughput) /* rgb share of the pixel; w unused */ \
  F(q, cs_uint, pixel)        /* film pixel it contributes to */   \
  F(q, cs_uint, depth)        /* scattering events so far */       \
  F(q, float, bsdf_pdf)       /* path: density of the sampled direction (MIS); 0 after a delta lobe; \
                                 photons: length travelled from the light */                     \
  F(q, cs_uint, flags)        /* path: PATH_* bits */                                         \
  F(q, cs_uint, sample)       /* path: index into the pixel's sample sequence (its pass) */

/* A segment toward a light, with what it adds to the film when unoccluded. */
#define SHADOW_RECORD_FIELDS(F, q)                                   \
  F(q, cs_float4, origin)       /* xyz; w = tmax (ends short of the light) */ \
  F(q, cs_float4, dir)          /* xyz unit direction; w unused */   \
  F(q, cs_float4, contribution) /* rgb; w unused */                  \
  F(q, cs_uint, pixel)

/* The record structs: what one slot holds, and what the layout test checks. */
#define RECORD_STRUCT_MEMBER(q, type, name) type name;
typedef struct {
  PATH_RECORD_FIELDS(RECORD_STRUCT_MEMBER, _)
} PathRecord; /* 68 bytes of fields (what a queue slot stores: queues are SoA), 80 with the struct's float4 alignment */

/* PathRecord.flags */
#define PATH_SPECULAR 1u /* arrived by a delta lobe or from the camera: emission hit counts fully */
typedef struct {
  SHADOW_RECORD_FIELDS(RECORD_STRUCT_MEMBER, _)
  cs_uint pad0, pad1, pad2;
} ShadowRecord; /* 64 bytes */

#endif /* CAUSTICA_SHARED_RECORDS_H */
