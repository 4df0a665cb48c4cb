// The glTF node graph: the scene's root nodes walked depth-first with an
// explicit stack (no recursion; a cycle is an error naming the edge that
// closes it, and depth and instance counts are bounded, host/limits.h),
// each node's world transform composed as parent * local, and what a node
// places: mesh primitives as triangles, a camera, a KHR_lights_punctual
// light.
#include <glm/gtc/quaternion.hpp>

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
    std::vector<char> on_path(m_.nodes.size(), 0);
    struct Frame {
      size_t node;
      glm::dmat4 parent;
      int depth;
      bool leave;
    };
    std::vector<Frame> stack;
    for (size_t i = roots.size(); i-- > 0;) {
      const size_t n =
          checked_index(ctx_, roots[i], m_.nodes.size(), roots_pointer + "/" + std::to_string(i), "nodes");
      stack.push_back(Frame{n, root_, 0, false});
    }
    uint64_t instances = 0;
    while (!stack.empty()) {
      const Frame f = stack.back();
      stack.pop_back();
      if (f.leave) {
        on_path[f.node] = 0;
        continue;
      }
      if (++instances > limits::kMaxGltfNodeInstances)
        ctx_.fail(node_pointer(f.node), "the node graph places more than " +
                                            std::to_string(limits::kMaxGltfNodeInstances) +
                                            " node instances (the limit; nodes sharing children multiply)");
      if (f.depth >= limits::kMaxGltfNodeDepth)
        ctx_.fail(node_pointer(f.node), "nodes nested deeper than " + std::to_string(limits::kMaxGltfNodeDepth) +
                                            " levels (the limit)");
      const glm::dmat4 world = f.parent * node_local_transform(ctx_, f.node);
      visit(f.node, world);
      on_path[f.node] = 1;
      stack.push_back(Frame{f.node, world, f.depth, true});
      const std::vector<int>& children = m_.nodes[f.node].children;
      for (size_t k = children.size(); k-- > 0;) {
        const std::string cp = node_pointer(f.node) + "/children/" + std::to_string(k);
        const size_t c = checked_index(ctx_, children[k], m_.nodes.size(), cp, "nodes");
        if (on_path[c])
          ctx_.fail(cp, "node " + std::to_string(c) + " is its own ancestor (a cycle in the node graph)");
        stack.push_back(Frame{c, world, f.depth + 1, false});
      }
    }
  }

 private:
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
