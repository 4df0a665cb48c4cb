// The glTF node graph: checked first (every index, no cycle: an error naming
// the edge that closes it; depth and instance counts bounded, host/limits.h,
// counted on the graph before anything is expanded), then the scene's root
// nodes walked depth-first with an explicit stack (no recursion),
// each node's world transform composed as parent * local, and what a node
// places: mesh primitives as triangles, a camera, a KHR_lights_punctual
// light.
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

#include "host/limits.h"
#include "host/scene/gltf_internal.h"

namespace caustica::gltf_detail {

namespace {

std::string node_pointer(size_t node) { return "/nodes/" + std::to_string(node); }

void require_finite(const Context& ctx, const std::vector<double>& v, size_t size, const std::string& pointer,
                    const char* what) {
  if (v.size() != size)
    ctx.fail(pointer, std::string("expected ") + what + " of " + std::to_string(size) + " numbers, got " +
                          std::to_string(v.size()));
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) ctx.fail(pointer + "/" + std::to_string(i), "expected a finite number");
}

class NodeWalker {
 public:
  NodeWalker(Context& ctx, const glm::dmat4& root) : ctx_(ctx), m_(ctx.model), root_(root) {}

  void walk(const std::vector<int>& roots, const std::string& roots_pointer) {
    check_graph(roots, roots_pointer);
    struct Frame {
      size_t node;
      glm::dmat4 parent;
    };
    std::vector<Frame> stack;
    for (size_t i = roots.size(); i-- > 0;) stack.push_back(Frame{size_t(roots[i]), root_});
    while (!stack.empty()) {
      const Frame f = stack.back();
      stack.pop_back();
      const glm::dmat4 world = f.parent * node_local_transform(ctx_, f.node);
      visit(f.node, world);
      const std::vector<int>& children = m_.nodes[f.node].children;
      for (size_t k = children.size(); k-- > 0;) stack.push_back(Frame{size_t(children[k]), world});
    }
  }

 private:
  // Before anything is expanded: every index valid, no cycle, no chain
  // deeper than the limit, and the instances the walk will place (each node
  // once per path from a root: nodes sharing children multiply) counted on
  // the graph itself, once per node, so a graph of 2^40 instances is
  // refused in microseconds. A depth-first search in the walk's order (so a
  // cycle is named by the same edge), with an explicit stack.
  void check_graph(const std::vector<int>& roots, const std::string& roots_pointer) {
    enum : char { kUnseen, kOnPath, kDone };
    std::vector<char> state(m_.nodes.size(), kUnseen);
    std::vector<uint64_t> instances(m_.nodes.size(), 0);  // saturated at the limit + 1
    std::vector<int> height(m_.nodes.size(), 0);          // levels from the node down to its deepest leaf
    constexpr uint64_t kOver = limits::kMaxGltfNodeInstances + 1;
    struct Frame {
      size_t node;
      size_t next_child;
    };
    std::vector<Frame> path;
    uint64_t total = 0;
    for (size_t i = 0; i < roots.size(); ++i) {
      const std::string rp = roots_pointer + "/" + std::to_string(i);
      const size_t root = checked_index(ctx_, roots[i], m_.nodes.size(), rp, "nodes");
      if (state[root] == kUnseen) {
        state[root] = kOnPath;
        path.push_back(Frame{root, 0});
      }
      while (!path.empty()) {
        Frame& f = path.back();
        const std::vector<int>& children = m_.nodes[f.node].children;
        if (f.next_child < children.size()) {
          const size_t k = f.next_child++;
          const std::string cp = node_pointer(f.node) + "/children/" + std::to_string(k);
          const size_t c = checked_index(ctx_, children[k], m_.nodes.size(), cp, "nodes");
          if (state[c] == kOnPath)
            ctx_.fail(cp, "node " + std::to_string(c) + " is its own ancestor (a cycle in the node graph)");
          // c at depth path.size(): its deepest descendant at depth + height - 1.
          if (state[c] == kUnseen ? path.size() >= size_t(limits::kMaxGltfNodeDepth)
                                  : path.size() + size_t(height[c]) > size_t(limits::kMaxGltfNodeDepth))
            ctx_.fail(node_pointer(c), "nodes nested deeper than " + std::to_string(limits::kMaxGltfNodeDepth) +
                                           " levels (the limit)");
          if (state[c] == kUnseen) {
            state[c] = kOnPath;
            path.push_back(Frame{c, 0});
          }
          continue;
        }
        uint64_t count = 1;
        int below = 0;
        for (int c : children) {
          count = std::min(kOver, count + instances[size_t(c)]);
          below = std::max(below, height[size_t(c)]);
        }
        instances[f.node] = count;
        height[f.node] = below + 1;
        state[f.node] = kDone;
        path.pop_back();
      }
      total = std::min(kOver, total + instances[root]);
      if (total > limits::kMaxGltfNodeInstances)
        ctx_.fail(rp, "the node graph places more than " + std::to_string(limits::kMaxGltfNodeInstances) +
                          " node instances (the limit; nodes sharing children multiply)");
    }
  }

  void visit(size_t n, const glm::dmat4& world) {
    const tinygltf::Node& node = m_.nodes[n];
    const std::string np = node_pointer(n);
    if (node.skin >= 0)
      ctx_.warn_once("skin", np + "/skin", "skinning is not supported; meshes are rendered in their bind pose");
    if (node.mesh >= 0)
      add_mesh_instance(ctx_, checked_index(ctx_, node.mesh, m_.meshes.size(), np + "/mesh", "meshes"), world);
    if (node.camera >= 0) camera(checked_index(ctx_, node.camera, m_.cameras.size(), np + "/camera", "cameras"), world);
    auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext != node.extensions.end()) {
      const tinygltf::Value& v = ext->second;
      const std::string lp = np + "/extensions/KHR_lights_punctual/light";
      if (!v.IsObject() || !v.Has("light") || !v.Get("light").IsNumber())
        ctx_.fail(lp, "expected the index of a light");
      const double index = v.Get("light").GetNumberAsDouble();
      const int i = std::fabs(index) < 1e9 && index == std::floor(index) ? int(index) : -1;
      light(checked_index(ctx_, i, m_.lights.size(), lp, "extensions/KHR_lights_punctual/lights"), world);
    }
  }

  void camera(size_t c, const glm::dmat4& world) {
    const tinygltf::Camera& cam = m_.cameras[c];
    const std::string cp = "/cameras/" + std::to_string(c);
    if (cam.type != "perspective") {
      ctx_.warn_once("camera type", cp + "/type", "camera type \"" + cam.type + "\" is not supported; skipped");
      return;
    }
    const double yfov = cam.perspective.yfov;
    if (!(yfov > 0.0 && yfov < 3.14159))
      ctx_.fail(cp + "/perspective/yfov", "expected a vertical field of view in radians in (0, pi), got " +
                                              std::to_string(yfov));
    GltfCamera out;
    out.index = static_cast<int>(c);
    out.position = glm::vec3(world * glm::dvec4(0, 0, 0, 1));
    const glm::dmat3 linear(world);
    out.forward = glm::vec3(glm::normalize(linear * glm::dvec3(0, 0, -1)));
    out.up = glm::vec3(glm::normalize(linear * glm::dvec3(0, 1, 0)));
    out.yfov_radians = static_cast<float>(yfov);
    const double aspect = cam.perspective.aspectRatio;
    out.aspect = aspect > 0.0 && aspect < 1e4 ? static_cast<float>(aspect) : 0.0f;
    if (!std::isfinite(out.position.x + out.position.y + out.position.z + out.forward.x + out.forward.y +
                       out.forward.z + out.up.x + out.up.y + out.up.z))
      ctx_.fail(cp, "the camera's node transform is singular (no position or direction)");
    ctx_.out.cameras.push_back(out);
  }

  void light(size_t l, const glm::dmat4& world) {
    const tinygltf::Light& in = m_.lights[l];
    GltfLight out;
    out.pointer = "/extensions/KHR_lights_punctual/lights/" + std::to_string(l);
    glm::dvec3 colour(1.0);
    if (!in.color.empty()) {
      require_finite(ctx_, in.color, 3, out.pointer + "/color", "a colour");
      colour = glm::dvec3(in.color[0], in.color[1], in.color[2]);
    }
    if (!(in.intensity >= 0.0 && std::isfinite(in.intensity)) || glm::any(glm::lessThan(colour, glm::dvec3(0.0))))
      ctx_.fail(out.pointer, "expected a non-negative colour and intensity");
    out.intensity = glm::vec3(colour * in.intensity);
    out.position = glm::vec3(world * glm::dvec4(0, 0, 0, 1));
    out.direction = glm::vec3(glm::normalize(glm::dmat3(world) * glm::dvec3(0, 0, -1)));
    if (in.type == "point") {
      out.type = GltfLight::Type::Point;
    } else if (in.type == "spot") {
      out.type = GltfLight::Type::Spot;
      out.inner_cone = static_cast<float>(in.spot.innerConeAngle);
      out.outer_cone = static_cast<float>(in.spot.outerConeAngle);
    } else if (in.type == "directional") {
      out.type = GltfLight::Type::Directional;
    } else {
      ctx_.fail(out.pointer + "/type", "expected \"point\", \"spot\" or \"directional\", got \"" + in.type + "\"");
    }
    if (in.range > 0.0)
      ctx_.warn_once("light range", out.pointer + "/range", "light \"range\" is not supported; the light reaches "
                                                            "everywhere with inverse-square falloff");
    if (!std::isfinite(out.position.x + out.position.y + out.position.z + out.direction.x + out.direction.y +
                       out.direction.z))
      ctx_.fail(out.pointer, "the light's node transform is singular");
    ctx_.out.lights.push_back(out);
  }

  Context& ctx_;
  const tinygltf::Model& m_;
  const glm::dmat4 root_;
};

}  // namespace

glm::dmat4 node_local_transform(const Context& ctx, size_t n) {
  const tinygltf::Node& node = ctx.model.nodes[n];
  const std::string np = node_pointer(n);
  if (!node.matrix.empty()) {
    require_finite(ctx, node.matrix, 16, np + "/matrix", "a column-major 4x4 matrix");
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[size_t(c * 4 + r)];
    return m;
  }
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (!node.translation.empty()) {
    require_finite(ctx, node.translation, 3, np + "/translation", "a translation");
    t[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
  }
  if (!node.rotation.empty()) {
    require_finite(ctx, node.rotation, 4, np + "/rotation", "a unit quaternion (x, y, z, w)");
    glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glm: w first
    const double len = glm::length(q);
    if (!(len > 1e-6)) ctx.fail(np + "/rotation", "expected a unit quaternion, got one of length 0");
    r = glm::mat4_cast(q / len);
  }
  if (!node.scale.empty()) {
    require_finite(ctx, node.scale, 3, np + "/scale", "a scale");
    s = glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  }
  return t * r * s;
}

void convert_nodes(Context& ctx, const glm::dmat4& root) {
  const tinygltf::Model& m = ctx.model;
  NodeWalker walker(ctx, root);
  if (!m.animations.empty())
    ctx.warn("/animations", "animations are not supported; rendering the nodes' own (rest) transforms");
  if (m.scenes.empty()) {
    // No scene: every node that is no node's child is a root.
    std::vector<char> child(m.nodes.size(), 0);
    for (const tinygltf::Node& node : m.nodes)
      for (int c : node.children)
        if (c >= 0 && static_cast<size_t>(c) < child.size()) child[size_t(c)] = 1;
    std::vector<int> roots;
    for (size_t i = 0; i < m.nodes.size(); ++i)
      if (!child[i]) roots.push_back(static_cast<int>(i));
    if (!m.nodes.empty())
      ctx.warn("/scenes", "the file has no scene; rendering its " + std::to_string(roots.size()) + " root nodes");
    walker.walk(roots, "/nodes");
    return;
  }
  const size_t s = m.defaultScene < 0 ? 0 : checked_index(ctx, m.defaultScene, m.scenes.size(), "/scene", "scenes");
  if (m.scenes.size() > 1)
    ctx.warn("/scenes", "the file has " + std::to_string(m.scenes.size()) + " scenes; rendering scene " +
                            std::to_string(s) + " only");
  walker.walk(m.scenes[s].nodes, "/scenes/" + std::to_string(s) + "/nodes");
}

}  // namespace caustica::gltf_detail
