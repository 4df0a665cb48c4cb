// Rectangle light, "type": "arealight" (kernels/lib/lights/rect_light.h):
// centre ("position"), edge vectors u and v (or directions and a size, as
// the community's variants write it: scenes/FORMAT.md) and radiance
// ("intensity") on the side of cross(u, v).
#include <cmath>

#include "host/lights/light_types.h"
#include "host/scene/scene_reader.h"

namespace caustica {
namespace {

using namespace scene_detail;

// Side of the square used for an area light that gives no size at all.
constexpr float kDefaultAreaLightSize = 0.1f;

void read_rect_light(const Reader& r, const json& l, const std::string& path, Scene& scene) {
  r.check_keys(l, path, {"type", "position", "intensity", "u", "v", "u_axis", "v_axis", "width", "height", "size",
                         "samples"});
  const glm::vec3 centre = r.read_vec3(l, "position", path, Range::Coordinate);
  const glm::vec3 intensity = r.read_vec3(l, "intensity", path, Range::NonNegative);
  r.read_int(l, "samples", path, 1, 1 << 20, 0);  // checked; path mode's samples per pixel decide instead
  const char* u_key = nullptr;
  const char* v_key = nullptr;
  const json* u = Reader::find_any(l, {"u", "u_axis"}, &u_key);
  const json* v = Reader::find_any(l, {"v", "v_axis"}, &v_key);
  const json* size = Reader::find(l, "size");
  const bool wh = Reader::find(l, "width") || Reader::find(l, "height");
  if (size && wh) r.fail(path + "/size", "give the size either as \"size\" or as \"width\"/\"height\", not both");
  glm::vec3 du = u ? r.vec3(*u, path + "/" + u_key, Range::Coordinate) : glm::vec3(1, 0, 0);
  glm::vec3 dv = v ? r.vec3(*v, path + "/" + v_key, Range::Coordinate) : glm::vec3(0, 0, 1);
  glm::vec3 unit_u = du, unit_v = dv;
  if (u && !unit_direction(du, &unit_u)) r.expected(path + "/" + u_key, "a direction of nonzero length", *u);
  if (v && !unit_direction(dv, &unit_v)) r.expected(path + "/" + v_key, "a direction of nonzero length", *v);
  glm::vec3 edge_u, edge_v;
  if (size || wh) {
    // u and v give directions only; the extent comes from the size.
    glm::vec2 extent;
    if (size) {
      extent = r.vec2(*size, path + "/size", Range::Size);
    } else {
      extent.x = r.read_number(l, "width", path, Range::Size);
      extent.y = r.read_number(l, "height", path, Range::Size);
    }
    du = unit_u;
    dv = unit_v;
    if (!v && std::fabs(glm::dot(du, dv)) > 0.999f) dv = glm::vec3(0, 1, 0);  // default v along u
    if (!u && std::fabs(glm::dot(du, dv)) > 0.999f) du = glm::vec3(0, 1, 0);
    edge_u = du * extent.x;
    edge_v = dv * extent.y;
  } else if (u && v) {
    edge_u = du;  // full edge vectors, as the authors' samplers use them
    edge_v = dv;
  } else if (u || v) {
    r.fail(path + "/" + (u ? u_key : v_key), std::string("expected both edge vectors (\"u\" and \"v\") or a "
                                                         "\"size\"/\"width\"/\"height\", got only \"") +
                                                 (u ? u_key : v_key) + "\"");
  } else {
    edge_u = glm::vec3(kDefaultAreaLightSize, 0, 0);
    edge_v = glm::vec3(0, 0, kDefaultAreaLightSize);
    r.warn(path, "area light without a size (u/v, width/height or size): using a horizontal 0.1 x 0.1 square");
  }
  const float area = glm::length(glm::cross(edge_u, edge_v));
  if (!(area > 0.0f)) r.fail(path, "expected edge vectors u and v that span a rectangle, got parallel ones");
  Light a{};
  a.kind = LIGHT_RECT;
  a.p0 = to_float4(centre);
  a.p1 = to_float4(edge_u);
  a.p2 = to_float4(edge_v);
  a.emitted = to_float4(intensity, area);
  scene.lights.push_back(a);
}

// Phong: a point light at the centre with the light's intensity.
Light rect_stand_in(const Light& l) { return delta_light_at(to_vec3(l.p0), to_vec3(l.emitted)); }

void add_triangle(Scene& scene, uint32_t light_index, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material) {
  Triangle t{};
  t.v0 = to_float4(a);
  t.v1 = to_float4(b);
  t.v2 = to_float4(c);
  t.material = material;
  scene.light_geometry.prims.push_back(
      {light_index, (PRIM_TRIANGLE << PRIM_TYPE_SHIFT) | uint32_t(scene.triangles.size())});
  scene.triangles.push_back(t);
  if (!scene.triangle_shading.empty()) {  // a parallel array when present
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    TriangleShading s{};
    s.n0 = s.n1 = s.n2 = to_float4(n);
    s.u1 = 1.0f;
    s.v2 = 1.0f;
    scene.triangle_shading.push_back(s);
  }
  // The other parallel arrays: no tangents (no normal map), white.
  if (!scene.triangle_tangents.empty()) scene.triangle_tangents.push_back(TriangleTangents{});
  if (!scene.triangle_colours.empty()) scene.triangle_colours.push_back(vertex_colours(nullptr));
}

// Two triangles, counter-clockwise about cross(u, v): the emitting side.
void add_rect_geometry(Scene& scene, uint32_t light_index) {
  const Light l = scene.lights[light_index];
  const glm::vec3 centre = to_vec3(l.p0), u = to_vec3(l.p1), v = to_vec3(l.p2);
  const uint32_t m = add_emissive_material(scene, to_vec3(l.emitted));
  const glm::vec3 a = centre - 0.5f * u - 0.5f * v, b = centre + 0.5f * u - 0.5f * v, c = centre + 0.5f * u + 0.5f * v,
                  d = centre - 0.5f * u + 0.5f * v;
  add_triangle(scene, light_index, a, b, c, m);
  add_triangle(scene, light_index, a, c, d, m);
}

// The tree: its four corners, emitting on the side of cross(u, v).
LightBounds rect_tree_bounds(const Light& l) {
  const glm::vec3 c = to_vec3(l.p0), u = to_vec3(l.p1), v = to_vec3(l.p2);
  const glm::vec3 corners[4] = {c - 0.5f * u - 0.5f * v, c + 0.5f * u - 0.5f * v, c + 0.5f * u + 0.5f * v,
                                c - 0.5f * u + 0.5f * v};
  return planar_bounds(corners, 4, glm::cross(u, v), (l.flags & LIGHT_TWO_SIDED) != 0u);
}

}  // namespace

LightType rect_light_type() {
  LightType t;
  t.kind = LIGHT_RECT;
  t.file_type = "arealight";
  t.read = read_rect_light;
  t.power = area_light_power;
  t.whitted_stand_in = rect_stand_in;
  t.add_geometry = add_rect_geometry;
  t.tree_bounds = rect_tree_bounds;
  return t;
}

}  // namespace caustica
