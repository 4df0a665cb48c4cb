#include "host/accel/bvh_wide.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <string>

#include "host/accel/bvh_wide_internal.h"
#include "host/error.h"

namespace caustica {
namespace {

using wide_detail::CollapsePlan;
using wide_detail::is_triangle;
using wide_detail::kBlockLanes;
using wide_detail::node_box;
constexpr uint32_t kMaxInnerNodes = WIDE_NODE_INDEX_MASK + 1;

// The builder's box (finite empty sentinels, half-area for SAH ratios).
using bvh_detail::Box;
using bvh_detail::kEmptyHi;
using bvh_detail::kEmptyLo;

uint32_t wide_leaf_count(uint32_t child) { return ((child >> WIDE_LEAF_COUNT_SHIFT) & (WIDE_LEAF_MAX_COUNT - 1u)) + 1u; }

// Leaf references that fit one child slot: up to WIDE_LEAF_MAX_COUNT blocks
// of triangles, or up to WIDE_LEAF_MAX_COUNT other references.
struct Chunk {
  Box box;
  bool triangles = false;
  std::vector<uint32_t> refs;
};

// A child slot while a wide node is assembled: a binary inner node, which
// may still be opened, or leaf chunks (several of them are opened when the
// node has room, and otherwise get a wide node of their own).
struct Slot {
  Box box;
  int64_t node = -1;
  bool planned = false;  // node: its wide node's children come from the cost-driven plan
  std::vector<Chunk> chunks;
  bool openable(size_t free_slots) const {
    return node >= 0 || (chunks.size() > 1 && chunks.size() - 1 <= free_slots);
  }
};

// What emitting a subtree produces: its wide nodes in depth-first order
// (indices from 0, the subtree's root first), its leaves' triangle blocks
// (numbered from 0; only their references, fill_blocks() writes them) and
// other references. Subtrees below the drafted top of the tree are emitted
// on all threads, each into its own Emission, and joined depth first with
// their indices offset (Collapser::emit_root): the same layout as emitting
// the whole tree in one recursion.
struct Emission {
  std::vector<BvhNode8> nodes;
  std::vector<uint32_t> prim_refs;
  std::vector<uint32_t> block_refs;  // kBlockLanes references per numbered block
  uint32_t blocks = 0;
  size_t triangle_lanes = 0, leaves = 0;
  double node_sah = 0.0, leaf_sah = 0.0;
  std::vector<uint32_t> scratch_refs, scratch_tris, scratch_others;  // leaf_slot's, kept across calls
};

class Collapser {
 public:
  Collapser(const Bvh& bvh, const Scene& scene, const WideBvhOptions& options, WideBvh& out)
      : bvh_(bvh), scene_(scene), options_(options), out_(out) {}

  void run() {
    duplicates_ = bvh_.references > scene_.primitive_count();
    count_triangles();
    const BvhNode& root = bvh_.nodes[0];
    if (bvh_.nodes.size() == 1 && root.count == 0) {  // the empty scene
      out_.nodes.push_back(empty_node());
      out_.nodes[0].height = 1;
      out_.height = 1;
      return;
    }
    const double root_area = node_box(root).half_area();
    Emission scratch;  // for the root's own slots
    std::vector<Slot> slots;
    if (options_.collapse == WideBvhOptions::Collapse::Sah) {
      plan_ = wide_detail::plan_collapse(bvh_, duplicates_, options_);
      slots = planned_children(scratch, 0);
    } else {
      slots = {make_slot(scratch, 0)};
    }
    emit_root(scratch, std::move(slots), root_area);
    fill_blocks();
    // Normalised by the box a ray must enter, the union of the root's slots
    // (the binary root's box, or less where leaf boxes were tightened).
    Box entered;
    const BvhNode8& top = out_.nodes[0];
    for (int i = 0; i < WIDE_WIDTH; ++i)
      if (top.child[i] != WIDE_CHILD_EMPTY) {
        entered.grow(glm::vec3(top.lo_x[i], top.lo_y[i], top.lo_z[i]));
        entered.grow(glm::vec3(top.hi_x[i], top.hi_y[i], top.hi_z[i]));
      }
    const double entered_area = entered.half_area();
    if (entered_area > 0.0) {
      out_.node_sah = (out_.node_sah - root_area + entered_area) / entered_area;
      out_.leaf_sah /= entered_area;
    }
    out_.height = static_cast<int>(out_.nodes[0].height);
    if (out_.height >= kWideStackSize)
      throw Error("wide BVH: " + std::to_string(out_.height) + " levels deep, the traversal stack holds " +
                  std::to_string(kWideStackSize - 1));
  }

 private:
  static BvhNode8 empty_node() {
    BvhNode8 n{};
    for (int i = 0; i < WIDE_WIDTH; ++i) {
      n.lo_x[i] = n.lo_y[i] = n.lo_z[i] = kEmptyLo;
      n.hi_x[i] = n.hi_y[i] = n.hi_z[i] = kEmptyHi;
      n.child[i] = WIDE_CHILD_EMPTY;
    }
    return n;
  }

  // Triangles under each binary node (references, duplicates included), or
  // UINT32_MAX when the subtree holds anything else: decides which subtrees
  // merge into one block. Children follow their parent in the depth-first
  // layout, so one backward sweep sees them first.
  void count_triangles() {
    const size_t n = bvh_.nodes.size();
    triangles_.assign(n, 0);
    subtree_end_.assign(n, 0);
    for (size_t i = n; i-- > 0;) {
      const BvhNode& node = bvh_.nodes[i];
      subtree_end_[i] = node.count > 0 || node.offset <= i ? uint32_t(i + 1) : subtree_end_[node.offset];
      if (node.count > 0) {
        uint32_t c = 0;
        for (uint32_t k = node.offset; k < node.offset + node.count; ++k)
          c = (c == UINT32_MAX || !is_triangle(bvh_.prim_refs[k])) ? UINT32_MAX : c + 1;
        triangles_[i] = c;
      } else if (i + 1 < n && node.offset > i) {
        const uint32_t a = triangles_[i + 1], b = triangles_[node.offset];
        triangles_[i] = (a == UINT32_MAX || b == UINT32_MAX) ? UINT32_MAX : a + b;
      }
    }
  }

  bool leaf_like(int64_t node) const {
    const BvhNode& n = bvh_.nodes[node];
    return n.count > 0 || (options_.merge_small_subtrees && triangles_[node] <= options_.merge_max_triangles);
  }

  // The references under `node` and the union of its binary leaves' boxes.
  void gather(int64_t node, std::vector<uint32_t>& refs, Box& leaf_union) const {
    const BvhNode& n = bvh_.nodes[node];
    if (n.count > 0) {
      refs.insert(refs.end(), bvh_.prim_refs.begin() + n.offset, bvh_.prim_refs.begin() + n.offset + n.count);
      leaf_union.grow(node_box(n));
      return;
    }
    gather(node + 1, refs, leaf_union);
    gather(n.offset, refs, leaf_union);
  }

  Box triangle_box(uint32_t ref) const {
    const Triangle& t = scene_.triangles[ref & PRIM_INDEX_MASK];
    Box b;
    b.grow(to_vec3(t.v0));
    b.grow(to_vec3(t.v1));
    b.grow(to_vec3(t.v2));
    return b;
  }

  Slot make_slot(Emission& e, int64_t node) const {
    if (!leaf_like(node)) {
      Slot slot;
      slot.box = node_box(bvh_.nodes[node]);
      slot.node = node;
      return slot;
    }
    return leaf_slot(e, node);
  }

  // Every reference under `node` as leaf chunks (one slot; several chunks
  // when the references are of both kinds or too many for one chunk).
  Slot leaf_slot(Emission& e, int64_t node) const {
    Slot slot;
    slot.box = node_box(bvh_.nodes[node]);
    // Scratch vectors kept across calls: this runs once per leaf.
    std::vector<uint32_t>& refs = e.scratch_refs;
    std::vector<uint32_t>& tris = e.scratch_tris;
    std::vector<uint32_t>& others = e.scratch_others;
    refs.clear();
    tris.clear();
    others.clear();
    Box leaf_union;
    gather(node, refs, leaf_union);
    // A merged subtree may hold a spatially split triangle twice; only
    // builds with spatial splits make duplicates.
    if (duplicates_) {
      std::sort(refs.begin(), refs.end());
      refs.erase(std::unique(refs.begin(), refs.end()), refs.end());
    }
    for (uint32_t r : refs) (is_triangle(r) ? tris : others).push_back(r);
    const size_t per_tri_chunk = WIDE_LEAF_MAX_COUNT * kBlockLanes;
    for (size_t i = 0; i < tris.size(); i += per_tri_chunk) {
      Chunk c;
      c.triangles = true;
      c.refs.assign(tris.begin() + i, tris.begin() + std::min(tris.size(), i + per_tri_chunk));
      if (others.empty() && tris.size() <= per_tri_chunk) {
        // Each binary leaf's box bounds the parts of its triangles it is
        // responsible for (clipped ones, after spatial splits), so their
        // union is the tightest box of one chunk holding them all, and it
        // costs no reads of the triangles.
        c.box = leaf_union;
      } else {
        // Chunks of part of the references: the box of their triangles,
        // restricted to this subtree's (which may be a clipped part of them).
        for (uint32_t r : c.refs) c.box.grow(triangle_box(r));
        c.box.lo = glm::max(c.box.lo, slot.box.lo);
        c.box.hi = glm::min(c.box.hi, slot.box.hi);
      }
      slot.chunks.push_back(std::move(c));
    }
    for (size_t i = 0; i < others.size(); i += WIDE_LEAF_MAX_COUNT) {
      Chunk c;
      c.box = slot.box;  // sphere and cylinder boxes need the builder's outward rounding: keep its box
      c.refs.assign(others.begin() + i, others.begin() + std::min(others.size(), i + size_t{WIDE_LEAF_MAX_COUNT}));
      slot.chunks.push_back(std::move(c));
    }
    if (slot.chunks.size() == 1) slot.box = slot.chunks[0].box;
    return slot;
  }

  // Replaces an opened slot by its parts.
  std::vector<Slot> open(Emission& e, const Slot& slot) const {
    std::vector<Slot> parts;
    if (slot.node >= 0) {
      parts.push_back(make_slot(e, slot.node + 1));
      parts.push_back(make_slot(e, bvh_.nodes[slot.node].offset));
      return parts;
    }
    for (const Chunk& c : slot.chunks) {
      Slot s;
      s.box = c.box;
      s.chunks = {c};
      parts.push_back(std::move(s));
    }
    return parts;
  }

  // The child slots of `node` as a subtree given at most `slots` of them.
  void planned_slots(Emission& e, int64_t node, int slots, std::vector<Slot>& out) const {
    const int8_t c = plan_.nodes[node].choice[slots - 1];
    if (c == CollapsePlan::kFewer) {
      planned_slots(e, node, slots - 1, out);
    } else if (c > 0) {
      planned_slots(e, node + 1, c, out);
      planned_slots(e, bvh_.nodes[node].offset, slots - c, out);
    } else if (c == CollapsePlan::kLeaf) {
      Slot leaf = leaf_slot(e, node);
      if (leaf.chunks.size() == 1) {
        out.push_back(std::move(leaf));
      } else {
        for (Slot& part : open(e, leaf)) out.push_back(std::move(part));
      }
    } else {
      Slot s;
      s.box = node_box(bvh_.nodes[node]);
      s.node = node;
      s.planned = true;
      out.push_back(std::move(s));
    }
  }

  // The slots of the wide node made for binary `node`.
  std::vector<Slot> planned_children(Emission& e, int64_t node) const {
    std::vector<Slot> slots;
    const BvhNode& n = bvh_.nodes[node];
    if (n.count > 0) {  // a leaf too big (or too mixed) for the slots above it
      Slot leaf = leaf_slot(e, node);
      if (leaf.chunks.size() <= WIDE_WIDTH) return open(e, leaf);
      leaf.planned = false;
      slots.push_back(std::move(leaf));  // emit_node groups the chunks
      return slots;
    }
    const int k = plan_.nodes[node].split;
    planned_slots(e, node + 1, k, slots);
    planned_slots(e, n.offset, WIDE_WIDTH - k, slots);
    return slots;
  }

  uint32_t emit_leaf(Emission& e, const Chunk& c) const {
    uint32_t first, count;
    if (c.triangles) {
      // The blocks are only numbered here; fill_blocks() writes them.
      first = e.blocks;
      count = static_cast<uint32_t>((c.refs.size() + kBlockLanes - 1) / kBlockLanes);
      e.blocks += count;
      e.triangle_lanes += c.refs.size();
      for (size_t b = 0; b < count; ++b) {
        const size_t lanes = std::min(kBlockLanes, c.refs.size() - b * kBlockLanes);
        e.block_refs.insert(e.block_refs.end(), c.refs.begin() + b * kBlockLanes,
                           c.refs.begin() + b * kBlockLanes + lanes);
        e.block_refs.insert(e.block_refs.end(), kBlockLanes - lanes, c.refs[b * kBlockLanes]);  // padding repeats lane 0
      }
    } else {
      first = static_cast<uint32_t>(e.prim_refs.size());
      count = static_cast<uint32_t>(c.refs.size());
      e.prim_refs.insert(e.prim_refs.end(), c.refs.begin(), c.refs.end());
    }
    check_leaf_index(size_t{first} + count);
    return WIDE_LEAF_FLAG | (c.triangles ? 0u : WIDE_LEAF_PRIMS) | ((count - 1) << WIDE_LEAF_COUNT_SHIFT) | first;
  }

  // Writes every triangle block from its references, on all threads: the
  // scattered reads of the scene's triangles are most of the collapse's
  // memory traffic, and each block depends on its four references only.
  void fill_blocks() {
    const uint32_t blocks = static_cast<uint32_t>(block_refs_.size() / kBlockLanes);
    out_.triangle_blocks.resize(blocks);
    const bvh_detail::Workers workers(bvh_detail::resolve_threads(options_.threads));
    workers.for_chunks(blocks, workers.chunks(blocks), [this](int, size_t begin, size_t end) {
      for (size_t b = begin; b < end; ++b) {
        TriangleBlock4& block = out_.triangle_blocks[b];
        for (size_t lane = 0; lane < kBlockLanes; ++lane) {
          const uint32_t ref = block_refs_[b * kBlockLanes + lane];
          const Triangle& t = scene_.triangles[ref & PRIM_INDEX_MASK];
          const cs_float4* v[3] = {&t.v0, &t.v1, &t.v2};
          for (int vertex = 0; vertex < 3; ++vertex) {
            block.v[3 * vertex + 0][lane] = v[vertex]->x;
            block.v[3 * vertex + 1][lane] = v[vertex]->y;
            block.v[3 * vertex + 2][lane] = v[vertex]->z;
          }
          block.ref[lane] = ref;
        }
      }
    });
  }

  static void check_leaf_index(size_t end) {
    if (end > WIDE_LEAF_INDEX_MASK) throw Error("wide BVH: too many leaf blocks for the child encoding");
  }
  static void check_node_count(size_t count) {
    if (count > kMaxInnerNodes) throw Error("wide BVH: more inner nodes than the traversal can address");
  }

  // The slots of a wide node: the plan fixes every slot but the chunks of a
  // leaf it had to wrap in a node of its own (too many chunks for the slots
  // above), which open here, as do all slots of a greedy collapse.
  std::vector<Slot> open_slots(Emission& e, std::vector<Slot> slots) const {
    const bool greedy = options_.collapse == WideBvhOptions::Collapse::Greedy ||
                        std::all_of(slots.begin(), slots.end(), [](const Slot& s) { return s.node < 0; });
    while (greedy && slots.size() < WIDE_WIDTH) {
      const size_t free_slots = WIDE_WIDTH - slots.size();
      int best = -1;
      double best_area = -1.0;
      for (size_t i = 0; i < slots.size(); ++i) {
        const double area = slots[i].box.half_area();
        if (slots[i].openable(free_slots) && area > best_area) {
          best = static_cast<int>(i);
          best_area = area;
        }
      }
      if (best < 0) break;
      std::vector<Slot> parts = open(e, slots[best]);
      slots.erase(slots.begin() + best);
      for (Slot& p : parts) slots.push_back(std::move(p));
    }
    return slots;
  }

  // Emits what one child slot holds; returns the child field and raises
  // *height to the levels below the slot plus one.
  uint32_t emit_slot(Emission& e, Slot& s, uint32_t* height) const {
    const double area = s.box.half_area();
    uint32_t child;
    if (s.planned) {
      child = emit_node(e, planned_children(e, s.node), area);
    } else if (s.node < 0 && s.chunks.size() == 1) {
      child = emit_leaf(e, s.chunks[0]);
      ++e.leaves;
      e.leaf_sah += area * double(wide_leaf_count(child));
      return child;
    } else if (s.node < 0 && s.chunks.size() > WIDE_WIDTH) {
      // Only depth-limited builds make leaves this big: group the chunks
      // into eight slots and let the recursion split them further.
      std::vector<Slot> groups(WIDE_WIDTH);
      for (size_t k = 0; k < s.chunks.size(); ++k) {
        Slot& g = groups[k * WIDE_WIDTH / s.chunks.size()];
        g.box.grow(s.chunks[k].box);
        g.chunks.push_back(std::move(s.chunks[k]));
      }
      child = emit_node(e, std::move(groups), area);
    } else {
      child = emit_node(e, {std::move(s)}, area);
    }
    *height = std::max(*height, e.nodes[child].height + 1);
    return child;
  }

  static void set_slot(BvhNode8& node, int i, const Box& box, uint32_t child) {
    node.lo_x[i] = box.lo.x;
    node.lo_y[i] = box.lo.y;
    node.lo_z[i] = box.lo.z;
    node.hi_x[i] = box.hi.x;
    node.hi_y[i] = box.hi.y;
    node.hi_z[i] = box.hi.z;
    node.child[i] = child;
  }

  // Builds one wide node from `slots` and, depth first, everything below
  // it; returns its index.
  uint32_t emit_node(Emission& e, std::vector<Slot> slots, double area) const {
    e.node_sah += area;
    const uint32_t index = static_cast<uint32_t>(e.nodes.size());
    check_node_count(size_t{index} + 1);
    e.nodes.push_back(empty_node());
    slots = open_slots(e, std::move(slots));
    BvhNode8 node = empty_node();
    uint32_t height = 1;
    for (size_t i = 0; i < slots.size(); ++i) {
      const Box box = slots[i].box;
      set_slot(node, static_cast<int>(i), box, emit_slot(e, slots[i], &height));
    }
    node.height = height;
    e.nodes[index] = node;
    return index;
  }

  // The top of the tree is drafted on one thread: wide nodes whose slots
  // hold more than `threshold` binary nodes stay in the draft, everything
  // else becomes a part, emitted on whichever thread is free into an
  // Emission of its own. Parts are then joined depth first into out_, with
  // their indices offset: the same layout as emitting everything in turn.
  struct Draft {
    std::vector<Slot> slots;
    double area = 0.0;
    std::vector<std::unique_ptr<Draft>> below;  // per slot: a drafted node, or null for a part
    std::vector<size_t> part;                   // per slot: its part, where below is null
  };

  std::unique_ptr<Draft> draft(Emission& scratch, std::vector<Slot> slots, double area, size_t threshold,
                               std::vector<Slot*>& parts) const {
    auto d = std::make_unique<Draft>();
    d->slots = open_slots(scratch, std::move(slots));
    d->area = area;
    d->below.resize(d->slots.size());
    d->part.assign(d->slots.size(), 0);
    for (size_t i = 0; i < d->slots.size(); ++i) {
      Slot& s = d->slots[i];
      const size_t size = s.node >= 0 ? subtree_end_[s.node] - size_t(s.node) : 0;
      if (size > threshold && s.planned)
        d->below[i] = draft(scratch, planned_children(scratch, s.node), s.box.half_area(), threshold, parts);
      else if (size > threshold)
        d->below[i] = draft(scratch, {s}, s.box.half_area(), threshold, parts);
      else
        d->part[i] = parts.size(), parts.push_back(&s);
    }
    return d;
  }

  void emit_root(Emission& scratch, std::vector<Slot> slots, double area) {
    const bvh_detail::Workers workers(bvh_detail::resolve_threads(options_.threads));
    constexpr size_t kPartsPerThread = 16;
    const size_t threshold = workers.threads() > 1 ? bvh_.nodes.size() / (kPartsPerThread * workers.threads())
                                                   : std::numeric_limits<size_t>::max();
    std::vector<Slot*> todo;
    const std::unique_ptr<Draft> top = draft(scratch, std::move(slots), area, threshold, todo);

    std::vector<Emission> parts(todo.size());
    std::vector<uint32_t> local(todo.size()), heights(todo.size(), 1);
    workers.for_each_dynamic(todo.size(), [&](size_t i) { local[i] = emit_slot(parts[i], *todo[i], &heights[i]); });

    size_t blocks = 0;
    for (const Emission& p : parts) blocks += p.blocks;
    block_refs_.reserve(blocks * kBlockLanes);
    join(*top, parts, local, heights);
    check_node_count(out_.nodes.size());
    check_leaf_index(std::max(block_refs_.size() / kBlockLanes, out_.prim_refs.size()));
  }

  // Appends a drafted node and, depth first, what is below it; returns its index.
  uint32_t join(const Draft& d, std::vector<Emission>& parts, const std::vector<uint32_t>& local,
                const std::vector<uint32_t>& heights) {
    const uint32_t index = static_cast<uint32_t>(out_.nodes.size());
    check_node_count(size_t{index} + 1);
    out_.nodes.push_back(empty_node());
    out_.node_sah += d.area;
    BvhNode8 node = empty_node();
    uint32_t height = 1;
    for (size_t i = 0; i < d.slots.size(); ++i) {
      uint32_t child;
      if (d.below[i]) {
        child = join(*d.below[i], parts, local, heights);
        height = std::max(height, out_.nodes[child].height + 1);
      } else {
        Emission& p = parts[d.part[i]];
        // Indices in the part count from 0; in the tree, from what precedes it.
        const uint32_t node_base = static_cast<uint32_t>(out_.nodes.size());
        const uint32_t block_base = static_cast<uint32_t>(block_refs_.size() / kBlockLanes);
        const uint32_t prim_base = static_cast<uint32_t>(out_.prim_refs.size());
        check_leaf_index(size_t{block_base} + p.blocks);
        check_leaf_index(size_t{prim_base} + p.prim_refs.size());
        auto rebase = [&](uint32_t c) {
          if (c == WIDE_CHILD_EMPTY) return c;
          if (!(c & WIDE_LEAF_FLAG)) return c + node_base;
          return c + ((c & WIDE_LEAF_PRIMS) ? prim_base : block_base);
        };
        for (BvhNode8& n : p.nodes)
          for (uint32_t& c : n.child) c = rebase(c);
        out_.nodes.insert(out_.nodes.end(), p.nodes.begin(), p.nodes.end());
        block_refs_.insert(block_refs_.end(), p.block_refs.begin(), p.block_refs.end());
        out_.prim_refs.insert(out_.prim_refs.end(), p.prim_refs.begin(), p.prim_refs.end());
        out_.triangle_lanes += p.triangle_lanes;
        out_.leaves += p.leaves;
        out_.node_sah += p.node_sah;
        out_.leaf_sah += p.leaf_sah;
        child = rebase(local[d.part[i]]);
        height = std::max(height, heights[d.part[i]]);
        p = Emission();  // its memory goes as soon as it is copied
      }
      set_slot(node, static_cast<int>(i), d.slots[i].box, child);
    }
    node.height = height;
    out_.nodes[index] = node;
    return index;
  }

  const Bvh& bvh_;
  const Scene& scene_;
  WideBvhOptions options_;
  WideBvh& out_;
  bool duplicates_ = false;  // some primitive is referenced twice (spatial splits)
  std::vector<uint32_t> triangles_;
  std::vector<uint32_t> subtree_end_;  // one past the last binary node of each node's subtree
  CollapsePlan plan_;
  std::vector<uint32_t> block_refs_;  // kBlockLanes references per triangle block, in block order
};

}  // namespace

WideBvh collapse_bvh(const Bvh& bvh, const Scene& scene, const WideBvhOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (bvh.nodes.empty()) throw Error("wide BVH: the binary BVH has no root");
  WideBvh out;
  out.nodes.reserve(bvh.nodes.size() / 4 + 1);
  Collapser(bvh, scene, options, out).run();
  out.collapse_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace caustica
