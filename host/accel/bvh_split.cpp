// Split search for the BVH builder: binned SAH over reference centroids
// (object splits) and binned SAH over reference extents with triangles
// clipped into every bin they cross (spatial splits, Stich, Friedrich and
// Dietrich 2009, "Spatial Splits in Bounding Volume Hierarchies").
#include <algorithm>
#include <cmath>

#include "host/accel/bvh_internal.h"

namespace caustica::bvh_detail {

float round_down(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::max()) : f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::max()) : f;
}

Box clip_triangle(const glm::vec3* v, int axis, float s0, float s1, const Box& bound) {
  // The clipped polygon's vertices are the triangle's vertices inside the
  // slab plus the edges' crossings of its two planes; its box is theirs.
  // Crossings are computed in double and rounded outward so the box stays
  // conservative for the traversal.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  glm::dvec3 lo(kInf), hi(-kInf);
  bool any = false;
  auto add = [&](const glm::dvec3& q) {
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
    any = true;
  };
  const double planes[2] = {s0, s1};
  const int plane_count = s0 == s1 ? 1 : 2;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 a(v[i]), b(v[(i + 1) % 3]);
    const double pa = a[axis], pb = b[axis];
    if (pa >= s0 && pa <= s1) add(a);
    for (int k = 0; k < plane_count; ++k) {
      const double p = planes[k];
      if ((pa < p && pb > p) || (pa > p && pb < p)) {
        glm::dvec3 q = a + (p - pa) / (pb - pa) * (b - a);
        q[axis] = p;
        add(q);
      }
    }
  }
  if (!any) return Box{};
  Box r;
  r.lo = {round_down(lo.x), round_down(lo.y), round_down(lo.z)};
  r.hi = {round_up(hi.x), round_up(hi.y), round_up(hi.z)};
  return intersection(r, bound);
}

int Splitter::object_bin(float c, float lo, float scale) const {
  const int nb = s_.object_bins;
  const float k = (c - lo) * scale;  // may exceed int range for tiny extents
  if (!(k < static_cast<float>(nb - 1))) return nb - 1;
  return k > 0.0f ? static_cast<int>(k) : 0;
}

void Splitter::bin_objects(const Ref* refs, size_t n, const Box& cbox, const float* scale, const int* axes,
                           int axis_count, int sets, ObjectBin* bins) const {
  // object_bin() on all three axes at once, lane by lane the same float
  // operations, so that the partition (which calls object_bin) sends every
  // reference to the side its bin is on.
  const int nb = s_.object_bins;
  const Lane4 base{cbox.lo.x, cbox.lo.y, cbox.lo.z, 0.0f};
  const Lane4 scales{scale[0], scale[1], scale[2], 0.0f};
  const Lane4 last = lane4_splat(static_cast<float>(nb - 1)), zero = lane4_splat(0.0f);
  const size_t set_size = size_t(axis_count) * nb;
  auto add = [&](const Ref& r, ObjectBin* set) {
    const Lane4 lo = ref_lo(r), hi = ref_hi(r);
    const Lane4 c = (lo + hi) * 0.5f;
    Lane4 k = (c - base) * scales;
    k = k < last ? k : last;  // NaN and beyond: the last bin
    k = k > zero ? k : zero;
    typedef int Int4 __attribute__((vector_size(16)));
    const Int4 bin = __builtin_convertvector(k, Int4);
    const bool splittable = prims_.splittable(r.prim);
    for (int a = 0; a < axis_count; ++a) {
      ObjectBin& b = set[a * nb + bin[axes[a]]];
      b.lo = lane4_min(b.lo, lo);
      b.hi = lane4_max(b.hi, hi);
      b.centroid_lo = lane4_min(b.centroid_lo, c);
      b.centroid_hi = lane4_max(b.centroid_hi, c);
      ++b.count;
      b.splittable = b.splittable || splittable;
    }
  };
  // Neighbouring references tend to fall in the same bin, and each update
  // of a bin waits for the previous one: two sets of bins, for even and
  // odd references, halve that chain.
  size_t i = 0;
  if (sets == 2)
    for (; i + 1 < n; i += 2) {
      add(refs[i], bins);
      add(refs[i + 1], bins + set_size);
    }
  for (; i < n; ++i) add(refs[i], bins);
}

Split Splitter::object_split(const Ref* refs, size_t n, const Box& cbox, const Workers* workers) {
  const int nb = s_.object_bins;
  float scale[3] = {0.0f, 0.0f, 0.0f};
  int axes[3], axis_count = 0;  // the axes binned
  const glm::vec3 e = cbox.hi - cbox.lo;
  const int widest = (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
  for (int axis = 0; axis < 3; ++axis) {
    const float extent = cbox.hi[axis] - cbox.lo[axis];
    if (!(extent > 0.0f) || (s_.widest_axis_only && axis != widest)) continue;
    scale[axis] = nb / extent;
    axes[axis_count++] = axis;
  }
  Split best;
  if (axis_count == 0) return best;
  const int chunks = workers ? workers->chunks(n) : 1;
  object_chunks_ = chunks;
  const int sets = n >= 64 ? 2 : 1;
  // Per chunk `sets` sets of bins, then their sum; a set holds the bins of
  // the axes binned, one after the other.
  const size_t set_size = size_t(axis_count) * nb, chunk_size = set_size * sets;
  object_bins_.assign(chunk_size * chunks + set_size, ObjectBin{});
  auto bin_chunk = [&](int c, size_t b, size_t e) {
    bin_objects(refs + b, e - b, cbox, scale, axes, axis_count, sets, &object_bins_[c * chunk_size]);
  };
  if (chunks > 1)
    workers->for_chunks(n, chunks, bin_chunk);
  else
    bin_chunk(0, 0, n);
  ObjectBin* sum = &object_bins_[chunk_size * chunks];
  for (size_t j = 0; j < chunk_size * chunks; ++j) sum[j % set_size].add(object_bins_[j]);

  right_cost_.resize(nb);
  right_box_.resize(nb);
  int best_slot = 0;  // the best axis's place among the binned ones
  for (int a = 0; a < axis_count; ++a) {
    const int axis = axes[a];
    const ObjectBin* bins = sum + a * nb;
    // Sweep from the right storing area * count of everything right of
    // each plane, then from the left evaluating each plane.
    ObjectBin acc;
    for (int k = nb - 1; k > 0; --k) {
      acc.add(bins[k]);
      right_box_[k] = acc.box();
      right_cost_[k] = acc.count > 0 ? right_box_[k].half_area() * acc.count : -1.0;
    }
    acc = ObjectBin{};
    for (int k = 1; k < nb; ++k) {
      acc.add(bins[k - 1]);
      if (acc.count == 0 || right_cost_[k] < 0.0) continue;
      const double cost = acc.box().half_area() * acc.count + right_cost_[k];
      if (cost < best.cost) {
        best.kind = Split::kObject;
        best.cost = cost;
        best.axis = axis;
        best.bin = k;
        best.bin_lo = cbox.lo[axis];
        best.bin_scale = scale[axis];
        best_slot = a;
      }
    }
  }
  if (best.kind == Split::kNone) return best;
  // The children as the partition will leave them, and each chunk's share
  // of the left side, which places its references in the partition.
  const ObjectBin* bins = sum + best_slot * nb;
  ObjectBin left, right;
  for (int k = 0; k < nb; ++k) (k < best.bin ? left : right).add(bins[k]);
  best.left = left.bounds();
  best.right = right.bounds();
  best.left_count = left.count;
  chunk_left_.assign(chunks, 0);
  for (int c = 0; c < chunks; ++c)
    for (int set = 0; set < sets; ++set)
      for (int k = 0; k < best.bin; ++k)
        chunk_left_[c] += object_bins_[c * chunk_size + set * set_size + best_slot * nb + k].count;
  return best;
}

size_t Splitter::object_partition(Ref* refs, size_t n, const Split& split, const Workers* workers) {
  // Out of place and stable: every reference is copied to the next free
  // slot of its side, the slot chosen without a branch (which side a
  // reference goes to is a coin toss near the root, and mispredicted
  // branches made the in-place partition the build's largest cost). Chunk
  // c's references go after those of chunks before it on each side, which
  // is where a single pass would put them.
  Ref* out = partitioned_.reserve(n);
  const int chunks = object_chunks_;
  auto partition_chunk = [&](int c, size_t b, size_t e) {
    size_t left = 0, right = split.left_count;
    for (int k = 0; k < c; ++k) left += chunk_left_[k];
    right += b - left;
    for (size_t i = b; i < e; ++i) {
      const Ref& r = refs[i];
      const float centroid = 0.5f * (r.box.lo[split.axis] + r.box.hi[split.axis]);
      const bool goes_left = object_bin(centroid, split.bin_lo, split.bin_scale) < split.bin;
      out[goes_left ? left : right] = r;
      left += goes_left;
      right += !goes_left;
    }
  };
  auto copy_back = [&](int, size_t b, size_t e) { std::memcpy(refs + b, out + b, (e - b) * sizeof(Ref)); };
  if (chunks > 1 && workers) {
    workers->for_chunks(n, chunks, partition_chunk);
    workers->for_chunks(n, chunks, copy_back);
  } else {
    partition_chunk(0, 0, n);
    copy_back(0, 0, n);
  }
  return split.left_count;
}

// Object median along the widest centroid axis; any halving will do when all
// centroids coincide.
size_t Splitter::median_partition(Ref* refs, size_t n, const Box& cbox) const {
  const glm::vec3 e = cbox.hi - cbox.lo;
  const int axis = (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
  const size_t mid = n / 2;
  std::nth_element(refs, refs + mid, refs + n,
                   [&](const Ref& a, const Ref& b) { return a.box.centroid()[axis] < b.box.centroid()[axis]; });
  return mid;
}

namespace {

// Spatial bin boundaries of one axis: planes[0] = node lo, planes[nb] = node
// hi. Bins are looked up against these stored floats, never re-derived, so
// that binning, the SAH estimate and the final partition all agree on which
// side of a plane a reference lies.
struct Planes {
  const float* p;
  int nb;
  float inv_step;

  // Largest j with p[j] <= x (0 when x is below the node).
  int bin_at(float x) const {
    const float f = (x - p[0]) * inv_step;
    int j = !(f > 0.0f) ? 0 : (f >= float(nb - 1) ? nb - 1 : int(f));
    while (j > 0 && p[j] > x) --j;
    while (j < nb - 1 && p[j + 1] <= x) ++j;
    return j;
  }
};

}  // namespace

void Splitter::bin_spatial(const Ref* refs, size_t n, int nb, const float* planes, const bool* active,
                           SpatialBin* bins) const {
  Planes axes[3];
  for (int axis = 0; axis < 3; ++axis) {
    const float* p = planes + axis * (nb + 1);
    axes[axis] = Planes{p, nb, active[axis] ? nb / (p[nb] - p[0]) : 0.0f};
  }
  for (size_t i = 0; i < n; ++i) {
    const Ref& r = refs[i];
    const bool split = prims_.splittable(r.prim);
    for (int axis = 0; axis < 3; ++axis) {
      if (!active[axis]) continue;
      const Planes& pl = axes[axis];
      SpatialBin* b = bins + axis * nb;
      if (!split) {  // spheres and cylinders go whole to their centroid's side
        SpatialBin& bin = b[pl.bin_at(r.box.centroid()[axis])];
        bin.box.grow(r.box);
        ++bin.enter;
        ++bin.exit;
        continue;
      }
      const float lo = r.box.lo[axis], hi = r.box.hi[axis];
      const int first = pl.bin_at(lo);
      int last = pl.bin_at(hi);
      while (last > first && pl.p[last] >= hi) --last;  // touching a plane is not crossing it
      ++b[first].enter;
      ++b[last].exit;
      if (first == last) {
        b[first].box.grow(r.box);
        continue;
      }
      // Bin j receives the triangle's vertices inside it and its sections
      // by the bin's two planes; each section (a segment) is computed once
      // and shared by the bins on either side. Plain float is enough here:
      // these boxes only estimate costs, the partition clips conservatively.
      const glm::vec3* v = prims_.vertices(r.prim);
      int ia = 0, ib = 1, ic = 2;  // vertex order along the axis
      if (v[ib][axis] < v[ia][axis]) std::swap(ia, ib);
      if (v[ic][axis] < v[ib][axis]) std::swap(ib, ic);
      if (v[ib][axis] < v[ia][axis]) std::swap(ia, ib);
      const glm::vec3 a = v[ia], m = v[ib], c = v[ic];
      const glm::vec3 ac = c - a, am = m - a, mc = c - m;
      const float xa = a[axis], xm = m[axis], xc = c[axis];
      Box below;  // section by the bin's lower plane
      if (lo > xa && lo < xc) {
        below.grow(a + ((lo - xa) / (xc - xa)) * ac);
        below.grow(lo < xm ? a + ((lo - xa) / (xm - xa)) * am : m + ((lo - xm) / (xc - xm)) * mc);
      }
      float bottom = lo;
      for (int j = first; j <= last; ++j) {
        const float top = j == last ? hi : pl.p[j + 1];
        Box above;
        if (top > xa && top < xc) {
          above.grow(a + ((top - xa) / (xc - xa)) * ac);
          above.grow(top < xm ? a + ((top - xa) / (xm - xa)) * am : m + ((top - xm) / (xc - xm)) * mc);
        }
        Box piece = below;
        piece.grow(above);
        if (xa >= bottom && xa <= top) piece.grow(a);
        if (xm >= bottom && xm <= top) piece.grow(m);
        if (xc >= bottom && xc <= top) piece.grow(c);
        const Box part = intersection(piece, r.box);
        if (!part.empty()) b[j].box.grow(part);
        below = above;
        bottom = top;
      }
    }
  }
}

Split Splitter::spatial_split(const Ref* refs, size_t n, const Box& box, uint64_t budget, const Workers* workers) {
  // Binning cost grows with the bins each reference crosses, and deep in the
  // tree references are as large as their node: small nodes get fewer bins.
  const int nb = static_cast<int>(std::clamp<size_t>(n, kMinSpatialBins, s_.spatial_bins));
  Split best;
  std::vector<float>& planes = planes_;
  planes.assign(3 * size_t(nb + 1), 0.0f);
  bool active[3];
  bool any = false;
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = box.lo[axis], hi = box.hi[axis], extent = hi - lo;
    active[axis] = extent > 0.0f && std::isfinite(extent);
    if (!active[axis]) continue;
    any = true;
    float* p = &planes[axis * (nb + 1)];
    for (int j = 0; j < nb; ++j) p[j] = std::min(lo + j * (extent / nb), hi);
    p[nb] = hi;
  }
  if (!any) return best;

  const int chunks = workers ? workers->chunks(n) : 1;
  spatial_bins_.assign(size_t(chunks) * 3 * nb, SpatialBin{});
  auto bin_chunk = [&](int c, size_t b, size_t e) {
    bin_spatial(refs + b, e - b, nb, planes.data(), active, &spatial_bins_[c * 3 * nb]);
  };
  if (chunks > 1)
    workers->for_chunks(n, chunks, bin_chunk);
  else
    bin_chunk(0, 0, n);
  for (int c = 1; c < chunks; ++c)
    for (int i = 0; i < 3 * nb; ++i) {
      const SpatialBin& o = spatial_bins_[c * 3 * nb + i];
      spatial_bins_[i].box.grow(o.box);
      spatial_bins_[i].enter += o.enter;
      spatial_bins_[i].exit += o.exit;
    }

  right_box_.resize(nb);
  right_count_.resize(nb);
  for (int axis = 0; axis < 3; ++axis) {
    if (!active[axis]) continue;
    const SpatialBin* bins = &spatial_bins_[axis * nb];
    const float* p = &planes[axis * (nb + 1)];
    Box acc;
    uint32_t count = 0;
    for (int k = nb - 1; k > 0; --k) {
      acc.grow(bins[k].box);
      count += bins[k].exit;
      right_box_[k] = acc;
      right_count_[k] = count;
    }
    acc = Box{};
    count = 0;
    for (int k = 1; k < nb; ++k) {
      acc.grow(bins[k - 1].box);
      count += bins[k - 1].enter;
      const uint32_t right = right_count_[k];
      if (count == 0 || right == 0 || !(p[k] > box.lo[axis] && p[k] < box.hi[axis])) continue;
      if (uint64_t(count) + right - n > budget) continue;
      const double cost = acc.half_area() * count + right_box_[k].half_area() * right;
      if (cost < best.cost) {
        best.kind = Split::kSpatial;
        best.cost = cost;
        best.axis = axis;
        best.plane = p[k];
      }
    }
  }
  return best;
}

size_t Splitter::spatial_partition(std::vector<Ref>& stack, size_t begin, const Split& split, uint64_t budget,
                                   uint64_t* duplicates) {
  const int axis = split.axis;
  const float plane = split.plane;
  const size_t end = stack.size();
  enum Side { kLeft, kRight, kBoth };
  auto side = [&](const Ref& r) {
    if (!prims_.splittable(r.prim)) return r.box.centroid()[axis] < plane ? kLeft : kRight;
    if (r.box.lo[axis] >= plane) return kRight;
    if (r.box.hi[axis] <= plane) return kLeft;
    return kBoth;
  };

  Box left, right;
  uint64_t nl = 0, nr = 0;
  for (size_t i = begin; i < end; ++i) {
    const Side s = side(stack[i]);
    if (s == kLeft) left.grow(stack[i].box), ++nl;
    if (s == kRight) right.grow(stack[i].box), ++nr;
  }

  // Reference unsplitting (Stich et al. section 4.4): a straddling triangle
  // goes whole to one side when that costs less than clipping it into both,
  // judged against the children as accumulated so far. Left references are
  // compacted in place (never ahead of the read position), right ones wait
  // in scratch_.
  scratch_.clear();
  size_t w = begin;
  uint64_t made = 0;
  for (size_t i = begin; i < end; ++i) {
    const Ref r = stack[i];
    const Side s = side(r);
    if (s == kLeft) {
      stack[w++] = r;
      continue;
    }
    if (s == kRight) {
      scratch_.push_back(r);
      continue;
    }
    const glm::vec3* v = prims_.vertices(r.prim);
    const Box lbox = clip_triangle(v, axis, r.box.lo[axis], plane, r.box);
    const Box rbox = clip_triangle(v, axis, plane, r.box.hi[axis], r.box);
    Box l_split = left, r_split = right, l_whole = left, r_whole = right;
    l_split.grow(lbox);
    r_split.grow(rbox);
    l_whole.grow(r.box);
    r_whole.grow(r.box);
    // A side the clip finds empty gets nothing; rounding can make the box
    // straddle while the triangle does not.
    const bool can_split = made < budget && !lbox.empty() && !rbox.empty();
    const double c_split = can_split ? l_split.half_area() * (nl + 1) + r_split.half_area() * (nr + 1)
                                     : std::numeric_limits<double>::max();
    const double c_left = rbox.empty() || !lbox.empty() ? l_whole.half_area() * (nl + 1) + right.half_area() * nr
                                                        : std::numeric_limits<double>::max();
    const double c_right = lbox.empty() || !rbox.empty() ? left.half_area() * nl + r_whole.half_area() * (nr + 1)
                                                         : std::numeric_limits<double>::max();
    if (c_split <= c_left && c_split <= c_right) {
      stack[w++] = Ref{lbox, r.prim};
      scratch_.push_back(Ref{rbox, r.prim});
      left = l_split;
      right = r_split;
      ++nl;
      ++nr;
      ++made;
    } else if (c_left <= c_right) {
      stack[w++] = r;
      left = l_whole;
      ++nl;
    } else {
      scratch_.push_back(r);
      right = r_whole;
      ++nr;
    }
  }
  stack.resize(w);
  stack.insert(stack.end(), scratch_.begin(), scratch_.end());
  *duplicates += made;
  return w - begin;
}

}  // namespace caustica::bvh_detail
