// Pieces of the BVH builder (host/accel/bvh.cpp drives the recursion and the
// threads, host/accel/bvh_split.cpp finds and applies splits). Not part of
// the public API.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <thread>
#include <vector>

#include "host/parallel.h"

namespace caustica::bvh_detail {

// Finite "empty box" bounds: the traversal rejects inverted boxes only while
// they stay finite (see bvh_traverse.h).
constexpr float kEmptyLo = 1e18f;
constexpr float kEmptyHi = -1e18f;

struct Box {
  glm::vec3 lo{kEmptyLo};
  glm::vec3 hi{kEmptyHi};

  void grow(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  void grow(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  // Half the surface area: SAH only needs ratios.
  double half_area() const {
    if (empty()) return 0.0;
    glm::dvec3 e = glm::dvec3(hi) - glm::dvec3(lo);
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
  glm::vec3 centroid() const { return 0.5f * (lo + hi); }
};

inline Box intersection(const Box& a, const Box& b) {
  Box r;
  r.lo = glm::max(a.lo, b.lo);
  r.hi = glm::min(a.hi, b.hi);
  return r;
}

// What a node needs to know of its references before splitting: their box,
// their centroids' box, and whether any of them is a triangle (only those
// can be split spatially).
struct RefBounds {
  Box box, centroids;
  bool splittable = false;
  void merge(const RefBounds& o) {
    box.grow(o.box);
    centroids.grow(o.centroids);
    splittable = splittable || o.splittable;
  }
};

// Double -> float rounded outward, so that boxes computed in double still
// contain the exact geometry once stored as floats: the traversal relies on
// boxes being conservative.
float round_down(double x);
float round_up(double x);

// A primitive, or the part of a triangle inside `box`, as the builder moves
// it around. `prim` indexes Prims. 32 bytes, aligned: box.lo and box.hi
// each load as one 4-float vector (Lane4 below) from one cache line.
struct alignas(32) Ref {
  Box box;
  uint32_t prim;
  uint32_t unused = 0;
};
static_assert(sizeof(Ref) == 32 && offsetof(Ref, box) == 0 && sizeof(Box) == 24, "Ref layout");

// Four floats in one SIMD register, through the compiler's generic vectors
// (SSE on x86-64, NEON on ARM): binning touches every reference at every
// level, and scalar box updates were most of the build's time.
typedef float Lane4 __attribute__((vector_size(16)));
inline Lane4 lane4_min(Lane4 a, Lane4 b) { return a < b ? a : b; }
inline Lane4 lane4_max(Lane4 a, Lane4 b) { return a > b ? a : b; }
inline Lane4 lane4_splat(float x) { return Lane4{x, x, x, x}; }
// box.lo in lanes 0-2 (lane 3 holds box.hi.x)
inline Lane4 ref_lo(const Ref& r) {
  Lane4 v;
  std::memcpy(&v, reinterpret_cast<const char*>(&r), sizeof v);
  return v;
}
// box.hi in lanes 0-2 (lane 3 holds prim)
inline Lane4 ref_hi(const Ref& r) {
  Lane4 v;
  std::memcpy(&v, reinterpret_cast<const char*>(&r) + offsetof(Box, hi), sizeof v);
  return v;
}
inline Box box_of(Lane4 lo, Lane4 hi) {
  Box b;
  b.lo = {lo[0], lo[1], lo[2]};
  b.hi = {hi[0], hi[1], hi[2]};
  return b;
}

// Every primitive of the scene in one index space: spheres, cylinders, then
// triangles (only those are ever split, so only their vertices are kept).
struct Prims {
  std::vector<uint32_t> codes;  // (type << 30) | index, for the kernels
  std::vector<glm::vec3> triangle_vertices;
  uint32_t first_triangle = 0;

  bool splittable(uint32_t p) const { return p >= first_triangle; }
  const glm::vec3* vertices(uint32_t p) const { return &triangle_vertices[3 * size_t(p - first_triangle)]; }
};

struct Settings {
  int max_leaf = 4;
  int object_bins = 16;
  bool widest_axis_only = false;  // object splits: bin only the widest centroid axis
  int spatial_bins = 0;  // most spatial bins per axis; 0: no spatial splits
  int max_depth = 64;
  double min_overlap = 0.0;  // half area of child overlap (object split) that makes a spatial split worth trying
};

// Box of the part of triangle `v` between the planes x[axis] = s0 and s1,
// intersected with `bound`; empty when nothing of the triangle lies there.
// Clipping the polygon rather than chopping its box is what makes spatial
// splits pay off for long diagonal triangles.
Box clip_triangle(const glm::vec3* v, int axis, float s0, float s1, const Box& bound);

// Workers and resolve_threads (host/parallel.h): callers of for_chunks
// merge per-chunk results with exact operations (min, max, integer sums)
// so that the outcome does not depend on the chunking.
using caustica::resolve_threads;
using caustica::Workers;

struct Split {
  enum Kind { kNone, kObject, kSpatial } kind = kNone;
  int axis = -1;
  double cost = std::numeric_limits<double>::max();
  // Object: centroids binned with (c - bin_lo) * bin_scale go left below `bin`.
  int bin = 0;
  float bin_lo = 0.0f, bin_scale = 0.0f;
  // Object: what the partition will give each child (the boxes' overlap
  // decides whether to try a spatial split), known from the bins.
  RefBounds left, right;
  size_t left_count = 0;
  float plane = 0.0f;  // spatial: split position along axis
};

constexpr int kMinSpatialBins = 8;

// Split search and partitioning; holds per-thread scratch, so one per thread.
class Splitter {
 public:
  Splitter(const Settings& settings, const Prims& prims) : s_(settings), prims_(prims) {}

  Split object_split(const Ref* refs, size_t n, const Box& centroid_box, const Workers* workers);
  // Only planes whose estimated duplicates fit in `budget` are considered.
  Split spatial_split(const Ref* refs, size_t n, const Box& box, uint64_t budget, const Workers* workers);

  // Reorders refs[0, n) into left then right, each side in its original
  // order (so the result does not depend on the chunking), on the threads
  // the split's binning used; returns split.left_count.
  size_t object_partition(Ref* refs, size_t n, const Split& split, const Workers* workers);
  size_t median_partition(Ref* refs, size_t n, const Box& centroid_box) const;
  // Replaces stack[begin, end) by the left references followed by the right
  // ones (straddling triangles either clipped into both or, when that is
  // cheaper or the budget is spent, moved whole to one side); returns the
  // left count and adds the duplicates made to *duplicates.
  size_t spatial_partition(std::vector<Ref>& stack, size_t begin, const Split& split, uint64_t budget,
                           uint64_t* duplicates);

 private:
  // A bin of an object split, or the sum of a run of them.
  struct ObjectBin {
    Lane4 lo = lane4_splat(kEmptyLo), hi = lane4_splat(kEmptyHi);  // the references' box
    Lane4 centroid_lo = lane4_splat(kEmptyLo), centroid_hi = lane4_splat(kEmptyHi);
    uint32_t count = 0;
    bool splittable = false;

    void add(const ObjectBin& b) {
      lo = lane4_min(lo, b.lo);
      hi = lane4_max(hi, b.hi);
      centroid_lo = lane4_min(centroid_lo, b.centroid_lo);
      centroid_hi = lane4_max(centroid_hi, b.centroid_hi);
      count += b.count;
      splittable = splittable || b.splittable;
    }
    Box box() const { return box_of(lo, hi); }
    RefBounds bounds() const {
      RefBounds r;
      r.box = box();
      r.centroids = box_of(centroid_lo, centroid_hi);
      r.splittable = splittable;
      return r;
    }
  };
  // Uninitialised room for n references (Ref is trivially copyable).
  struct RefBuffer {
    struct Free {
      void operator()(Ref* p) const { ::operator delete[](p, std::align_val_t(alignof(Ref))); }
    };
    std::unique_ptr<Ref, Free> data;
    size_t capacity = 0;
    Ref* reserve(size_t n) {
      if (n > capacity) {
        data.reset(static_cast<Ref*>(::operator new[](n * sizeof(Ref), std::align_val_t(alignof(Ref)))));
        capacity = n;
      }
      return data.get();
    }
  };
  struct SpatialBin {
    Box box;
    uint32_t enter = 0, exit = 0;
  };

  int object_bin(float centroid, float lo, float scale) const;
  // Bins refs[0, n) on axes[0, axis_count) into `sets` sets of bins (see
  // object_split for the layout).
  void bin_objects(const Ref* refs, size_t n, const Box& cbox, const float* scale, const int* axes, int axis_count,
                   int sets, ObjectBin* bins) const;
  void bin_spatial(const Ref* refs, size_t n, int nb, const float* planes, const bool* active, SpatialBin* bins) const;

  const Settings& s_;
  const Prims& prims_;
  std::vector<ObjectBin> object_bins_;  // per chunk, then their sum
  int object_chunks_ = 1;               // chunks of the last object_split's binning
  std::vector<size_t> chunk_left_;      // its best split's left count, per chunk
  RefBuffer partitioned_;
  std::vector<SpatialBin> spatial_bins_;
  std::vector<float> planes_;
  std::vector<double> right_cost_;
  std::vector<Box> right_box_;
  std::vector<uint32_t> right_count_;
  std::vector<Ref> scratch_;
};

}  // namespace caustica::bvh_detail
