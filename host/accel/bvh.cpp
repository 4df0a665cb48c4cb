#include "host/accel/bvh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>

#include "host/accel/bvh_internal.h"

namespace caustica {
namespace {

using namespace bvh_detail;

// A spatial split is only searched for where the best object split leaves
// children overlapping by more than this fraction of the root's area: below
// it the clipping work is wasted (Stich et al. suggest 1e-5).
constexpr double kSpatialOverlap = 1e-5;
// Duplicated references allowed, per primitive. A budget of 1.0 lowered the
// SAH cost of the conference room and Sponza by under 1% more than 0.3 does,
// for more memory and a slower build.
constexpr double kSpatialBudget = 0.3;
// Spatial bins per axis (at most; small nodes use fewer). Finer than the
// object bins: a plane through long triangles must land where their pieces'
// boxes shrink most, and 16 bins cost the conference room 4% in SAH.
constexpr int kSpatialBins = 32;
// Subtrees of at most this many references (or n / kJobsPerScene, if
// larger) become independent jobs for the worker threads. Neither depends
// on the thread count, and the tree does not depend on either.
constexpr size_t kMinJobRefs = 4096;
constexpr size_t kJobsPerScene = 64;

Box box_around(const glm::dvec3& center, const glm::dvec3& extent) {
  Box b;
  b.lo = {round_down(center.x - extent.x), round_down(center.y - extent.y), round_down(center.z - extent.z)};
  b.hi = {round_up(center.x + extent.x), round_up(center.y + extent.y), round_up(center.z + extent.z)};
  return b;
}

Box sphere_box(const Sphere& s) {
  double r = s.center_radius.w;
  return box_around(glm::dvec3(to_vec3(s.center_radius)), glm::dvec3(r));
}

// Tight box of a capped cylinder: along world axis i the two cap discs reach
// |a_i| * half from the centre plus the disc's own extent r * sqrt(1 - a_i^2).
Box cylinder_box(const Cylinder& c) {
  glm::dvec3 a = glm::dvec3(to_vec3(c.axis_half));
  double half = c.axis_half.w, r = c.center_radius.w;
  glm::dvec3 e;
  for (int i = 0; i < 3; ++i) e[i] = std::abs(a[i]) * half + r * std::sqrt(std::max(0.0, 1.0 - a[i] * a[i]));
  return box_around(glm::dvec3(to_vec3(c.center_radius)), e);
}

Box triangle_box(const Triangle& t) {
  Box b;
  b.grow(to_vec3(t.v0));
  b.grow(to_vec3(t.v1));
  b.grow(to_vec3(t.v2));
  return b;
}

int ceil_log2(uint64_t n) {
  int k = 0;
  while ((uint64_t{1} << k) < n) ++k;
  return k;
}

uint32_t make_ref(uint32_t type, size_t index) {
  return (type << PRIM_TYPE_SHIFT) | (static_cast<uint32_t>(index) & PRIM_INDEX_MASK);
}

// The tree as built, before flattening. Subtrees built on different threads
// live in different arenas; flattening walks them in a fixed order, which
// is what makes the result independent of the thread count.
struct BuildNode {
  enum Kind : uint8_t { kInner, kLeaf, kLink };
  Box box;
  uint32_t a = 0, b = 0;  // inner: left, right child; leaf: first ref, count; link: job index
  Kind kind = kInner;
};

struct Arena {
  std::vector<BuildNode> nodes;  // a subtree's root is its first node
  std::vector<uint32_t> refs;    // leaf contents, as kernel prim refs
};

// A job's references where no spatial split can add any: a range of the
// top builder's array, which nothing else touches once handed off, so it
// is built in place rather than copied (10 MB of copying and page faults
// on the conference room). The stack only shrinks there.
class RefSpan {
 public:
  RefSpan() = default;
  RefSpan(Ref* data, size_t size) : data_(data), size_(size) {}
  size_t size() const { return size_; }
  void resize(size_t n) { size_ = n; }
  Ref& operator[](size_t i) { return data_[i]; }
  Ref* begin() { return data_; }
  Ref* end() { return data_ + size_; }

 private:
  Ref* data_ = nullptr;
  size_t size_ = 0;
};

struct Job {
  std::vector<Ref> refs;  // its own copy, when spatial splits may grow it
  RefSpan span;           // otherwise
  int depth = 0;
  uint64_t budget = 0;
  Arena arena;
};

class JobQueue;

// Builds one subtree depth-first. References live on `stack`: a node owns
// the top range, and splitting replaces it by the left then the right
// child's references, so the right child (on top) is built first.
class SubtreeBuilder {
 public:
  SubtreeBuilder(const Settings& settings, const Prims& prims, Splitter& splitter, Arena& arena)
      : s_(settings), prims_(prims), splitter_(splitter), arena_(arena) {}

  // The top of the tree: large nodes bin on all threads, and subtrees of at
  // most `threshold` references are left to jobs.
  void spawn_jobs(const Workers* workers, JobQueue* jobs, size_t threshold) {
    workers_ = workers;
    jobs_ = jobs;
    job_threshold_ = threshold;
  }

  // `known`: the references' bounds when the parent's partition gathered them.
  // Stack: std::vector<Ref>, or RefSpan where there are no spatial splits.
  template <class Stack>
  uint32_t build(Stack& stack, size_t begin, int depth, uint64_t budget, const RefBounds* known = nullptr) {
    const size_t n = stack.size() - begin;
    const uint32_t id = static_cast<uint32_t>(arena_.nodes.size());
    if (jobs_ && n <= job_threshold_) {
      Job job;
      if (s_.spatial_bins > 0)
        job.refs.assign(stack.begin() + begin, stack.end());
      else
        job.span = RefSpan(&stack[begin], n);
      job.depth = depth;
      job.budget = budget;
      stack.resize(begin);
      arena_.nodes.push_back(BuildNode{Box{}, hand_off(std::move(job)), 0, BuildNode::kLink});
      return id;
    }
    const RefBounds bd = known ? *known : bounds(&stack[begin], n);
    arena_.nodes.push_back(BuildNode{bd.box, 0, 0, BuildNode::kInner});

    if (n <= size_t(s_.max_leaf) || depth >= s_.max_depth) {
      BuildNode& leaf = arena_.nodes[id];
      leaf.kind = BuildNode::kLeaf;
      leaf.a = static_cast<uint32_t>(arena_.refs.size());
      leaf.b = static_cast<uint32_t>(n);
      for (size_t i = begin; i < stack.size(); ++i) arena_.refs.push_back(prims_.codes[stack[i].prim]);
      stack.resize(begin);
      return id;
    }

    // Median splits halve the count, so once the levels left barely suffice
    // for them, SAH (which may peel off one reference per level, and spatial
    // splits, which may keep all of them on one side) must stop.
    size_t left_count = 0;
    uint64_t duplicates = 0;
    RefBounds sides[2];
    const RefBounds* children = nullptr;  // sides, when the object split's binning gave them
    if (ceil_log2(n) < s_.max_depth - depth) {
      const Workers* workers = helpers();
      const Split object = splitter_.object_split(&stack[begin], n, bd.centroids, workers);
      if constexpr (std::is_same<Stack, std::vector<Ref>>::value) {  // spatial splits may grow the stack
        if (s_.spatial_bins > 0 && bd.splittable && budget > 0 &&
            (object.kind == Split::kNone ||
             intersection(object.left.box, object.right.box).half_area() > s_.min_overlap)) {
          const Split spatial = splitter_.spatial_split(&stack[begin], n, bd.box, budget, workers);
          if (spatial.kind != Split::kNone && spatial.cost < object.cost) {
            left_count = splitter_.spatial_partition(stack, begin, spatial, budget, &duplicates);
            // All on one side means nothing was clipped and the order is
            // unchanged: the object split still applies.
            if (left_count == stack.size() - begin) left_count = 0;
          }
        }
      }
      if (left_count == 0 && object.kind != Split::kNone) {
        left_count = splitter_.object_partition(&stack[begin], n, object, workers);
        sides[0] = object.left;
        sides[1] = object.right;
        children = sides;
      }
    }
    if (left_count == 0) left_count = splitter_.median_partition(&stack[begin], n, bd.centroids);

    // The budget left is shared in proportion to the children's sizes: a
    // deterministic rule (unlike a global counter raced for by threads).
    const size_t total = stack.size() - begin;
    const uint64_t rest = budget - duplicates;
    const uint64_t left_budget = rest * left_count / total;
    const uint32_t right =
        build(stack, begin + left_count, depth + 1, rest - left_budget, children ? &children[1] : nullptr);
    const uint32_t left = build(stack, begin, depth + 1, left_budget, children ? &children[0] : nullptr);
    arena_.nodes[id].a = left;
    arena_.nodes[id].b = right;
    return id;
  }

 private:
  RefBounds bounds(const Ref* refs, size_t n) const {
    auto scan = [&](size_t b, size_t e) {
      RefBounds r;
      for (size_t i = b; i < e; ++i) {
        r.box.grow(refs[i].box);
        r.centroids.grow(refs[i].box.centroid());
        r.splittable = r.splittable || prims_.splittable(refs[i].prim);
      }
      return r;
    };
    const Workers* workers = helpers();
    const int chunks = workers ? workers->chunks(n) : 1;
    if (chunks <= 1) return scan(0, n);
    std::vector<RefBounds> part(chunks);
    workers->for_chunks(n, chunks, [&](int c, size_t b, size_t e) { part[c] = scan(b, e); });
    for (int c = 1; c < chunks; ++c) part[0].merge(part[c]);
    return part[0];
  }

  const Settings& s_;
  const Prims& prims_;
  Splitter& splitter_;
  Arena& arena_;
  const Workers* workers_ = nullptr;
  uint32_t hand_off(Job job);  // queues a job; defined after JobQueue
  // Threads for one node's binning: only until the first job is queued,
  // after which the workers have subtrees to build and extra threads would
  // only take turns with them.
  const Workers* helpers() const;

  JobQueue* jobs_ = nullptr;
  size_t job_threshold_ = 0;
};

// Subtrees handed off by the top of the build. Worker threads build each as
// soon as it is queued, while the calling thread goes on splitting the top
// levels (whose partitions are sequential), and joins them when it is done.
// Each subtree depends on its own references only, so neither the order nor
// the thread count changes the tree.
class JobQueue {
 public:
  JobQueue(const Settings& settings, const Prims& prims, int threads) : settings_(settings), prims_(prims) {
    for (int t = 1; t < threads; ++t) pool_.emplace_back([this] { work(); });
  }
  ~JobQueue() { close(); }

  // Queues a job; returns its index, which the flattening uses.
  uint32_t push(Job job) {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
    ready_.notify_one();
    return static_cast<uint32_t>(jobs_.size() - 1);
  }

  size_t queued() {
    std::lock_guard<std::mutex> lock(mutex_);
    return jobs_.size();
  }

  // Builds what is left on the calling thread too, then waits for the rest.
  const std::deque<Job>& finish() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
      ready_.notify_all();
    }
    work();
    close();
    if (error_) std::rethrow_exception(error_);
    return jobs_;
  }

 private:
  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
      ready_.notify_all();
    }
    for (std::thread& t : pool_) t.join();
    pool_.clear();
  }

  void work() {
    try {
      Splitter splitter(settings_, prims_);
      for (;;) {
        Job* job;
        {
          std::unique_lock<std::mutex> lock(mutex_);
          ready_.wait(lock, [this] { return next_ < jobs_.size() || closed_; });
          if (next_ == jobs_.size()) return;
          job = &jobs_[next_++];  // deque elements stay put while others are pushed
        }
        SubtreeBuilder builder(settings_, prims_, splitter, job->arena);
        if (settings_.spatial_bins > 0) {
          builder.build(job->refs, 0, job->depth, job->budget);
          std::vector<Ref>().swap(job->refs);
        } else {
          builder.build(job->span, 0, job->depth, job->budget);
        }
      }
    } catch (...) {  // the first failure (out of memory) is rethrown by finish()
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      next_ = jobs_.size();
      closed_ = true;
      ready_.notify_all();
    }
  }

  const Settings& settings_;
  const Prims& prims_;
  std::deque<Job> jobs_;
  size_t next_ = 0;
  bool closed_ = false;
  std::exception_ptr error_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::vector<std::thread> pool_;
};

uint32_t SubtreeBuilder::hand_off(Job job) { return jobs_->push(std::move(job)); }
const Workers* SubtreeBuilder::helpers() const { return jobs_ && jobs_->queued() > 0 ? nullptr : workers_; }

class Flattener {
 public:
  Flattener(Bvh& out, const std::deque<Job>& jobs, double root_area) : out_(out), jobs_(jobs), root_area_(root_area) {}

  void emit(const Arena& arena, uint32_t id, int depth) {
    const BuildNode& b = arena.nodes[id];
    if (b.kind == BuildNode::kLink) return emit(jobs_[b.a].arena, 0, depth);
    const uint32_t index = static_cast<uint32_t>(out_.nodes.size());
    out_.nodes.push_back(BvhNode{b.box.lo.x, b.box.lo.y, b.box.lo.z, 0u, b.box.hi.x, b.box.hi.y, b.box.hi.z, 0u});
    out_.max_depth = std::max(out_.max_depth, depth);
    const double area = root_area_ > 0.0 ? b.box.half_area() / root_area_ : 1.0;
    if (b.kind == BuildNode::kLeaf) {
      out_.nodes[index].offset = static_cast<uint32_t>(out_.prim_refs.size());
      out_.nodes[index].count = b.b;
      out_.prim_refs.insert(out_.prim_refs.end(), arena.refs.begin() + b.a, arena.refs.begin() + b.a + b.b);
      out_.sah_cost += area * b.b;
      return;
    }
    out_.sah_cost += area;
    emit(arena, b.a, depth + 1);
    out_.nodes[index].offset = static_cast<uint32_t>(out_.nodes.size());
    emit(arena, b.b, depth + 1);
  }

 private:
  Bvh& out_;
  const std::deque<Job>& jobs_;
  double root_area_;
};

void build_nonempty(const Scene& scene, const BvhBuildOptions& options, Bvh& bvh) {
  using Quality = BvhBuildOptions::Quality;
  Settings settings;
  settings.max_leaf = std::max(1, options.max_leaf_size);
  settings.object_bins = std::clamp(options.bins, 2, 256);
  settings.max_depth = std::clamp(options.max_depth, 0, kBvhMaxDepth);
  if (options.quality == Quality::Fast) {
    settings.object_bins = std::min(settings.object_bins, 8);
    settings.widest_axis_only = true;
    settings.max_leaf *= 2;
  }
  if (options.quality == Quality::Spatial) settings.spatial_bins = kSpatialBins;
  const int threads = resolve_threads(options.threads);

  Workers workers(threads);
  Prims prims;
  const size_t n = scene.primitive_count();
  std::vector<Ref> refs(n);
  prims.codes.resize(n);
  std::vector<RefBounds> part(1);
  auto add = [&](RefBounds& bounds, size_t i, const Box& box, uint32_t code) {
    refs[i].box = box;
    refs[i].prim = static_cast<uint32_t>(i);
    prims.codes[i] = code;
    bounds.box.grow(box);
    bounds.centroids.grow(box.centroid());
  };
  for (size_t i = 0; i < scene.spheres.size(); ++i) add(part[0], i, sphere_box(scene.spheres[i]), make_ref(PRIM_SPHERE, i));
  for (size_t i = 0; i < scene.cylinders.size(); ++i)
    add(part[0], scene.spheres.size() + i, cylinder_box(scene.cylinders[i]), make_ref(PRIM_CYLINDER, i));
  prims.first_triangle = static_cast<uint32_t>(scene.spheres.size() + scene.cylinders.size());
  if (settings.spatial_bins > 0) prims.triangle_vertices.resize(3 * scene.triangles.size());
  // Triangles, the bulk of large scenes, on all threads; the root's bounds
  // are gathered on the way (merged with exact min/max, so per chunk).
  const int chunks = workers.chunks(scene.triangles.size());
  part.resize(std::max(1, chunks));
  part[0].splittable = !scene.triangles.empty();
  workers.for_chunks(scene.triangles.size(), chunks, [&](int c, size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) {
      const Triangle& t = scene.triangles[i];
      add(part[c], prims.first_triangle + i, triangle_box(t), make_ref(PRIM_TRIANGLE, i));
      if (settings.spatial_bins > 0) {
        prims.triangle_vertices[3 * i + 0] = to_vec3(t.v0);
        prims.triangle_vertices[3 * i + 1] = to_vec3(t.v1);
        prims.triangle_vertices[3 * i + 2] = to_vec3(t.v2);
      }
    }
  });
  RefBounds root = part[0];
  for (size_t c = 1; c < part.size(); ++c) root.merge(part[c]);
  const double root_area = root.box.half_area();
  settings.min_overlap = kSpatialOverlap * root_area;
  const uint64_t budget = settings.spatial_bins > 0 ? static_cast<uint64_t>(kSpatialBudget * n) : 0;

  Splitter splitter(settings, prims);
  Arena top;
  JobQueue queue(settings, prims, threads);
  SubtreeBuilder builder(settings, prims, splitter, top);
  builder.spawn_jobs(threads > 1 ? &workers : nullptr, &queue, std::max(kMinJobRefs, n / kJobsPerScene));
  builder.build(refs, 0, 0, budget, &root);
  const std::deque<Job>& jobs = queue.finish();  // before refs go: jobs may be built in them
  std::vector<Ref>().swap(refs);

  size_t nodes = top.nodes.size(), references = top.refs.size();
  for (const Job& job : jobs) {
    nodes += job.arena.nodes.size();
    references += job.arena.refs.size();
  }
  bvh.nodes.reserve(nodes);
  bvh.prim_refs.reserve(references);
  Flattener(bvh, jobs, root_area).emit(top, 0, 0);
  bvh.references = bvh.prim_refs.size();
}

}  // namespace

Bvh build_bvh(const Scene& scene, const BvhBuildOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  Bvh bvh;
  if (scene.primitive_count() == 0)
    bvh.nodes.push_back(BvhNode{kEmptyLo, kEmptyLo, kEmptyLo, 0u, kEmptyHi, kEmptyHi, kEmptyHi, 0u});
  else
    build_nonempty(scene, options, bvh);
  bvh.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return bvh;
}

}  // namespace caustica
